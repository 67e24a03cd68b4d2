#include "display/cut/session_events.hpp"

namespace kerf::cut {
namespace {

/// Row-major rotation matrix of a unit quaternion (w, x, y, z).
std::array<double, 9> rotation(const std::array<double, 4>& q) noexcept {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
            2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

}  // namespace

std::string_view to_string(CutEndKind kind) noexcept {
    switch (kind) {
        case CutEndKind::kCompleted:
            return "completed";
        case CutEndKind::kWithdrawn:
            return "withdrawn";
        case CutEndKind::kAborted:
            return "aborted";
    }
    return "unknown";
}

Vec3 RigidPose::direction_to_body(const Vec3& d) const noexcept {
    const auto r = rotation(orientation_wxyz);
    return {r[0] * d[0] + r[3] * d[1] + r[6] * d[2], r[1] * d[0] + r[4] * d[1] + r[7] * d[2],
            r[2] * d[0] + r[5] * d[1] + r[8] * d[2]};
}

Vec3 RigidPose::to_body(const Vec3& p) const noexcept { return direction_to_body(p - position_m); }

Vec3 RigidPose::to_world(const Vec3& p) const noexcept {
    const auto r = rotation(orientation_wxyz);
    return Vec3{r[0] * p[0] + r[1] * p[1] + r[2] * p[2], r[3] * p[0] + r[4] * p[1] + r[5] * p[2],
                r[6] * p[0] + r[7] * p[1] + r[8] * p[2]} +
           position_m;
}

std::array<float, 16> RigidPose::matrix() const noexcept {
    const auto r = rotation(orientation_wxyz);
    std::array<float, 16> m{};
    for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row) m[col * 4 + row] = static_cast<float>(r[row * 3 + col]);
    }
    for (int row = 0; row < 3; ++row) m[12 + row] = static_cast<float>(position_m[row]);
    m[15] = 1.0f;
    return m;
}

}  // namespace kerf::cut
