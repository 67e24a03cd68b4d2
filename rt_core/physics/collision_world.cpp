// CollisionWorld: per-body queries in the world frame (collision_world.hpp).
#include "rt_core/physics/collision_world.hpp"

#include <algorithm>

#include "rt_core/physics/triangle_geometry.hpp"

namespace kerf::physics {

namespace {
const RigidTransform kIdentity{};
}

void CollisionWorld::set_body(std::uint32_t slot, const CollisionBody* body) noexcept {
    if (slot >= kMaxBodies) return;
    Slot& s = slots_[slot];
    s.body = body;
    if (body) {
        s.pose = body->world_from_body();
        body->bounds(s.lo, s.hi);
    }
    slot_end_ = 0;
    for (std::uint32_t i = 0; i < kMaxBodies; ++i) {
        if (slots_[i].body) slot_end_ = i + 1;
    }
}

void CollisionWorld::set_pose(std::uint32_t slot, const RigidTransform& world_from_body) noexcept {
    if (slot < kMaxBodies) slots_[slot].pose = world_from_body;
}

void CollisionWorld::clear() noexcept {
    slots_ = {};
    slot_end_ = 0;
}

const CollisionBody* CollisionWorld::body(std::uint32_t slot) const noexcept {
    return slot < kMaxBodies ? slots_[slot].body : nullptr;
}

const RigidTransform& CollisionWorld::pose(std::uint32_t slot) const noexcept {
    return slot < kMaxBodies ? slots_[slot].pose : kIdentity;
}

SurfaceHit CollisionWorld::closest_point(const Vec3& p, double max_distance,
                                         MaterialMask materials) const noexcept {
    SurfaceHit best;
    double limit = max_distance;
    for (std::uint32_t i = 0; i < slot_end_; ++i) {
        const Slot& s = slots_[i];
        if (!s.body) continue;
        const Vec3 q = s.pose.apply_inverse(p);
        const float lo[3] = {float(s.lo.x), float(s.lo.y), float(s.lo.z)};
        const float hi[3] = {float(s.hi.x), float(s.hi.y), float(s.hi.z)};
        if (box_distance2(q, lo, hi) > limit * limit) continue;
        SurfaceHit hit = s.body->closest_point(q, limit, materials);
        if (!hit.found) continue;
        limit = hit.distance;
        hit.body = i;
        hit.point = s.pose.apply(hit.point);
        hit.normal = s.pose.rotate(hit.normal);
        best = hit;
    }
    return best;
}

bool CollisionWorld::inside(const Vec3& p, double max_distance) const noexcept {
    const SurfaceHit hit = closest_point(p, max_distance, kBoneSurfaces);
    return hit.found && dot(p - hit.point, hit.normal) < 0;
}

SegmentHit CollisionWorld::first_hit(const Vec3& from, const Vec3& to,
                                     HitSides sides) const noexcept {
    SegmentHit best;
    for (std::uint32_t i = 0; i < slot_end_; ++i) {
        const Slot& s = slots_[i];
        if (!s.body) continue;
        const Vec3 a = s.pose.apply_inverse(from), b = s.pose.apply_inverse(to);
        SegmentHit hit = s.body->first_hit(a, b, sides);
        if (!hit.found || (best.found && hit.t >= best.t)) continue;
        hit.body = i;
        hit.point = from + (to - from) * hit.t;
        hit.normal = s.pose.rotate(hit.normal);
        best = hit;
    }
    return best;
}

}  // namespace kerf::physics
