// kerf::config::ForceProfile — how bone feels (config/force/*.toml).
//
// Contact (virtual wall) parameters, the safety envelope the force model works inside, the
// cutting resistance of each bone material and the saw's geometry. SI units throughout.
// `validate_force_profile()` is a pure function the live-reload path calls off the real-time
// thread before swapping a new profile in at a tick boundary; the loader runs the same checks.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/result.hpp"
#include "config/config_error.hpp"

namespace kerf::config {

/// Surface contact: a spring-damper wall with Coulomb friction.
struct ContactParams {
    double stiffness_n_per_m = 0;   ///< wall spring
    double damping_n_s_per_m = 0;   ///< wall damper (on penetration velocity)
    double static_friction_n = 0;   ///< tangential force before sliding starts
    double dynamic_friction_n = 0;  ///< tangential force while sliding, <= static
};

/// The envelope the force model's output is shaped into before the device's own limits.
struct ForceLimits {
    double max_force_n = 0;                ///< clamp on |F| (must not exceed the device's peak)
    double slew_rate_n_per_s = 0;          ///< largest rate of change of |F|
    double ramp_in_s = 0;                  ///< time to ramp from 0 to full force after engaging
    double engage_threshold_n = 0;         ///< forces engage only once the demand is below this...
    std::uint32_t engage_quiet_ticks = 0;  ///< ...for this many consecutive ticks
};

/// Resistance of one bone material to the saw.
struct CuttingMaterial {
    double feed_resistance_n_s_per_m = 0;     ///< force opposing advance, per m/s of feed speed
    double plane_lock_stiffness_n_per_m = 0;  ///< spring holding the blade in the cut plane
    double twist_damping_n_m_s_per_rad = 0;   ///< torque opposing rotation about the plane normal
};

/// The oscillating saw: an oriented thin box (length x depth x kerf width).
struct SawParams {
    double blade_length_m = 0;  ///< along the blade, hub to teeth
    double blade_depth_m = 0;   ///< across the blade, in the cut plane
    double kerf_width_m = 0;    ///< thickness of material removed
    double speed_rpm = 0;       ///< oscillations (or revolutions) per minute
};

/// One force profile.
struct ForceProfile {
    std::string name;         ///< e.g. "default"
    std::string description;  ///< free text, may be empty
    ContactParams contact;
    ForceLimits limits;
    CuttingMaterial cortical;    ///< dense outer bone
    CuttingMaterial cancellous;  ///< spongy inner bone
    SawParams saw;
};

/// Every problem with `profile` (ranges, finiteness, cross-field rules); empty when valid.
/// Pure: no I/O, no globals; may allocate, so call it off the real-time thread.
/// Errors carry `key` and `value` but no file position (line == 0).
std::vector<ConfigError> validate_force_profile(const ForceProfile& profile);

/// Parses a force profile from TOML text; `source_name` is used in error messages.
Result<ForceProfile, ConfigError> parse_force_profile(std::string_view text,
                                                      std::string_view source_name);

/// Reads and parses a force profile file.
Result<ForceProfile, ConfigError> load_force_profile(const std::filesystem::path& path);

}  // namespace kerf::config
