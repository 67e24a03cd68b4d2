// The saw in bone: plane lock, feed resistance, cut events (saw_model.hpp).
#include "rt_core/physics/saw_model.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::physics {

std::string_view to_string(CutEventType type) noexcept {
    switch (type) {
        case CutEventType::kBegin:
            return "begin";
        case CutEventType::kProgress:
            return "progress";
        case CutEventType::kEnd:
            return "end";
    }
    return "unknown cut event";
}

std::string_view to_string(CutEndReason reason) noexcept {
    switch (reason) {
        case CutEndReason::kNone:
            return "none";
        case CutEndReason::kCompleted:
            return "completed";
        case CutEndReason::kWithdrawn:
            return "withdrawn";
        case CutEndReason::kAborted:
            return "aborted";
    }
    return "unknown end reason";
}

namespace {

/// The in-plane (u, v) frame of a locked cut.
struct PlaneFrame {
    Vec3 origin, u, v, n;
};

PlaneFrame frame_of(const CutEvent& cut) noexcept {
    return {cut.plane_point_m, cut.plane_u, cross(cut.plane_normal, cut.plane_u), cut.plane_normal};
}

}  // namespace

void SawModel::emit(CutEventType type, SawOutput& out) noexcept {
    if (out.event_count >= out.events.size()) return;
    CutEvent& e = out.events[out.event_count++];
    e = cut_;
    e.type = type;
}

Material SawModel::material_under_edge(const CollisionWorld& world,
                                       const Vec3& edge_m) const noexcept {
    const SurfaceHit hit = world.closest_point(edge_m, params_.cortical_thickness_m, kBoneSurfaces);
    return hit.found && hit.material == Material::kCortical ? Material::kCortical
                                                            : Material::kCancellous;
}

bool SawModel::begin_cut(const CollisionWorld& world, const ToolPose& pose,
                         const ContactOutput& contact, SawOutput& out) noexcept {
    const Vec3 u = pose.orientation.column(0), n = pose.orientation.column(2);
    const double half = 0.5 * params_.blade.length_m;
    const SegmentHit edge_hit =
        world.first_hit(pose.position_m - u * half, pose.position_m + u * half, HitSides::kBoth);
    if (!contact.in_contact && !edge_hit.found) {
        armed_ = true;  // clear of the bone: the next touch may start a cut
        return false;
    }
    if (!armed_) return false;  // still touching where the last cut ended
    cut_ = CutEvent{};
    cut_.cut_id = next_cut_id_++;
    if (edge_hit.found) {
        cut_.body_id = edge_hit.body;
        cut_.seed_point_m = edge_hit.point;
        cut_.triangle_hint = edge_hit.triangle;
    } else {
        cut_.body_id = contact.body;
        cut_.triangle_hint = contact.triangle;
        const SurfaceHit near =
            world.closest_point(contact.proxy_m, 4 * params_.blade.kerf_width_m);
        cut_.seed_point_m = near.found ? near.point : contact.proxy_m;
        if (near.found) cut_.triangle_hint = near.triangle, cut_.body_id = near.body;
    }
    cut_.plane_point_m = pose.position_m;
    cut_.plane_normal = normalized(n);
    cut_.plane_u = normalized(u - cut_.plane_normal * dot(u, cut_.plane_normal));
    cut_.blade = params_.blade;
    cut_.swept = {-half, half, 0, 0};
    locked_ = true;
    been_inside_ = false;
    front_depth_m_ = 0;
    since_progress_s_ = 0;
    reported_extent_m_ = 2 * half;
    swept_changed_ = false;
    emit(CutEventType::kBegin, out);
    return true;
}

double SawModel::advance_front(double edge_depth_m, double resistance_n_s_per_m,
                               double dt_s) noexcept {
    const double k = params_.front_stiffness_n_per_m;
    if (!(edge_depth_m > front_depth_m_) || !(k > 0)) return 0;  // behind the front: no push
    if (!(resistance_n_s_per_m > 0)) {
        front_depth_m_ = edge_depth_m;  // nothing resists: the front is where the edge is
        return 0;
    }
    // Backward Euler on resistance * d(front)/dt = k * (edge - front): the new front lies between
    // the old front and the edge whatever the ratio, so the force stays in [0, k * gap].
    const double a = k * dt_s / resistance_n_s_per_m;
    front_depth_m_ = (front_depth_m_ + a * edge_depth_m) / (1 + a);
    return k * (edge_depth_m - front_depth_m_);
}

void SawModel::end_cut(CutEndReason reason, SawOutput& out) noexcept {
    cut_.end_reason = reason;
    emit(CutEventType::kEnd, out);
    cut_.end_reason = CutEndReason::kNone;
    locked_ = false;
    armed_ = false;
}

SawOutput SawModel::step(const CollisionWorld& world, const ToolPose& pose,
                         const Vec3& velocity_m_s, double twist_rate_rad_s, bool running,
                         const ContactOutput& contact, double dt_s) noexcept {
    SawOutput out;
    if (!is_finite(pose.position_m) || !is_finite(velocity_m_s) || !(dt_s > 0)) {
        if (locked_) end_cut(CutEndReason::kAborted, out);
        return out;
    }
    if (!locked_) {
        if (!running || !begin_cut(world, pose, contact, out)) return out;
    } else if (!running) {
        end_cut(CutEndReason::kAborted, out);
        return out;
    }
    const PlaneFrame f = frame_of(cut_);
    const Vec3 rel = pose.position_m - f.origin;
    const double off = dot(rel, f.n), a = dot(rel, f.u), b = dot(rel, f.v);
    if (std::abs(off) > params_.max_off_plane_m) {
        end_cut(CutEndReason::kAborted, out);
        return out;
    }
    // The edge as it lies now, turned about the normal, in plane coordinates.
    const Vec3 u_now = pose.orientation.column(0);
    Vec3 u_in = normalized(u_now - f.n * dot(u_now, f.n));
    if (norm2(u_in) == 0) u_in = f.u;
    const double half = 0.5 * params_.blade.length_m;
    const double du = std::abs(dot(u_in, f.u)) * half, dv = std::abs(dot(u_in, f.v)) * half;
    SweptRect& s = cut_.swept;
    const SweptRect before = s;
    s.u_min_m = std::min(s.u_min_m, a - du), s.u_max_m = std::max(s.u_max_m, a + du);
    s.v_min_m = std::min(s.v_min_m, b - dv), s.v_max_m = std::max(s.v_max_m, b + dv);
    cut_.feed_depth_m = std::max(cut_.feed_depth_m, -b);
    swept_changed_ = swept_changed_ || s.u_min_m != before.u_min_m || s.u_max_m != before.u_max_m ||
                     s.v_min_m != before.v_min_m || s.v_max_m != before.v_max_m;

    // Forces: hold the plane; the edge pushes the cut front, which the material under the edge
    // lets advance at force / feed_resistance.
    const Material material = material_under_edge(world, pose.position_m);
    const CuttingParams& m =
        material == Material::kCortical ? params_.cortical : params_.cancellous;
    const double front_before = front_depth_m_;
    const double feed_force = advance_front(-b, m.feed_resistance_n_s_per_m, dt_s);
    out.force_n = f.n * (-m.plane_lock_stiffness_n_per_m * off) + f.v * feed_force;
    out.torque_n_m = f.n * (-m.twist_damping_n_m_s_per_rad * twist_rate_rad_s);
    out.material = material;
    out.feed_speed_m_s = (front_depth_m_ - front_before) / dt_s;
    out.feed_depth_m = cut_.feed_depth_m;
    out.front_depth_m = front_depth_m_;
    out.front_gap_m = std::max(-b - front_depth_m_, 0.0);
    out.locked = true;

    // Ends: back out above the entry, or through the far side of the bone.
    if (!been_inside_ && world.inside(pose.position_m, params_.blade.length_m)) been_inside_ = true;
    if (out.event_count == 0 && b > params_.withdraw_margin_m) {
        end_cut(CutEndReason::kWithdrawn, out);
        out.locked = false;
        return out;
    }
    if (out.event_count == 0 && been_inside_ && cut_.feed_depth_m > params_.blade.kerf_width_m &&
        b < -params_.withdraw_margin_m) {
        // Through: no part of the edge is in bone (no surface crossing along it, centre outside).
        const Vec3 e0 = pose.position_m - u_in * half, e1 = pose.position_m + u_in * half;
        if (!world.first_hit(e0, e1, HitSides::kBoth).found &&
            !world.inside(pose.position_m, params_.blade.length_m)) {
            end_cut(CutEndReason::kCompleted, out);
            out.locked = false;
            return out;
        }
    }
    // Progress: every progress_period_s while the sweep grows, or per progress_advance_m.
    since_progress_s_ += dt_s;
    const double extent = (s.u_max_m - s.u_min_m) + (s.v_max_m - s.v_min_m);
    const bool advanced = extent - reported_extent_m_ >= params_.progress_advance_m;
    if (out.event_count == 0 && swept_changed_ &&
        (advanced || since_progress_s_ >= params_.progress_period_s)) {
        emit(CutEventType::kProgress, out);
        since_progress_s_ = 0;
        reported_extent_m_ = extent;
        swept_changed_ = false;
    }
    return out;
}

}  // namespace kerf::physics
