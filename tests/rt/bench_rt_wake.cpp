// bench_rt_wake — the loop's wake-up latency with everything kerf-rt does each tick (the Kerf HID
// device code talking to kerf-hapsim --realtime, collision and force on a real CT bone, publishing
// state, telemetry and events) against an empty SCHED_FIFO loop (clock_nanosleep to absolute
// deadlines, nothing else) measured in the same run, on the same pinned CPU, alternating, N
// repetitions. Prints p50/p99/p99.9 per repetition and the median (min-max) of the p99 ratio.
// Whatever runs on the other core meanwhile is the caller's business (see rt_core/README.md).
//
//   bench_rt_wake [--reps 5] [--ticks 5000] [--cpu 1] [--hapsim-cpu 0]
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "config/base/main_guard.hpp"
#include "rt_core/loop/latency_histogram.hpp"
#include "rt_core/loop/loop_runner.hpp"
#include "tests/rt/rt_rig.hpp"

namespace {

using kerf::rt::LatencyHistogram;

bool pin_fifo(int cpu) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    sched_param p{};
    p.sched_priority = 80;
    return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0 &&
           pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0;
}

LatencyHistogram empty_loop(std::uint64_t ticks) {
    LatencyHistogram h;
    std::uint64_t deadline = kerf::rt::monotonic_ns() + 1'000'000;
    for (std::uint64_t i = 0; i < ticks; ++i) {
        const timespec ts{time_t(deadline / 1'000'000'000), long(deadline % 1'000'000'000)};
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
        }
        const std::uint64_t now = kerf::rt::monotonic_ns();
        h.record(now > deadline ? now - deadline : 0);
        deadline += 1'000'000;
        while (deadline < now) deadline += 1'000'000;
    }
    return h;
}

LatencyHistogram full_loop(std::uint64_t ticks, int hapsim_cpu) {
    const std::string script = "hold,0.05\nmove,0.0,-0.02,0.0,2.0\nsweep,0.004,0.0,0.004,1.5,60\n";
    std::vector<std::string> args = {"--realtime"};
    kerf::rt::test::Rig rig({script, args, 0, true, false});
    if (!rig.ok()) {
        std::fprintf(stderr, "bench_rt_wake: %s\n", rig.error().c_str());
        std::exit(1);
    }
    std::string pin = "taskset -pc " + std::to_string(hapsim_cpu) + " $(pgrep -n kerf-hapsim) " +
                      ">/dev/null 2>&1";
    if (std::system(pin.c_str()) != 0) std::fprintf(stderr, "bench_rt_wake: could not pin\n");
    kerf::rt::RunOptions o;
    o.max_ticks = ticks;
    kerf::rt::run_loop(rig.loop(), o);
    return rig.loop().stats().wake_latency;
}

double us(std::uint64_t ns) { return double(ns) / 1000.0; }

}  // namespace

static int program_main(int argc, char** argv) {
    int reps = 5, cpu = 1, hapsim_cpu = 0;
    std::uint64_t ticks = 5000;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        const long v = std::strtol(argv[i + 1], nullptr, 10);
        if (k == "--reps") reps = int(v);
        if (k == "--ticks") ticks = std::uint64_t(v);
        if (k == "--cpu") cpu = int(v);
        if (k == "--hapsim-cpu") hapsim_cpu = int(v);
    }
    if (!kerf::rt::test::have_shared_meshes()) {
        std::printf("bench_rt_wake: skipped, no %s\n", kerf::rt::test::calcaneus_path().c_str());
        return 0;
    }
    mlockall(MCL_CURRENT | MCL_FUTURE);
    if (!pin_fifo(cpu))
        std::printf("bench_rt_wake: SCHED_FIFO/affinity DENIED (figures degraded)\n");
    std::printf(
        "rep  empty p50/p99/p99.9 us      full p50/p99/p99.9 us       p99 ratio  "
        "(CPU %d, %llu ticks each, 1 kHz)\n",
        cpu, static_cast<unsigned long long>(ticks));
    std::vector<double> ratios;
    for (int r = 0; r < reps; ++r) {
        const LatencyHistogram e = empty_loop(ticks);
        const LatencyHistogram f = full_loop(ticks, hapsim_cpu);
        const double ratio =
            double(f.percentile(0.99)) / double(std::max<std::uint64_t>(1, e.percentile(0.99)));
        ratios.push_back(ratio);
        std::printf("%3d  %6.1f %7.1f %8.1f      %6.1f %7.1f %8.1f      %6.2f\n", r + 1,
                    us(e.percentile(0.5)), us(e.percentile(0.99)), us(e.percentile(0.999)),
                    us(f.percentile(0.5)), us(f.percentile(0.99)), us(f.percentile(0.999)), ratio);
    }
    std::sort(ratios.begin(), ratios.end());
    std::printf("p99 ratio full/empty: median %.2f (min %.2f, max %.2f) over %d repetitions\n",
                ratios[ratios.size() / 2], ratios.front(), ratios.back(), reps);
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_rt_wake", [&] { return program_main(argc, argv); });
}
