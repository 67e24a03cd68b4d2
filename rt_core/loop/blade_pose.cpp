#include "rt_core/loop/blade_pose.hpp"

#include <cmath>

namespace kerf::rt {

physics::Mat3 axis_angle(const physics::Vec3& axis, double angle_rad) noexcept {
    const physics::Vec3 k = physics::normalized(axis);
    const double c = std::cos(angle_rad), s = std::sin(angle_rad), t = 1 - c;
    physics::Mat3 r;
    r.m[0][0] = t * k.x * k.x + c, r.m[0][1] = t * k.x * k.y - s * k.z;
    r.m[0][2] = t * k.x * k.z + s * k.y;
    r.m[1][0] = t * k.x * k.y + s * k.z, r.m[1][1] = t * k.y * k.y + c;
    r.m[1][2] = t * k.y * k.z - s * k.x;
    r.m[2][0] = t * k.x * k.z - s * k.y, r.m[2][1] = t * k.y * k.z + s * k.x;
    r.m[2][2] = t * k.z * k.z + c;
    return r;
}

physics::Mat3 multiply(const physics::Mat3& a, const physics::Mat3& b) noexcept {
    physics::Mat3 r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
        }
    }
    return r;
}

void BladePose::update(std::uint32_t buttons, bool has_orientation,
                       const double (&wxyz)[4]) noexcept {
    const std::uint32_t pressed = buttons & ~last_buttons_;
    last_buttons_ = buttons;
    running_ = (buttons >> plan_.saw_button) & 1u;
    const bool was_sensed = sensed_;
    sensed_ = has_orientation;
    if (has_orientation) {
        const physics::Mat3 device =
            physics::rotation_from_quaternion(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
        current_ = multiply(plan_.world_from_device, device);
        return;
    }
    const int before = steps_;
    if ((pressed >> plan_.tilt_up_button) & 1u) ++steps_;
    if ((pressed >> plan_.tilt_down_button) & 1u) --steps_;
    if (steps_ != before || was_sensed) {
        const double angle = double(steps_) * plan_.step_deg * M_PI / 180.0;
        current_ = multiply(axis_angle(plan_.planned.column(0), angle), plan_.planned);
    }
}

}  // namespace kerf::rt
