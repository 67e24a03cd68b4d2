// The per-tick physics: contact, saw, passivity (force_model.hpp).
#include "rt_core/physics/force_model.hpp"

namespace kerf::physics {

ForceModel::ForceModel(const PhysicsParams& params) noexcept
    : params_(params), contact_(params.contact), saw_(params.saw), passivity_(params.passivity) {}

void ForceModel::set_params(const PhysicsParams& params) noexcept {
    params_ = params;
    contact_.set_params(params.contact);
    saw_.set_params(params.saw);
    passivity_.set_params(params.passivity);
}

void ForceModel::reset(const Vec3& tool_position_m) noexcept {
    contact_.reset(tool_position_m);
    passivity_.reset();
}

void ForceModel::reset_outside(const CollisionWorld& world, const Vec3& tool_position_m,
                               double reach_m) noexcept {
    passivity_.reset();
    place_proxy_outside(world, tool_position_m, reach_m);
}

void ForceModel::place_proxy_outside(const CollisionWorld& world, const Vec3& tool_position_m,
                                     double reach_m) noexcept {
    // The nearest surface says which way is out; a ray that way, counting every crossing, says
    // whether the tool is in bone at all and where it is in no shell any more (shells that
    // interpenetrate at joints: the nearest surface may be another bone's, entered, not left).
    const SurfaceHit near = world.closest_point(tool_position_m, reach_m, kBoneSurfaces);
    const double gap = 4 * params_.contact.skin_m;
    const Vec3 towards = near.found ? near.point : tool_position_m + Vec3{0, 1, 0};
    // The proxy goes `gap` past the exit, so an exit into less than twice that is no room.
    const CollisionWorld::WayOut out = world.way_out(tool_position_m, towards, 1.0, 2 * gap);
    if (out.known) {
        contact_.reset(out.depth > 0 ? out.exit + out.normal * gap : tool_position_m);
    } else if (near.found && dot(tool_position_m - near.point, near.normal) < 0) {
        contact_.reset(near.point + near.normal * gap);
    } else {
        contact_.reset(tool_position_m);
    }
}

PhysicsOutput ForceModel::step(const CollisionWorld& world, const ToolInput& input,
                               double dt_s) noexcept {
    PhysicsOutput out;
    const Vec3& tool = input.pose.position_m;
    if (!is_finite(tool) || !is_finite(input.velocity_m_s) || !(dt_s > 0)) {
        out.proxy_m = contact_.proxy();
        return out;
    }
    const bool was_locked = saw_.locked();
    if (!was_locked) out.contact = contact_.step(world, tool, input.velocity_m_s, dt_s);
    out.saw = saw_.step(world, input.pose, input.velocity_m_s, input.twist_rate_rad_s,
                        input.saw_running, out.contact, dt_s);
    Vec3 force;
    double stored_j = 0;  // energy the environment's springs hold now (for the observer)
    if (out.saw.locked) {
        // In its own kerf the blade cuts: no surface contact; the proxy rides with the tool.
        contact_.reset(tool);
        out.contact = ContactOutput{};
        out.contact.proxy_m = tool;
        force = out.saw.force_n;
        out.torque_n_m = out.saw.torque_n_m;
        const double k_lock = out.saw.material == Material::kCortical
                                  ? params_.saw.cortical.plane_lock_stiffness_n_per_m
                                  : params_.saw.cancellous.plane_lock_stiffness_n_per_m;
        const double off =
            dot(tool - saw_.current_cut().plane_point_m, saw_.current_cut().plane_normal);
        const double gap = out.saw.front_gap_m;
        stored_j = 0.5 * k_lock * off * off + 0.5 * params_.saw.front_stiffness_n_per_m * gap * gap;
    } else {
        if (was_locked) {
            // The cut ended this tick: put the proxy back outside the bone, on the nearest surface.
            place_proxy_outside(world, tool, params_.saw.blade.length_m);
            out.contact = contact_.step(world, tool, input.velocity_m_s, dt_s);
        }
        force = out.contact.force_n;
        const double d = norm(out.contact.proxy_m - tool);
        if (out.contact.in_contact) stored_j = 0.5 * params_.contact.stiffness_n_per_m * d * d;
    }
    const PassivityOutput p = passivity_.step(force, input.velocity_m_s, stored_j, dt_s);
    out.force_n = p.force_n;
    out.dissipated_j = p.dissipated_j;
    out.proxy_m = contact_.proxy();
    out.penetration_m = out.contact.penetration_m;
    if (out.contact.in_contact || out.saw.locked) out.contact_flags |= kContactTouching;
    if (out.saw.locked) out.contact_flags |= kContactCutLocked;
    return out;
}

}  // namespace kerf::physics
