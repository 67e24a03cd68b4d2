#include "firmware_host/safety/force_safety.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::firmware_host {
namespace {

double norm(const Vec3& v) noexcept { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

Vec3 scaled(const Vec3& v, double s) noexcept { return {v[0] * s, v[1] * s, v[2] * s}; }

bool finite(const Vec3& v) noexcept {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

std::string_view to_string(SafetyReason reason) noexcept {
    switch (reason) {
        case kReasonNone:
            return "none";
        case kReasonStale:
            return "stale input";
        case kReasonInvalidInput:
            return "invalid input";
        case kReasonNonFinite:
            return "non-finite force";
        case kReasonEStop:
            return "e-stop";
        case kReasonDeviceFault:
            return "device fault";
        case kReasonDisconnected:
            return "disconnected";
        case kReasonNotHomed:
            return "not homed";
        case kReasonWaitingToEngage:
            return "waiting to engage";
        case kReasonRamping:
            return "ramping in";
        case kReasonPeakClamp:
            return "peak clamp";
        case kReasonThermal:
            return "continuous-force limit";
        case kReasonSlew:
            return "slew limit";
    }
    return "unknown safety reason";
}

std::uint32_t ForceSafety::hard_faults(const SafetyInput& in) noexcept {
    std::uint32_t r = 0;
    const bool fresh = in.read_status == DeviceStatus::kOk;
    stale_ticks_ = fresh ? 0U : std::min(stale_ticks_, 0xFFFFFFFEU) + 1U;  // saturates
    if (stale_ticks_ >= std::max<std::uint32_t>(1U, limits_.stale_ticks)) r |= kReasonStale;
    if (in.read_status == DeviceStatus::kMalformed || in.read_status == DeviceStatus::kError) {
        r |= kReasonInvalidInput;
    }
    if (in.read_status == DeviceStatus::kDisconnected) r |= kReasonDisconnected;
    if (!finite(in.desired_force_n)) r |= kReasonNonFinite;
    if (in.flags.estop) r |= kReasonEStop;
    if (in.flags.watchdog_tripped || in.flags.encoder_fault || in.flags.over_temperature) {
        r |= kReasonDeviceFault;
    }
    if (!in.flags.homed) r |= kReasonNotHomed;
    return r;
}

namespace {
/// Reasons that are only late or unreadable samples: force resumes by itself when they pass.
constexpr std::uint32_t kTransientReasons = kReasonStale | kReasonInvalidInput;
}  // namespace

void ForceSafety::interrupt() noexcept {
    engaged_ = false;
    ramp_ = 0;
    quiet_ticks_ = 0;
    fresh_ticks_ = 0;
    last_ = {0, 0, 0};
}

Vec3 ForceSafety::step(const SafetyInput& in) noexcept {
    reasons_ = hard_faults(in);
    if (reasons_ != 0) {  // safe state: zero now (no slew on the way down), re-engage later
        engaged_ = false;
        ramp_ = 0;
        quiet_ticks_ = 0;
        fresh_ticks_ = 0;
        if ((reasons_ & ~kTransientReasons) != 0) hard_fault_ = true;
        return finish({0, 0, 0});
    }
    const double demand = norm(in.desired_force_n);
    if (!engaged_) {
        quiet_ticks_ = demand < limits_.engage_threshold_n ? quiet_ticks_ + 1U : 0U;
        // A lone late sample is tolerated while engaged, but it breaks a run towards resuming.
        fresh_ticks_ =
            in.read_status == DeviceStatus::kOk ? std::min(fresh_ticks_, 0xFFFFFFFEU) + 1U : 0U;
        const bool quiet = quiet_ticks_ >= limits_.engage_quiet_ticks;
        const bool resume =
            ever_engaged_ && !hard_fault_ && fresh_ticks_ >= limits_.resume_fresh_ticks;
        if (!quiet && !resume) {
            reasons_ |= kReasonWaitingToEngage;
            return finish({0, 0, 0});
        }
        engaged_ = true;
        ever_engaged_ = true;
        hard_fault_ = false;
    }
    return finish(shape(in.desired_force_n));
}

// Peak clamp, continuous limit, ramp-in, then slew from the last output: each keeps direction.
Vec3 ForceSafety::shape(const Vec3& desired) noexcept {
    Vec3 f = desired;
    double mag = norm(f);
    const double peak = std::max(0.0, limits_.peak_force_n);
    if (mag > peak) {
        f = scaled(f, peak / mag);
        mag = peak;
        reasons_ |= kReasonPeakClamp;
    }
    const double cont = std::clamp(limits_.continuous_force_n, 0.0, peak);
    if (thermal_n2_ >= cont * cont && mag > cont) {
        f = scaled(f, cont / mag);
        mag = cont;
        reasons_ |= kReasonThermal;
    }
    const double ramp_step = limits_.ramp_in_s > 0 ? limits_.period_s / limits_.ramp_in_s : 1.0;
    ramp_ = std::min(1.0, ramp_ + ramp_step);
    if (ramp_ < 1.0) {
        f = scaled(f, ramp_);
        reasons_ |= kReasonRamping;
    }
    const Vec3 delta = {f[0] - last_[0], f[1] - last_[1], f[2] - last_[2]};
    const double max_step = std::max(0.0, limits_.max_slew_n_per_s * limits_.period_s);
    const double step = norm(delta);
    if (step > max_step) {
        const double s = max_step / step;
        f = {last_[0] + delta[0] * s, last_[1] + delta[1] * s, last_[2] + delta[2] * s};
        reasons_ |= kReasonSlew;
    }
    return f;
}

Vec3 ForceSafety::finish(const Vec3& out) noexcept {
    const double alpha = limits_.thermal_time_constant_s > 0
                             ? std::min(1.0, limits_.period_s / limits_.thermal_time_constant_s)
                             : 1.0;
    const double f2 = out[0] * out[0] + out[1] * out[1] + out[2] * out[2];
    thermal_n2_ += alpha * (f2 - thermal_n2_);
    last_ = out;
    return out;
}

}  // namespace kerf::firmware_host
