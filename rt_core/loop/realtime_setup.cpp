#include "rt_core/loop/realtime_setup.hpp"

#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace kerf::rt {
namespace {

std::string denied(int err, const char* hint) {
    return std::string(std::strerror(err)) + " (" + hint + ")";
}

RealtimeItem request_policy(const config::RealtimeSettings& s) {
    RealtimeItem item;
    int policy = SCHED_OTHER;
    if (s.policy == config::SchedPolicy::kFifo) policy = SCHED_FIFO;
    if (s.policy == config::SchedPolicy::kRoundRobin) policy = SCHED_RR;
    item.what = policy == SCHED_FIFO ? "SCHED_FIFO"
                : policy == SCHED_RR ? "SCHED_RR"
                                     : "SCHED_OTHER";
    item.what += " priority " + std::to_string(s.priority);
    sched_param param{};
    param.sched_priority = policy == SCHED_OTHER ? 0 : s.priority;
    const int err = pthread_setschedparam(pthread_self(), policy, &param);
    item.ok = err == 0;
    item.result =
        item.ok ? "ok" : denied(err, "needs CAP_SYS_NICE or an RLIMIT_RTPRIO >= the priority");
    return item;
}

RealtimeItem request_mlockall() {
    RealtimeItem item{"mlockall(MCL_CURRENT | MCL_FUTURE)", false, {}};
    item.ok = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
    item.result = item.ok ? "ok" : denied(errno, "needs CAP_IPC_LOCK or a large RLIMIT_MEMLOCK");
    return item;
}

RealtimeItem request_affinity(const std::vector<std::uint32_t>& cpus) {
    RealtimeItem item;
    item.what = "CPU affinity {";
    cpu_set_t set;
    CPU_ZERO(&set);
    for (std::size_t i = 0; i < cpus.size(); ++i) {
        item.what += (i ? "," : "") + std::to_string(cpus[i]);
        if (cpus[i] < CPU_SETSIZE) CPU_SET(cpus[i], &set);
    }
    item.what += "}";
    const int err = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    item.ok = err == 0;
    item.result = item.ok ? "ok" : denied(err, "CPU offline, outside the cpuset, or not permitted");
    return item;
}

}  // namespace

bool RealtimeReport::degraded() const noexcept {
    for (const RealtimeItem& i : items) {
        if (!i.ok) return true;
    }
    return false;
}

std::string RealtimeReport::format() const {
    std::string out;
    for (const RealtimeItem& i : items) out += "  " + i.what + ": " + i.result + "\n";
    out += degraded() ? "  real time: DEGRADED (the loop runs, with worse timing)\n"
                      : "  real time: as requested\n";
    return out;
}

RealtimeReport apply_realtime(const config::RealtimeSettings& settings) {
    RealtimeReport report;
    if (!settings.cpu_affinity.empty())
        report.items.push_back(request_affinity(settings.cpu_affinity));
    report.items.push_back(request_policy(settings));
    if (settings.mlockall) report.items.push_back(request_mlockall());
    return report;
}

RealtimeItem keep_freed_memory() {
    RealtimeItem item;
    item.what = "heap keeps freed memory (one arena, mmap threshold 32 MiB, no trim)";
    // 32 MiB is glibc's largest mmap threshold on 64-bit; blocks below it come from the heap.
    // One arena: otherwise each thread's first allocation creates an arena of its own (64 MiB
    // reserved, grown by mprotect and, under mlockall, faulted in as it grows), so the world
    // builder thread would rebuild in a fresh arena that the warm-up on the main thread never
    // touched, and grow it round after round as bigger cut meshes arrive. The real-time thread
    // does not allocate, so the single arena's lock never stands in its way.
    item.ok = mallopt(M_ARENA_MAX, 1) == 1 && mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1 &&
              mallopt(M_TRIM_THRESHOLD, -1) == 1;
    item.result = item.ok ? "ok" : "mallopt refused";
    return item;
}

}  // namespace kerf::rt
