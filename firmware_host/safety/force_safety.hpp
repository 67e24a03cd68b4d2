// ForceSafety — the host-side last line before the wire, whatever the force model or the device
// does: zero force on stale, invalid or non-finite input, e-stop, device fault, disconnect or
// not homed; ramp-in on engage; a direction-preserving clamp at the peak force; a continuous
// (thermal) limit; a slew-rate limit. One `step()` per tick: noexcept, no allocation, O(1).
//
// Engaging. The first time, and after a hard fault (e-stop, device fault, disconnect, not homed,
// a non-finite demand), forces engage only once the demand has been quiet (the user let go).
// After a transient interruption — samples that were late (stale) or unreadable, or the loop's
// timing safe state (interrupt()) — forces resume, ramping in, after `resume_fresh_ticks` fresh
// samples in a row whatever the demand: a surgeon who keeps moving through one late sample keeps
// feeling the bone, and a tool pushed into bone while forces were off is pushed out gently.
//
//   SafetyInput in{desired_force, status == kOk, sample.flags, connected};
//   DeviceCommand cmd{safety.step(in), safety.engaged()};
#pragma once

#include <cstdint>
#include <string_view>

#include "firmware_host/device/device.hpp"

namespace kerf::firmware_host {

/// Limits, SI units. Filled from the device profile and force profile by the caller.
struct SafetyLimits {
    double period_s = 0.001;                ///< tick period
    double peak_force_n = 8.0;              ///< |F| never exceeds this
    double continuous_force_n = 4.0;        ///< |F| allowed while the thermal budget is spent
    double thermal_time_constant_s = 2.0;   ///< low-pass of |F|^2 (I^2 t model of motor heating)
    double max_slew_n_per_s = 2000.0;       ///< |F(k) - F(k-1)| <= this * period (except to zero)
    double ramp_in_s = 0.5;                 ///< 0 -> full scale after engaging
    double engage_threshold_n = 0.5;        ///< engage only once |desired| stays below this ...
    std::uint32_t engage_quiet_ticks = 20;  ///< ... for this many consecutive ticks
    std::uint32_t stale_ticks = 2;          ///< ticks without a fresh sample before zero force
    /// Fresh samples in a row after a transient interruption before force resumes (with ramp).
    std::uint32_t resume_fresh_ticks = 10;
};

/// Why the last step changed or zeroed the force (bit set).
enum SafetyReason : std::uint32_t {
    kReasonNone = 0,
    kReasonStale = 1U << 0,
    kReasonInvalidInput = 1U << 1,
    kReasonNonFinite = 1U << 2,
    kReasonEStop = 1U << 3,
    kReasonDeviceFault = 1U << 4,
    kReasonDisconnected = 1U << 5,
    kReasonNotHomed = 1U << 6,
    kReasonWaitingToEngage = 1U << 7,
    kReasonRamping = 1U << 8,
    kReasonPeakClamp = 1U << 9,
    kReasonThermal = 1U << 10,
    kReasonSlew = 1U << 11,
};
std::string_view to_string(SafetyReason reason) noexcept;  ///< name of one bit

/// What the loop knows this tick.
struct SafetyInput {
    Vec3 desired_force_n{};
    DeviceStatus read_status = DeviceStatus::kNoData;  ///< this tick's Device::try_read result
    DeviceFlags flags;                                 ///< from the newest sample
};

class ForceSafety {
public:
    explicit ForceSafety(const SafetyLimits& limits) noexcept : limits_(limits) {}

    /// The force to command this tick. noexcept, no allocation, constant time.
    Vec3 step(const SafetyInput& in) noexcept;

    bool engaged() const noexcept { return engaged_; }
    /// The loop zeroed force for a transient reason of its own (its timing safe state): from the
    /// next step the output restarts from zero and resumes like after a stale sample. noexcept.
    void interrupt() noexcept;
    std::uint32_t reasons() const noexcept {
        return reasons_;
    }  ///< SafetyReason bits of the last step
    double thermal_state_n2() const noexcept { return thermal_n2_; }  ///< low-passed |F|^2
    const SafetyLimits& limits() const noexcept { return limits_; }
    /// Swaps limits at a tick boundary (validated by the caller off the real-time thread).
    void set_limits(const SafetyLimits& limits) noexcept { limits_ = limits; }

private:
    std::uint32_t hard_faults(const SafetyInput& in) noexcept;
    Vec3 shape(const Vec3& desired) noexcept;
    Vec3 finish(const Vec3& out) noexcept;

    SafetyLimits limits_;
    Vec3 last_{};
    double thermal_n2_ = 0;
    double ramp_ = 0;
    bool engaged_ = false;
    std::uint32_t quiet_ticks_ = 0;
    std::uint32_t stale_ticks_ = 0;
    std::uint32_t fresh_ticks_ = 0;  ///< fault-free steps in a row while not engaged
    bool ever_engaged_ = false;      ///< forces were on once (a first engage always waits quiet)
    bool hard_fault_ = false;        ///< a hard fault since the last engage: wait for quiet
    std::uint32_t reasons_ = 0;
};

}  // namespace kerf::firmware_host
