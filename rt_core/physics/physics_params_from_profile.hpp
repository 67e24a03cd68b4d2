// Maps a validated config::ForceProfile onto PhysicsParams. Header-only and field-by-field, so
// kerf_physics itself does not link the TOML loader; call it off the RT thread (after
// validate_force_profile), then ForceModel::set_params() at a tick boundary.
#pragma once

#include "config/force_profile.hpp"
#include "rt_core/physics/force_model.hpp"

namespace kerf::physics {

/// The profile's contact, cutting and saw values over `base` (which supplies the physics-only
/// parameters the profile has no key for: skin, cortical thickness, passivity ...).
inline PhysicsParams physics_params_from_profile(const config::ForceProfile& profile,
                                                 PhysicsParams base = {}) {
    base.contact.stiffness_n_per_m = profile.contact.stiffness_n_per_m;
    base.contact.damping_n_s_per_m = profile.contact.damping_n_s_per_m;
    base.contact.static_friction_n = profile.contact.static_friction_n;
    base.contact.dynamic_friction_n = profile.contact.dynamic_friction_n;
    const auto cutting = [](const config::CuttingMaterial& m) {
        return CuttingParams{m.feed_resistance_n_s_per_m, m.plane_lock_stiffness_n_per_m,
                             m.twist_damping_n_m_s_per_rad};
    };
    // The edge meets the cut front as the tool meets a surface: with the wall's stiffness, which
    // the device profile's limits already render stably.
    base.saw.front_stiffness_n_per_m = profile.contact.stiffness_n_per_m;
    base.saw.cortical = cutting(profile.cortical);
    base.saw.cancellous = cutting(profile.cancellous);
    base.saw.blade = {profile.saw.blade_length_m, profile.saw.blade_depth_m,
                      profile.saw.kerf_width_m};
    return base;
}

}  // namespace kerf::physics
