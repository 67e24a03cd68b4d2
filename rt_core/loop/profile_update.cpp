#include "rt_core/loop/profile_update.hpp"

namespace kerf::rt {

#define KERF_PARAM(NAME, EXPR)                                             \
    ForceParameter {                                                       \
        NAME, [](const config::ForceProfile& p) { return double(p.EXPR); } \
    }

const std::array<ForceParameter, kForceParameterCount> kForceParameters = {{
    KERF_PARAM("contact.stiffness_n_per_m", contact.stiffness_n_per_m),
    KERF_PARAM("contact.damping_n_s_per_m", contact.damping_n_s_per_m),
    KERF_PARAM("contact.static_friction_n", contact.static_friction_n),
    KERF_PARAM("contact.dynamic_friction_n", contact.dynamic_friction_n),
    KERF_PARAM("limits.max_force_n", limits.max_force_n),
    KERF_PARAM("limits.slew_rate_n_per_s", limits.slew_rate_n_per_s),
    KERF_PARAM("limits.ramp_in_s", limits.ramp_in_s),
    KERF_PARAM("limits.engage_threshold_n", limits.engage_threshold_n),
    KERF_PARAM("limits.engage_quiet_ticks", limits.engage_quiet_ticks),
    KERF_PARAM("cortical.feed_n_s_per_m", cortical.feed_resistance_n_s_per_m),
    KERF_PARAM("cortical.lock_n_per_m", cortical.plane_lock_stiffness_n_per_m),
    KERF_PARAM("cortical.twist_n_m_s_per_rad", cortical.twist_damping_n_m_s_per_rad),
    KERF_PARAM("cancellous.feed_n_s_per_m", cancellous.feed_resistance_n_s_per_m),
    KERF_PARAM("cancellous.lock_n_per_m", cancellous.plane_lock_stiffness_n_per_m),
    KERF_PARAM("cancellous.twist_n_m_s_per_rad", cancellous.twist_damping_n_m_s_per_rad),
    KERF_PARAM("saw.blade_length_m", saw.blade_length_m),
    KERF_PARAM("saw.blade_depth_m", saw.blade_depth_m),
    KERF_PARAM("saw.kerf_width_m", saw.kerf_width_m),
    KERF_PARAM("saw.speed_rpm", saw.speed_rpm),
}};

#undef KERF_PARAM

std::uint32_t diff_profiles(const config::ForceProfile& before, const config::ForceProfile& after,
                            std::array<ParameterChange, kForceParameterCount>& out) {
    std::uint32_t n = 0;
    for (std::uint32_t id = 0; id < kForceParameterCount; ++id) {
        const double a = kForceParameters[id].get(before);
        const double b = kForceParameters[id].get(after);
        if (a != b) out[n++] = ParameterChange{id, b, a};
    }
    return n;
}

}  // namespace kerf::rt
