// kerf::rt::BladePose — the saw blade's orientation each tick. A device that senses orientation
// (a Kerf HID device announcing it, a Phantom/Touch-class mechanism) gives it directly; without
// one the blade takes the planned cut's orientation and the user steps it with two buttons (tilt
// about the blade's edge, +/- step_deg per press). The saw runs while `saw_button` is held.
// Everything per tick is noexcept and allocation-free.
#pragma once

#include <cstdint>

#include "rt_core/physics/vec3.hpp"

namespace kerf::rt {

/// The planned cut and the buttons (configure time).
struct BladePlan {
    /// Blade axes of the planned cut, world frame: columns u (edge), v (edge -> back), n (normal).
    /// Default: a transverse cut of the built-in foot (normal +z along the toes, edge along +x,
    /// the blade entering from the dorsal side, cutting towards -y).
    physics::Mat3 planned;
    double step_deg = 5.0;         ///< tilt per button press
    std::uint32_t saw_button = 0;  ///< held: the saw runs
    std::uint32_t tilt_up_button = 1;
    std::uint32_t tilt_down_button = 2;
    /// Rotation from the device frame to the world frame (applied to sensed orientations).
    physics::Mat3 world_from_device;
};

class BladePose {
public:
    explicit BladePose(const BladePlan& plan) noexcept : plan_(plan), current_(plan.planned) {}

    /// Updates from this tick's buttons and (when sensed) orientation. noexcept.
    void update(std::uint32_t buttons, bool has_orientation, const double (&wxyz)[4]) noexcept;
    /// The blade axes this tick, world frame.
    const physics::Mat3& orientation() const noexcept { return current_; }
    bool saw_running() const noexcept { return running_; }
    bool sensed() const noexcept { return sensed_; }
    /// Signed number of tilt steps applied to the planned orientation.
    int steps() const noexcept { return steps_; }

private:
    BladePlan plan_;
    physics::Mat3 current_;
    std::uint32_t last_buttons_ = 0;
    int steps_ = 0;
    bool running_ = false;
    bool sensed_ = false;
};

/// The rotation by `angle_rad` about the unit axis `axis` (Rodrigues). noexcept.
physics::Mat3 axis_angle(const physics::Vec3& axis, double angle_rad) noexcept;
/// a * b.
physics::Mat3 multiply(const physics::Mat3& a, const physics::Mat3& b) noexcept;

}  // namespace kerf::rt
