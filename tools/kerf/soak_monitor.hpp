// `kerf soak`'s view of a running session: a thread attached to the segment as the soak monitor
// (the consumer slot reserved for it, ipc::ConsumerRole::kMonitor) that keeps every event it is
// delivered (ring, and journal for what the ring lost) and a compact copy of every telemetry
// sample kerf-rt publishes, for the checks after the round; plus resident-memory samples of a
// process from /proc/<pid>/status. Not real-time code: it polls every 2 ms and sleeps between.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "config/base/result.hpp"
#include "rt_core/ipc/consumer.hpp"

namespace kerf::cli {

/// One telemetry sample, kept small (a 2-hour soak holds 7.2 million of them).
struct TickSample {
    std::uint64_t time_ns = 0;  ///< CLOCK_MONOTONIC of the tick
    std::uint64_t tick = 0;     ///< kerf-rt's tick number
    float force_n = 0;          ///< |commanded force|, N
    float penetration_m = 0;    ///< tool depth into the surface, m
    std::uint32_t safety_reasons = 0;
    std::uint32_t loop_flags = 0;
    std::uint32_t contact_flags = 0;
    std::uint32_t period_ns = 0;
};

/// One event as delivered: enough to compare with the journal record by record.
struct SeenEvent {
    std::uint64_t sequence = 0;
    std::uint32_t checksum = 0;
    std::uint16_t type = 0;
};

/// What the monitor collected (copied out after stop()).
struct MonitorData {
    std::vector<TickSample> ticks;
    std::vector<SeenEvent> events;
    ipc::ConsumerStats stats;
};

class SessionMonitor {
public:
    /// Attaches to `session` as the monitor (telemetry on, events from sequence 0) and starts the
    /// thread; fails with the attach error.
    static Result<std::unique_ptr<SessionMonitor>, std::string> start(const std::string& session);
    ~SessionMonitor();  ///< stop()

    /// The newest sample's contact flags (bit 1: a cut is locked) and its time. Any thread.
    std::uint32_t contact_flags() const noexcept { return contact_.load(); }
    /// The newest sample's |commanded force|, N. Any thread.
    float force_n() const noexcept { return force_.load(); }
    /// The producer's next event sequence (events published so far). Any thread.
    std::uint64_t published_events() const noexcept;
    /// Stops the thread, releases the slot and hands over what was collected. Idempotent.
    MonitorData stop();

private:
    explicit SessionMonitor(ipc::Consumer consumer);
    void run();

    ipc::Consumer consumer_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint32_t> contact_{0};
    std::atomic<float> force_{0};
    std::mutex mutex_;
    MonitorData data_;
    std::thread thread_;
    bool stopped_ = false;
};

/// Resident memory of a process now, from /proc/<pid>/status (kB).
struct MemorySample {
    std::uint64_t rss_kb = 0, anon_kb = 0, file_kb = 0, shmem_kb = 0;
    bool ok = false;  ///< false when the process is gone or the file unreadable
};
MemorySample read_memory(pid_t pid);

}  // namespace kerf::cli
