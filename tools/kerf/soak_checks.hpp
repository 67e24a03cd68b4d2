// `kerf soak`'s checks, as pure functions over what a round collected (kerf-rt's telemetry, the
// events the monitor was delivered, the journal, memory samples), so each can be tested alone:
//   - every device fault: kerf-rt saw it, commanded zero force within 2 ticks of the first tick
//     that saw it and held zero while it saw it, and recovered after the fault was cleared;
//   - the commanded force never above the limit (the force profile's and the device's);
//   - the events a consumer was delivered equal the journal, record by record;
//   - resident memory flat after warm-up.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tools/kerf/soak_monitor.hpp"
#include "tools/kerf/soak_plan.hpp"

namespace kerf::cli {

/// A device fault as injected: on at `on_ns`, cleared at `off_ns` (CLOCK_MONOTONIC).
struct FaultWindow {
    SoakFault fault = SoakFault::kDrop;
    std::uint64_t on_ns = 0, off_ns = 0;
};

/// What the telemetry says about one injected device fault.
struct FaultVerdict {
    FaultWindow window;
    bool covered = false;  ///< telemetry was received around the fault (else unverified)
    bool seen = false;     ///< kerf-rt flagged bad input or a device fault
    bool pushing = false;  ///< force was commanded just before (the tool was in bone)
    std::uint64_t first_bad_tick = 0;
    std::int64_t ticks_to_zero = -1;      ///< first zero-force tick minus first bad tick
    std::uint64_t nonzero_while_bad = 0;  ///< ticks >= 2 after the first bad one with force
    bool recovered = false;               ///< input clean and device ready again after off_ns
    double recovery_s = -1;               ///< off_ns to the first clean tick, s
    std::string problem;                  ///< empty when every rule held (or unverified)
    bool ok() const { return problem.empty(); }
};

/// SafetyReason bits that mean the device's input cannot be trusted (firmware_host/safety).
std::uint32_t bad_input_reasons() noexcept;

/// Whether a tick's commanded force could reach the hand: no zero-force safety reason (the
/// bad-input ones, not homed, waiting to engage), no timing safe state, no device fault and no
/// failed loop check. A tick where it could not is one where the tool may sink into bone with
/// no force at all, by design (e-stop, unplug, stale samples, a safe state, before engaging).
bool force_reaches_hand(const TickSample& s) noexcept;

/// Checks each window against `ticks` (sorted by time). A fault whose recovery is not seen
/// within `recovery_limit_s` of its clearing fails.
std::vector<FaultVerdict> check_device_faults(const std::vector<TickSample>& ticks,
                                              const std::vector<FaultWindow>& windows,
                                              double recovery_limit_s = 10.0);

/// The commanded force against its limit.
struct ForceVerdict {
    double peak_n = 0;
    double limit_n = 0;
    std::uint64_t over = 0;  ///< samples above the limit (beyond float rounding)
    bool ok() const { return over == 0; }
};
ForceVerdict check_force_limit(const std::vector<TickSample>& ticks, double limit_n);

/// A delivered event sequence against the journal's.
struct SequenceVerdict {
    std::uint64_t journal = 0, delivered = 0;
    std::int64_t first_difference = -1;  ///< index of the first mismatch, -1 when equal
    bool ok() const { return first_difference < 0 && journal == delivered; }
};
SequenceVerdict compare_sequences(const std::vector<SeenEvent>& journal,
                                  const std::vector<SeenEvent>& delivered);

/// Resident memory over a process's life: after warm-up against the end.
struct MemoryVerdict {
    std::uint64_t warm_kb = 0;  ///< median of the samples in the 5 s after warm-up
    std::uint64_t end_kb = 0;   ///< median of the last 5 samples
    std::uint64_t peak_kb = 0;
    double growth_pct = 0;
    bool measured = false;  ///< enough samples after warm-up
};
/// `t_s` and `kb` are parallel (seconds since the process started, resident kB).
MemoryVerdict memory_growth(const std::vector<double>& t_s, const std::vector<std::uint64_t>& kb,
                            double warmup_s);

}  // namespace kerf::cli
