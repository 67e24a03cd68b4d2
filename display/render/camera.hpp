// kerf::render::Camera — an orbit camera around a target point: presets that frame a bounding box
// from a named side, orbit and zoom for interaction, and the view/projection matrices the
// renderer uses. World frame: metres, +z up. No GL.
#pragma once

#include <glm/glm.hpp>
#include <string_view>

namespace kerf::render {

/// Named viewpoints, each framing the scene's bounding box.
enum class CameraPreset : std::uint8_t {
    kFront,      ///< looking along +y
    kSide,       ///< looking along -x
    kTop,        ///< looking down -z
    kIsometric,  ///< from (+x, -y, +z), the default
};
std::string_view to_string(CameraPreset p) noexcept;

class Camera {
public:
    /// A camera at `preset` framing the box [lo, hi] (metres).
    static Camera framing(const glm::dvec3& lo, const glm::dvec3& hi,
                          CameraPreset preset = CameraPreset::kIsometric);

    /// Turns about the target: yaw about +z, pitch towards the poles (clamped short of them), rad.
    void orbit(double yaw_rad, double pitch_rad) noexcept;
    /// Moves towards (factor < 1) or away from (factor > 1) the target.
    void zoom(double factor) noexcept;
    /// Sets the point the camera looks at, m.
    void set_target(const glm::dvec3& target_m) noexcept { target_ = target_m; }

    /// Eye position, world frame, m.
    glm::dvec3 eye() const noexcept;
    /// World -> eye matrix.
    glm::mat4 view() const noexcept;
    /// Eye -> clip matrix for a viewport of `aspect` = width / height.
    glm::mat4 projection(double aspect) const noexcept;

    double yaw_rad() const noexcept { return yaw_; }
    double pitch_rad() const noexcept { return pitch_; }
    double distance_m() const noexcept { return distance_; }
    const glm::dvec3& target() const noexcept { return target_; }

private:
    glm::dvec3 target_{0.0};
    double distance_ = 1.0;
    double yaw_ = 0.0;
    double pitch_ = 0.0;
    double fov_y_rad_ = 0.75;
};

}  // namespace kerf::render
