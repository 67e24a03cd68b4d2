// kerf::rt::run_loop — paces a HapticLoop. Real time: sleeps to absolute deadlines
// (clock_nanosleep TIMER_ABSTIME on CLOCK_MONOTONIC), measures how late each wake-up was, skips
// (and counts) deadlines a stall made impossible, and times each tick's work. Lockstep: no sleep;
// the device read waits for the emulator's answer, so the emulator sets the pace and a run is
// deterministic. Runs on the calling thread (set up with apply_realtime() first).
#pragma once

#include <atomic>
#include <cstdint>
#include <span>

#include "rt_core/loop/haptic_loop.hpp"

namespace kerf::rt {

/// One tick of a force trace (tests, tuning): what the loop saw and commanded.
struct TraceRow {
    double tool_position_m[3];  ///< world frame, m
    double force_n[3];          ///< commanded, device frame, N
};

struct RunOptions {
    std::int64_t period_ns = 1'000'000;
    bool lockstep = false;
    std::uint64_t max_ticks = 0;              ///< 0: until `stop`
    const std::atomic<bool>* stop = nullptr;  ///< set by another thread or a signal handler
    std::span<TraceRow> trace;                ///< filled tick by tick while it has room
    std::uint64_t* trace_rows = nullptr;      ///< receives the number of rows written
};

/// CLOCK_MONOTONIC now, ns. noexcept.
std::uint64_t monotonic_ns() noexcept;

/// Runs ticks until `stop` or `max_ticks`; then commands zero force. noexcept, allocation-free.
void run_loop(HapticLoop& loop, const RunOptions& options) noexcept;

}  // namespace kerf::rt
