// kerf::physics::ForceModel — the whole per-tick physics the loop calls: surface contact (proxy),
// the saw (plane lock, feed resistance, cut events) and the passivity controller, in that order.
//
//   ForceModel model(params);                 // configure: off the RT thread
//   model.reset(tool_position);               // the proxy starts at the tool (must be outside)
//   each tick: PhysicsOutput out = model.step(world, input, dt);   // noexcept, no allocation
//   -> out.force_n to ForceSafety and the device; out.saw.events[0..saw.event_count) to the rings;
//      out.contact_flags / penetration_m / dissipated_j to telemetry.
// The model keeps no pointer to the world: swapping a body between ticks is safe.
#pragma once

#include <array>
#include <cstdint>

#include "rt_core/physics/passivity_observer.hpp"
#include "rt_core/physics/proxy_contact.hpp"
#include "rt_core/physics/saw_model.hpp"

namespace kerf::physics {

/// Every parameter of the physics (map config::ForceProfile with physics_params_from_profile()).
struct PhysicsParams {
    ContactParams contact;
    SawParams saw;
    PassivityParams passivity;
};

/// The tool this tick, world frame.
struct ToolInput {
    ToolPose pose;                ///< cutting edge centre (the contact point) and blade axes
    Vec3 velocity_m_s;            ///< tool velocity, m/s (filtered by the device layer)
    double twist_rate_rad_s = 0;  ///< turning rate about the blade normal (0 without orientation)
    bool saw_running = false;     ///< the motor runs (a button / pedal)
};

/// Bits of PhysicsOutput::contact_flags; equal to ipc TelemetrySample::contact_flags bits.
inline constexpr std::uint32_t kContactTouching = 1u << 0;   ///< touching bone
inline constexpr std::uint32_t kContactCutLocked = 1u << 1;  ///< a cut plane is locked

/// What the physics produced this tick (world frame, SI).
struct PhysicsOutput {
    Vec3 force_n;                     ///< force on the device, before ForceSafety, N
    Vec3 torque_n_m;                  ///< torque for devices that render one, N m
    Vec3 proxy_m;                     ///< proxy (god-object) position, m
    double penetration_m = 0;         ///< tool depth behind the surface, m
    std::uint32_t contact_flags = 0;  ///< kContact* bits
    double dissipated_j = 0;          ///< energy the passivity controller removed this tick, J
    ContactOutput contact;            ///< surface contact details
    SawOutput saw;                    ///< cut details; saw.events[0..saw.event_count) to publish
};

class ForceModel {
public:
    explicit ForceModel(const PhysicsParams& params = {}) noexcept;

    /// New parameters at a tick boundary (validated off the RT thread). noexcept.
    void set_params(const PhysicsParams& params) noexcept;
    const PhysicsParams& params() const noexcept { return params_; }
    /// Re-starts contact at `tool_position_m` (outside every body) and forgets observed energy.
    void reset(const Vec3& tool_position_m) noexcept;
    /// Re-starts contact for a tool that may be inside a body (a device re-engaged after a loss,
    /// forces that were off): when the tool is in bone, the proxy goes to where a ray from it
    /// towards the nearest surface (searched within `reach_m`) is first in no shell, else to the
    /// tool. One closest-point query and a bounded ray walk (CollisionWorld::way_out). noexcept.
    void reset_outside(const CollisionWorld& world, const Vec3& tool_position_m,
                       double reach_m) noexcept;
    /// One tick. noexcept, no allocation, bounded work; non-finite input gives zero force.
    PhysicsOutput step(const CollisionWorld& world, const ToolInput& input, double dt_s) noexcept;

    const ProxyContact& contact() const noexcept { return contact_; }
    const SawModel& saw() const noexcept { return saw_; }
    const PassivityObserver& passivity() const noexcept { return passivity_; }

private:
    void place_proxy_outside(const CollisionWorld& world, const Vec3& tool_position_m,
                             double reach_m) noexcept;
    PhysicsParams params_;
    ProxyContact contact_;
    SawModel saw_;
    PassivityObserver passivity_;
};

}  // namespace kerf::physics
