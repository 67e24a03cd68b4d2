// kerf::rt::ProfileUpdate — a validated force profile ready for the loop: the physics and safety
// parameters it maps to and the list of values that changed (one ParametersChanged event each).
// Built off the real-time thread by ProfileReloader; swapped in at a tick boundary.
//
// Parameter ids are this file's table order (kForceParameters): stable, append-only, and what the
// `parameter_id` of an ipc::ParametersChangedPayload means.
#pragma once

#include <array>
#include <cstdint>

#include "config/force_profile.hpp"
#include "firmware_host/safety/force_safety.hpp"
#include "rt_core/physics/force_model.hpp"

namespace kerf::rt {

/// One force-profile value by stable id and name (name suffix = SI unit).
struct ForceParameter {
    const char* name;                              ///< e.g. "contact.stiffness_n_per_m"
    double (*get)(const config::ForceProfile& p);  ///< reads it from a profile
};
inline constexpr std::uint32_t kForceParameterCount = 19;
extern const std::array<ForceParameter, kForceParameterCount> kForceParameters;

struct ParameterChange {
    std::uint32_t id = 0;  ///< index in kForceParameters
    double value = 0;
    double previous = 0;
};

struct ProfileUpdate {
    std::uint64_t revision = 0;  ///< 1, 2, ... per accepted reload
    physics::PhysicsParams physics;
    firmware_host::SafetyLimits safety;
    std::array<ParameterChange, kForceParameterCount> changes{};
    std::uint32_t change_count = 0;
};

/// The values that differ between `before` and `after` (exact comparison), in table order.
std::uint32_t diff_profiles(const config::ForceProfile& before, const config::ForceProfile& after,
                            std::array<ParameterChange, kForceParameterCount>& out);

}  // namespace kerf::rt
