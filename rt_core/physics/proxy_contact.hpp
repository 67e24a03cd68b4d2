// kerf::physics::ProxyContact — god-object (proxy) contact on the triangle mesh.
//
// The proxy is a point that follows the device but never crosses a surface: each tick it moves
// towards the device position by segment casts (CollisionWorld::first_hit, front faces), stopping
// `skin_m` before a crossing and sliding along up to three constraint planes (Zilles-Salisbury /
// Ruspini), so thin walls, edges, vertices and the rims of caps all stop it. The device is coupled
// to the proxy by a spring-damper: F = k (proxy - device) - b v_device,n (the damper acts on the
// velocity along the contact normal, only while in contact). Coulomb friction with stick/slip:
// while in contact, the proxy stays put tangentially (stick) until the tangential spring force
// exceeds the static bound; then it slides so that the tangential force equals the dynamic bound
// (slip) until the device comes back inside the static bound. The bounds are the profile's
// forces, capped by the normal force (no friction without load): min(static_friction_n, |F_n|).
//
// Meshes must be closed and outward-oriented (what the display publishes): only front faces stop
// the proxy, so a proxy that was ever put inside (reset) leaves through the surface. A body that
// moves (CollisionWorld::set_pose: a severed piece dragged) carries the proxy resting on it along,
// so the proxy stays on its surface instead of ending up inside it.
#pragma once

#include <cstdint>

#include "rt_core/physics/collision_world.hpp"

namespace kerf::physics {

/// Surface contact parameters (config::ContactParams plus the proxy's own).
struct ContactParams {
    double stiffness_n_per_m = 1500;   ///< device <-> proxy spring
    double damping_n_s_per_m = 2;      ///< damper on the device's normal velocity, in contact
    double static_friction_n = 0.4;    ///< tangential force before sliding starts
    double dynamic_friction_n = 0.25;  ///< tangential force while sliding, <= static
    double skin_m = 2e-6;              ///< gap the proxy keeps from the surface, m
};

/// What the contact model produced this tick (world frame, SI).
struct ContactOutput {
    Vec3 force_n;              ///< force on the device, N
    Vec3 proxy_m;              ///< proxy position after this tick, m
    Vec3 normal;               ///< contact normal (unit, outward) when in_contact
    double penetration_m = 0;  ///< device depth behind the proxy along the normal, m (>= 0)
    bool in_contact = false;   ///< the proxy is held by a surface
    bool slipping = false;     ///< friction: sliding (true) or sticking (false) while in contact
    std::uint32_t body = 0;    ///< touched body slot (in_contact)
    std::uint32_t triangle = kNoTriangle;  ///< touched triangle (in_contact)
    Material material = Material::kCortical;
};

class ProxyContact {
public:
    explicit ProxyContact(const ContactParams& params = {}) noexcept : params_(params) {}

    /// New parameters at a tick boundary (validated by the caller). noexcept.
    void set_params(const ContactParams& params) noexcept { params_ = params; }
    const ContactParams& params() const noexcept { return params_; }
    /// Puts the proxy at `position_m` (must be outside every body: e.g. the device at start).
    void reset(const Vec3& position_m) noexcept;
    /// Moves the proxy towards `device_m` and returns the coupling force. noexcept, no allocation,
    /// bounded work (a fixed number of casts). Non-finite input: zero force, proxy unchanged.
    ContactOutput step(const CollisionWorld& world, const Vec3& device_m,
                       const Vec3& device_velocity_m_s, double dt_s) noexcept;

    const Vec3& proxy() const noexcept { return proxy_; }

private:
    struct Plane {
        Vec3 n;        ///< unit outward normal
        double c = 0;  ///< the proxy must keep n . x >= c (the surface offset by the skin)
        std::uint32_t body = 0, triangle = kNoTriangle;
        Material material = Material::kCortical;
    };
    /// Moves from the proxy towards `goal` under the surface constraints: the frictionless proxy.
    Vec3 constrained_move(const CollisionWorld& world, const Vec3& goal, Plane* planes,
                          int& plane_count) const noexcept;

    ContactParams params_;
    Vec3 proxy_;
    bool sliding_ = false;
    bool resting_ = false;                       ///< the proxy ended the last tick on a surface
    std::uint32_t resting_body_ = 0;             ///< ... of this world slot
    const CollisionBody* resting_on_ = nullptr;  ///< ... holding this body (identity check only)
    RigidTransform resting_pose_;                ///< ... whose pose was this
};

}  // namespace kerf::physics
