#include "rt_core/loop/loop_runner.hpp"

#include <time.h>

#include <cerrno>

namespace kerf::rt {
namespace {

constexpr std::uint64_t kNsPerS = 1'000'000'000ull;

timespec to_timespec(std::uint64_t ns) noexcept {
    return timespec{time_t(ns / kNsPerS), long(ns % kNsPerS)};
}

void sleep_until(std::uint64_t deadline_ns) noexcept {
    const timespec ts = to_timespec(deadline_ns);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

bool keep_going(const RunOptions& o, std::uint64_t ticks) noexcept {
    if (o.stop && o.stop->load(std::memory_order_acquire)) return false;
    return o.max_ticks == 0 || ticks < o.max_ticks;
}

void record_trace(const HapticLoop& loop, TraceRow& row) noexcept {
    const physics::Vec3& p = loop.tool_position_m();
    row.tool_position_m[0] = p.x, row.tool_position_m[1] = p.y, row.tool_position_m[2] = p.z;
    for (int i = 0; i < 3; ++i) row.force_n[i] = loop.last_force_n()[i];
}

std::uint64_t ticks_run(const RunOptions& o, const HapticLoop& loop) noexcept {
    const std::uint64_t n = loop.stats().ticks;
    return n < o.trace.size() ? n : o.trace.size();
}

}  // namespace

std::uint64_t monotonic_ns() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::uint64_t(ts.tv_sec) * kNsPerS + std::uint64_t(ts.tv_nsec);
}

void run_loop(HapticLoop& loop, const RunOptions& o) noexcept {
    const auto period = std::uint64_t(o.period_ns);
    loop.prime();
    std::uint64_t deadline = monotonic_ns() + period;
    for (std::uint64_t ticks = 0; keep_going(o, ticks); ++ticks) {
        TickTiming timing;
        if (!o.lockstep) {
            sleep_until(deadline);
            timing.start_ns = monotonic_ns();
            timing.wake_latency_ns = timing.start_ns > deadline ? timing.start_ns - deadline : 0;
            // A stall longer than a period: the deadlines it covered are gone, not made up.
            timing.missed_deadlines = timing.wake_latency_ns / period;
            deadline += (timing.missed_deadlines + 1) * period;
        } else {
            // Lockstep is paced by the emulator; without a device (lost, being re-opened) the
            // clock paces it so the run neither spins nor burns its ticks in a moment.
            if (loop.waiting_for_device()) sleep_until(monotonic_ns() + period);
            timing.start_ns = monotonic_ns();
        }
        loop.tick(timing);
        loop.record_compute(monotonic_ns() - timing.start_ns);
        if (ticks < o.trace.size()) record_trace(loop, o.trace[ticks]);
    }
    if (o.trace_rows) *o.trace_rows = ticks_run(o, loop);
    loop.command_zero();
}

}  // namespace kerf::rt
