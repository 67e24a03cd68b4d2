#include "display/render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace kerf::render {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxPitch = 0.49 * kPi;
}  // namespace

std::string_view to_string(CameraPreset p) noexcept {
    switch (p) {
        case CameraPreset::kFront:
            return "front";
        case CameraPreset::kSide:
            return "side";
        case CameraPreset::kTop:
            return "top";
        case CameraPreset::kIsometric:
            return "isometric";
    }
    return "unknown";
}

Camera Camera::framing(const glm::dvec3& lo, const glm::dvec3& hi, CameraPreset preset) {
    Camera c;
    c.target_ = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    c.distance_ = radius / std::sin(0.5 * c.fov_y_rad_) * 1.05;
    switch (preset) {
        case CameraPreset::kFront:
            c.yaw_ = -0.5 * kPi;
            c.pitch_ = 0.0;
            break;
        case CameraPreset::kSide:
            c.yaw_ = 0.0;
            c.pitch_ = 0.0;
            break;
        case CameraPreset::kTop:
            c.yaw_ = -0.5 * kPi;
            c.pitch_ = kMaxPitch;
            break;
        case CameraPreset::kIsometric:
            c.yaw_ = -0.25 * kPi;
            c.pitch_ = 0.6;
            break;
    }
    return c;
}

void Camera::orbit(double yaw_rad, double pitch_rad) noexcept {
    if (!std::isfinite(yaw_rad) || !std::isfinite(pitch_rad)) return;
    yaw_ = std::remainder(yaw_ + yaw_rad, 2.0 * kPi);
    pitch_ = std::clamp(pitch_ + pitch_rad, -kMaxPitch, kMaxPitch);
}

void Camera::zoom(double factor) noexcept {
    if (!std::isfinite(factor) || factor <= 0.0) return;
    distance_ = std::clamp(distance_ * factor, 1e-4, 1e3);
}

glm::dvec3 Camera::eye() const noexcept {
    const glm::dvec3 dir(std::cos(pitch_) * std::cos(yaw_), std::cos(pitch_) * std::sin(yaw_),
                         std::sin(pitch_));
    return target_ + distance_ * dir;
}

glm::mat4 Camera::view() const noexcept {
    return glm::mat4(glm::lookAt(eye(), target_, glm::dvec3(0, 0, 1)));
}

glm::mat4 Camera::projection(double aspect) const noexcept {
    const double near_m = std::max(distance_ * 0.02, 1e-5);
    const double far_m = distance_ * 4.0;
    return glm::mat4(glm::perspective(fov_y_rad_, aspect, near_m, far_m));
}

}  // namespace kerf::render
