// The events a CutSession applies, in the cutting library's own terms (double precision, world
// frame, metres). The display process decodes kerf::ipc records into these (display/app); the
// CLI builds them from its arguments; tests build them by hand. Nothing here knows about shared
// memory.
//
// The blade's frame: origin `point_m`, unit normal `normal`, in-plane axis `u` (the blade's
// length direction) and v = normal x u. A swept region is a rectangle in that (u, v) frame. It
// is NOT the frame kerf::cut::Plane derives from the normal; CutSession converts between them.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "display/cut/plane.hpp"

namespace kerf::cut {

/// A cut plane with the blade's own in-plane axis (world frame).
struct BladeFrame {
    Vec3 point_m{0.0, 0.0, 0.0};  ///< a point on the plane, m
    Vec3 normal{0.0, 0.0, 1.0};   ///< plane normal (normalised by the session)
    Vec3 u{1.0, 0.0, 0.0};        ///< blade length direction in the plane (re-orthogonalised)
};

/// A rectangle in a BladeFrame's (u, v) coordinates, m.
struct SweptRect {
    double u_min_m = 0.0;
    double u_max_m = 0.0;
    double v_min_m = 0.0;
    double v_max_m = 0.0;
};

/// The blade entered bone: lock the plane and slice (nothing visible changes yet).
struct CutBegin {
    std::uint32_t cut_id = 0;
    std::uint32_t body_id = 0;  ///< the body being cut (index in CutSession::bodies())
    BladeFrame blade;
    Vec3 seed_m{0.0, 0.0, 0.0};       ///< where the blade first touched, world frame, m
    std::int64_t triangle_hint = -1;  ///< body-local triangle of the seed, or -1
    double kerf_width_m = 0.0;        ///< blade thickness, m; 0: a uniplanar cut that never opens
};

/// The cut advanced: the swept region grew.
struct CutProgress {
    std::uint32_t cut_id = 0;
    BladeFrame blade;  ///< the blade's frame now (it may rotate about the normal)
    SweptRect swept;   ///< swept region in `blade`'s (u, v) frame
};

/// How a cut ended.
enum class CutEndKind : std::uint8_t {
    kCompleted,  ///< through: kerf fully open, severed pieces become bodies
    kWithdrawn,  ///< blade pulled back: the partial cut stays as it is
    kAborted,    ///< stopped by a fault: treated like kWithdrawn
};
std::string_view to_string(CutEndKind kind) noexcept;

struct CutEnd {
    std::uint32_t cut_id = 0;
    CutEndKind kind = CutEndKind::kCompleted;
};

/// A rigid pose: x_world = R(orientation) * x_body + position.
struct RigidPose {
    Vec3 position_m{0.0, 0.0, 0.0};
    std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};  ///< unit quaternion

    Vec3 to_body(const Vec3& world_point_m) const noexcept;        ///< R^T (p - t)
    Vec3 direction_to_body(const Vec3& world_dir) const noexcept;  ///< R^T d
    Vec3 to_world(const Vec3& body_point_m) const noexcept;        ///< R p + t
    /// The 4x4 world-from-body matrix, column-major (OpenGL order), translation in m.
    std::array<float, 16> matrix() const noexcept;
};

/// A body's pose changed.
struct BodyMoved {
    std::uint32_t body_id = 0;
    RigidPose pose;  ///< the new world-from-body pose
};

}  // namespace kerf::cut
