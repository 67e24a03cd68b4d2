// God-object contact (proxy_contact.hpp).
#include "rt_core/physics/proxy_contact.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::physics {

namespace {

constexpr int kMaxCasts = 6;  ///< segment casts per tick (bounded work)

/// `g` projected onto the plane n . x = c.
Vec3 onto(const Vec3& g, const Vec3& n, double c) noexcept { return g - n * (dot(n, g) - c); }

}  // namespace

void ProxyContact::reset(const Vec3& position_m) noexcept {
    if (is_finite(position_m)) proxy_ = position_m;
    sliding_ = false;
    resting_ = false;
}

namespace {

bool same_pose(const RigidTransform& a, const RigidTransform& b) noexcept {
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            if (a.rotation.m[r][c] != b.rotation.m[r][c]) return false;
        }
    }
    return a.translation == b.translation;
}

}  // namespace

Vec3 ProxyContact::constrained_move(const CollisionWorld& world, const Vec3& goal, Plane* planes,
                                    int& plane_count) const noexcept {
    const double skin = params_.skin_m;
    Vec3 p = proxy_;
    Vec3 target = goal;
    for (int cast = 0; cast < kMaxCasts; ++cast) {
        const Vec3 d = target - p;
        const double length = norm(d);
        if (!(length > 0)) return p;
        const SegmentHit hit = world.first_hit(p, target, HitSides::kFront);
        if (!hit.found) return target;
        // Stop on the free part of the segment, about `skin` from the surface along its normal.
        const double cos_in = std::max(-dot(d * (1.0 / length), hit.normal), 0.05);
        const double back = std::min(hit.t, skin / (cos_in * length));
        p = p + d * (hit.t - back);
        if (plane_count == 3) return p;  // a corner: no direction left
        planes[plane_count++] = {hit.normal, dot(hit.normal, hit.point) + skin, hit.body,
                                 hit.triangle, hit.material};
        if (plane_count == 3) return p;
        // The goal projected onto the active planes (Lagrange: keep the ones it violates).
        const Plane& a = planes[plane_count - 1];
        target = onto(goal, a.n, a.c);
        if (plane_count == 2) {
            const Plane& b = planes[0];
            if (dot(b.n, target) < b.c) {
                const Vec3 t2 = onto(goal, b.n, b.c);
                if (dot(a.n, t2) >= a.c) {
                    target = t2;
                } else {
                    const double n12 = dot(a.n, b.n), det = 1 - n12 * n12;
                    if (det < 1e-9) return p;  // (anti)parallel walls: nowhere to slide
                    const double ra = dot(a.n, goal) - a.c, rb = dot(b.n, goal) - b.c;
                    const double la = (ra - n12 * rb) / det, lb = (rb - n12 * ra) / det;
                    target = goal - a.n * la - b.n * lb;
                }
            }
        }
    }
    return p;
}

ContactOutput ProxyContact::step(const CollisionWorld& world, const Vec3& device_m,
                                 const Vec3& device_velocity_m_s, double dt_s) noexcept {
    ContactOutput out;
    out.proxy_m = proxy_;
    if (!is_finite(device_m) || !is_finite(device_velocity_m_s) || !(dt_s > 0)) return out;

    // The body the proxy rests on moved since the last tick: the proxy moves with it.
    if (resting_ && world.body(resting_body_) == resting_on_ &&
        !same_pose(world.pose(resting_body_), resting_pose_)) {
        proxy_ = world.pose(resting_body_).apply(resting_pose_.apply_inverse(proxy_));
    }
    resting_ = false;

    Plane planes[3];
    int plane_count = 0;
    const Vec3 free = constrained_move(world, device_m, planes, plane_count);
    if (plane_count == 0) {  // nothing in the way: the proxy is the device
        proxy_ = free;
        sliding_ = false;
        out.proxy_m = proxy_;
        return out;
    }
    // Contact normal: the direction the surfaces push (proxy - device), else the first plane's.
    const double k = params_.stiffness_n_per_m;
    Vec3 n = normalized(free - device_m);
    if (norm2(n) == 0) n = planes[0].n;
    const double depth = std::max(dot(free - device_m, n), 0.0);
    const double normal_force = k * depth;

    // Coulomb friction on the tangential part of the proxy's slide (the normal part always
    // follows the surface): stick while the tangential spring force stays under the static bound;
    // while slipping, trail the frictionless proxy by the dynamic bound.
    Vec3 next = free;
    const Vec3 slide = free - proxy_;
    const Vec3 tangential = slide - n * dot(slide, n);
    const double t_length = norm(tangential);
    if (k > 0 && t_length > 0) {
        const double static_bound = std::min(params_.static_friction_n, normal_force) / k;
        const double dynamic_bound = std::min(params_.dynamic_friction_n, normal_force) / k;
        Vec3 held = free;
        if (!sliding_ && t_length <= static_bound) {
            held = free - tangential;
        } else if (t_length <= dynamic_bound) {
            held = free - tangential;
            sliding_ = false;
        } else {
            sliding_ = true;
            held = free - tangential * (dynamic_bound / t_length);
        }
        // The friction-held point must be reachable without crossing a surface.
        if (held == proxy_ || !world.first_hit(proxy_, held, HitSides::kFront).found) next = held;
    } else {
        sliding_ = false;
    }
    proxy_ = next;

    Vec3 force = (proxy_ - device_m) * k;
    force -= n * (params_.damping_n_s_per_m * dot(device_velocity_m_s, n));
    const double fn = dot(force, n);
    if (fn < 0) force -= n * fn;  // a surface pushes, never pulls

    const Plane& touched = planes[plane_count - 1];
    resting_ = true;
    resting_body_ = touched.body;
    resting_on_ = world.body(touched.body);
    resting_pose_ = world.pose(touched.body);
    out.force_n = force;
    out.proxy_m = proxy_;
    out.normal = n;
    out.penetration_m = depth;
    out.in_contact = true;
    out.slipping = sliding_;
    out.body = touched.body;
    out.triangle = touched.triangle;
    out.material = touched.material;
    return out;
}

}  // namespace kerf::physics
