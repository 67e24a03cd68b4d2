// kerf::physics::CollisionWorld — the bodies the tool can touch this tick, each with its pose,
// queried in the world frame. Fixed capacity (one slot per mailbox body), no allocation: the loop
// owns one and changes it only at tick boundaries, from the RT thread.
//
// The world does not own the bodies: whoever calls set_body() keeps the CollisionBody alive until
// the slot is changed and the loop has moved past that tick (free it off the RT thread).
#pragma once

#include <array>
#include <cstdint>

#include "rt_core/physics/collision_body.hpp"

namespace kerf::physics {

inline constexpr std::uint32_t kMaxBodies = 64;  ///< = ipc::kMeshMaxBodies

class CollisionWorld {
public:
    /// Puts `body` (may be nullptr: empty slot) in `slot` with the pose it was published with.
    /// Out-of-range slots are ignored. noexcept, O(1).
    void set_body(std::uint32_t slot, const CollisionBody* body) noexcept;
    /// Moves the body in `slot` (a BodyMoved: a severed piece dragged). noexcept, O(1).
    void set_pose(std::uint32_t slot, const RigidTransform& world_from_body) noexcept;
    /// Empties every slot. noexcept.
    void clear() noexcept;

    const CollisionBody* body(std::uint32_t slot) const noexcept;
    const RigidTransform& pose(std::uint32_t slot) const noexcept;
    /// One past the highest occupied slot.
    std::uint32_t slot_end() const noexcept { return slot_end_; }

    // ---- per tick: noexcept, allocation-free, world frame ------------------------------------
    /// Nearest surface point over all bodies within `max_distance` (m), `materials` only.
    SurfaceHit closest_point(const Vec3& p, double max_distance,
                             MaterialMask materials = kAllMaterials) const noexcept;
    /// Whether `p` is inside a body: the nearest bone surface (within `max_distance`) faces away.
    /// Exact on faces; near edges and vertices of sharp features it may err. For the saw.
    bool inside(const Vec3& p, double max_distance) const noexcept;
    /// First crossing of from -> to with any body's surface.
    SegmentHit first_hit(const Vec3& from, const Vec3& to, HitSides sides) const noexcept;

    /// Where a point leaves the bone along a ray (WayOut).
    struct WayOut {
        bool known = false;  ///< false: more crossings than the query walks (result unknown)
        int depth = 0;       ///< shells containing the start (front/back crossings counted)
        Vec3 exit;           ///< the first point on the ray inside no shell (the start if 0)
        Vec3 normal;         ///< outward normal of the surface crossed there (depth > 0)
    };
    /// Follows the ray from `from` towards `towards` (up to `length_m`), counting every surface
    /// crossing (leaving a shell +1, entering -1): the start lies inside that many shells, which
    /// is exact for closed outward meshes even where shells interpenetrate (joints) or share a
    /// plane, unlike the nearest-surface test of inside(). Returns where the ray is first in no
    /// shell. One traversal per body collects every crossing (CollisionBody::crossings, watertight
    /// through shared edges and vertices) into a fixed array of kMaxWayOutCrossings. Bounded,
    /// noexcept, no allocation.
    /// `min_gap_m`: a stretch in no shell shorter than this before the ray enters one again is
    /// no way out (a withdrawn cut's coincident caps, closed in the collision mesh: leaving one
    /// side and entering the other at the same point).
    WayOut way_out(const Vec3& from, const Vec3& towards, double length_m,
                   double min_gap_m = 0) const noexcept;
    /// Triangle crossings way_out() collects at most; more: the result is unknown.
    static constexpr int kMaxWayOutCrossings = 96;

private:
    struct Slot {
        const CollisionBody* body = nullptr;
        RigidTransform pose;
        Vec3 lo, hi;  ///< body bounds, body frame
    };
    std::array<Slot, kMaxBodies> slots_{};
    std::uint32_t slot_end_ = 0;
};

}  // namespace kerf::physics
