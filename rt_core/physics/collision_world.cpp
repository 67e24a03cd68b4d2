// CollisionWorld: per-body queries in the world frame (collision_world.hpp).
#include "rt_core/physics/collision_world.hpp"

#include <algorithm>
#include <cmath>

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
    if (!hit.found) return false;
    const Slot& s = slots_[hit.body];
    const Vec3 q = s.pose.apply_inverse(hit.point), d = s.pose.apply_inverse(p) - q;
    // The sign of (p - q) against the angle-weighted pseudonormal at q (Baerentzen & Aanaes): a
    // single face normal misjudges points whose nearest point is on a sharp edge or vertex.
    constexpr std::size_t kMaxIncident = 64;
    std::uint32_t incident[kMaxIncident];
    const std::size_t count = std::min(s.body->triangles_near(q, 1e-8, incident), kMaxIncident);
    Vec3 pseudo;
    for (std::size_t i = 0; i < count; ++i) {
        if (s.body->material(incident[i]) == Material::kCutSurface) continue;
        const TriangleCorners c = s.body->corners(incident[i]);
        const Vec3 n = normalized(cross(c.b - c.a, c.c - c.a));
        const Vec3* v[3] = {&c.a, &c.b, &c.c};
        double weight = M_PI;  // q on the face or on an edge: the face counts fully
        for (int k = 0; k < 3; ++k) {
            if (norm2(*v[k] - q) < 1e-16) {  // q is this corner: weight by the corner's angle
                const Vec3 e1 = normalized(*v[(k + 1) % 3] - *v[k]);
                const Vec3 e2 = normalized(*v[(k + 2) % 3] - *v[k]);
                weight = std::acos(std::clamp(dot(e1, e2), -1.0, 1.0));
            }
        }
        pseudo += n * weight;
    }
    if (norm2(pseudo) == 0) pseudo = s.pose.rotate_inverse(hit.normal);
    return dot(d, pseudo) < 0;
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

CollisionWorld::WayOut CollisionWorld::way_out(const Vec3& from, const Vec3& towards,
                                               double length_m, double min_gap_m) const noexcept {
    WayOut out;
    Vec3 d = normalized(towards - from);
    if (norm2(d) == 0) d = Vec3{0, 1, 0};
    const Vec3 end = from + d * length_m;
    SegmentCrossing crossings[kMaxWayOutCrossings];
    std::size_t count = 0;
    for (std::uint32_t i = 0; i < slot_end_; ++i) {
        const Slot& s = slots_[i];
        if (!s.body) continue;
        const Vec3 a = s.pose.apply_inverse(from), b = s.pose.apply_inverse(end);
        const Vec3 ab = b - a;
        const float lo[3] = {float(s.lo.x), float(s.lo.y), float(s.lo.z)};
        const float hi[3] = {float(s.hi.x), float(s.hi.y), float(s.hi.z)};
        if (!segment_hits_box(a, Vec3{1.0 / ab.x, 1.0 / ab.y, 1.0 / ab.z}, 1.0, lo, hi)) continue;
        const std::span<SegmentCrossing> room(crossings + count, kMaxWayOutCrossings - count);
        const std::size_t n = s.body->crossings(a, b, room);
        if (n > room.size()) return out;  // unknown: too many crossings
        for (std::size_t k = count; k < count + n; ++k) crossings[k].body = i;
        count += n;
    }
    std::sort(crossings, crossings + count,
              [](const SegmentCrossing& x, const SegmentCrossing& y) { return x.t < y.t; });
    int depth = 0;
    for (std::size_t k = 0; k < count; ++k) depth += crossings[k].sign;
    out.known = true;
    out.depth = std::max(depth, 0);
    out.exit = from;
    // The first crossing after which the ray is in no shell for at least min_gap_m (the next
    // crossing enters again); if none is that wide, the first after which it is in none at all.
    int inside = depth;
    std::size_t exit = count;
    for (std::size_t k = 0; k < count && depth > 0; ++k) {
        inside -= crossings[k].sign;
        if (inside > 0) continue;
        if (exit == count) exit = k;
        const double free_m =
            k + 1 < count ? (crossings[k + 1].t - crossings[k].t) * length_m : length_m;
        if (free_m >= min_gap_m) {
            exit = k;
            break;
        }
    }
    if (exit < count) {
        const SegmentCrossing& c = crossings[exit];
        const TriangleCorners t = slots_[c.body].body->corners(c.triangle);
        out.exit = from + d * (c.t * length_m);
        out.normal = slots_[c.body].pose.rotate(normalized(cross(t.b - t.a, t.c - t.a)));
    }
    return out;
}

}  // namespace kerf::physics
