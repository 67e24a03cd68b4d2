#include "rt_core/loop/body_grab.hpp"

namespace kerf::rt {

physics::RigidTransform BodyGrab::pose_now(const physics::Vec3& tool_m) const noexcept {
    physics::RigidTransform pose = pose_at_grab_;
    pose.translation = pose_at_grab_.translation + (tool_m - tool_at_grab_);
    return pose;
}

bool BodyGrab::update(std::uint32_t buttons, const physics::Vec3& tool_m, bool saw_busy,
                      physics::CollisionWorld& world, BodyMove& out) noexcept {
    const bool down = (buttons >> plan_.button) & 1u;
    const bool pressed = down && !button_was_down_;
    button_was_down_ = down;
    if (!held_) {
        if (!pressed || saw_busy || !physics::is_finite(tool_m)) return false;
        const physics::SurfaceHit hit = world.closest_point(tool_m, plan_.reach_m);
        if (!hit.found || !world.body(hit.body)) return false;
        held_ = true;
        body_ = hit.body;
        tool_at_grab_ = tool_m;
        pose_at_grab_ = world.pose(hit.body);
        published_translation_ = pose_at_grab_.translation;
        ++grabs_;
        return false;
    }
    if (!world.body(body_)) {  // the body is gone from the world (a reset scene)
        held_ = false;
        return false;
    }
    const physics::RigidTransform pose =
        physics::is_finite(tool_m) ? pose_now(tool_m) : world.pose(body_);
    world.set_pose(body_, pose);
    const bool letting_go = !down;
    if (letting_go) held_ = false;
    const double moved = physics::norm(pose.translation - published_translation_);
    if (!(moved >= plan_.publish_step_m) && !(letting_go && moved > 0)) return false;
    published_translation_ = pose.translation;
    out = BodyMove{body_, pose};
    return true;
}

void BodyGrab::reapply(physics::CollisionWorld& world) const noexcept {
    if (held_ && world.body(body_)) {
        physics::RigidTransform pose = pose_at_grab_;
        pose.translation = published_translation_;
        world.set_pose(body_, pose);
    }
}

}  // namespace kerf::rt
