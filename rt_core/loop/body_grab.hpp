// kerf::rt::BodyGrab — the hand takes hold of a bone piece and moves it (the paper: severed,
// moved, reattached; a chevron's freed head shifted laterally). While the grab button is held
// with the saw stopped and no cut locked, the body whose surface is nearest the tool point
// (within `reach_m` when the button went down) follows the tool's translation: its pose is the
// pose it had at the grab, translated by the tool's motion since (a 3-DoF hand turns nothing).
// The loop moves that body in its own collision world every tick and publishes BodyMoved (the
// event every consumer applies: kerf-display moves the piece, the journal keeps it) whenever the
// body has moved `publish_step_m` since the last one, and once more on release. Deterministic:
// the same inputs and worlds give the same events (lockstep, replay). Everything per tick is
// noexcept and allocation-free. Units: m.
#pragma once

#include <cstdint>

#include "rt_core/physics/collision_world.hpp"

namespace kerf::rt {

/// The grab's settings (configure time).
struct GrabPlan {
    std::uint32_t button = 3;        ///< held: the hand holds the body nearest the tool
    double reach_m = 0.005;          ///< a body this close to the tool point can be taken
    double publish_step_m = 0.0001;  ///< a BodyMoved per this much motion while held
};

/// A body's new pose for BodyMoved.
struct BodyMove {
    std::uint32_t body = 0;  ///< collision world slot (= the display's body id)
    physics::RigidTransform world_from_body;
};

class BodyGrab {
public:
    explicit BodyGrab(const GrabPlan& plan = {}) noexcept : plan_(plan) {}

    /// One tick, after kinematics and before collision: takes, moves (in `world`) or lets go of
    /// a body. Returns true when `out` holds a pose to publish as BodyMoved. noexcept, O(bodies).
    bool update(std::uint32_t buttons, const physics::Vec3& tool_m, bool saw_busy,
                physics::CollisionWorld& world, BodyMove& out) noexcept;
    /// After a new collision world was installed: the held body keeps its held pose (the
    /// display's world may predate the last moves). noexcept.
    void reapply(physics::CollisionWorld& world) const noexcept;
    /// Drops the hold without an event (a lost device). noexcept.
    void release() noexcept { held_ = false; }

    bool holding() const noexcept { return held_; }
    std::uint32_t body() const noexcept { return body_; }    ///< valid while holding()
    std::uint64_t grabs() const noexcept { return grabs_; }  ///< bodies taken so far

private:
    physics::RigidTransform pose_now(const physics::Vec3& tool_m) const noexcept;

    GrabPlan plan_;
    bool button_was_down_ = false;
    bool held_ = false;
    std::uint32_t body_ = 0;
    physics::Vec3 tool_at_grab_;
    physics::RigidTransform pose_at_grab_;
    physics::Vec3 published_translation_;  ///< translation of the last BodyMoved (or the grab)
    std::uint64_t grabs_ = 0;
};

}  // namespace kerf::rt
