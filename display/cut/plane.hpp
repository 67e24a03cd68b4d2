// kerf::cut::Plane — an oriented cutting plane in metres, with the in-plane 2-D frame that caps,
// loops and swept regions are expressed in.
//
//   auto plane = Plane::make({0.0, 0.0, 0.1}, {0.0, 0.0, 1.0});   // z = 100 mm, normal +z
//   if (!plane) return plane.error();                              // CutStatus::kInvalidPlane
//   double d = plane->signed_distance(p);                          // > 0: the positive side
//
// The frame (u, v, normal) is right-handed (u x v = normal) and depends only on the normal, so the
// same plane always gives the same 2-D coordinates.
#pragma once

#include <OpenMesh/Core/Geometry/VectorT.hh>

#include "config/base/result.hpp"
#include "display/cut/cut_result.hpp"

namespace kerf::cut {

using Vec3 = OpenMesh::Vec3d;
using Vec2 = OpenMesh::Vec2d;

/// Vertices closer to a plane than this fraction of the mesh scale (its bounding-box diagonal)
/// are ON the plane: reused as cut vertices, never interpolated at t ~ 0 or 1.
inline constexpr double kRelativeTolerance = 1e-6;

class Plane {
public:
    /// The plane z = 0 with normal +z (a placeholder value; use make()).
    Plane() noexcept;

    /// A plane through `point_m` with normal direction `normal` (normalised here).
    /// Fails with kInvalidPlane when a value is non-finite or the normal is (nearly) zero.
    static Result<Plane, CutStatus> make(const Vec3& point_m, const Vec3& normal) noexcept;

    /// Absolute on-plane tolerance for a mesh of size `scale_m` (kRelativeTolerance * scale_m).
    static double tolerance_for_scale(double scale_m) noexcept {
        return kRelativeTolerance * scale_m;
    }

    const Vec3& point() const noexcept { return point_; }    ///< a point on the plane, m
    const Vec3& normal() const noexcept { return normal_; }  ///< unit normal (positive side)
    const Vec3& u() const noexcept { return u_; }            ///< first in-plane unit axis
    const Vec3& v() const noexcept { return v_; }            ///< second in-plane unit axis

    /// Signed distance of `p` from the plane, m (positive on the normal's side): dot(p - point,
    /// normal), written out on the components (OpenMesh's vector loops are not unrolled at -O2;
    /// the same operations in the same order, so the same value).
    double signed_distance(const Vec3& p) const noexcept {
        return (p[0] - point_[0]) * normal_[0] + (p[1] - point_[1]) * normal_[1] +
               (p[2] - point_[2]) * normal_[2];
    }

    /// -1, 0 or +1: the side of `p`, 0 when within `tolerance_m` of the plane.
    int side(const Vec3& p, double tolerance_m) const noexcept {
        const double d = signed_distance(p);
        return d > tolerance_m ? 1 : (d < -tolerance_m ? -1 : 0);
    }

    /// Coordinates of `p` projected into the frame (u, v), m.
    Vec2 to_2d(const Vec3& p) const noexcept {
        // dot(p - point, u), dot(p - point, v), written out (see signed_distance).
        const double r0 = p[0] - point_[0], r1 = p[1] - point_[1], r2 = p[2] - point_[2];
        return Vec2(r0 * u_[0] + r1 * u_[1] + r2 * u_[2], r0 * v_[0] + r1 * v_[1] + r2 * v_[2]);
    }

    /// The 3-D point of frame coordinates `q` on the plane.
    Vec3 to_3d(const Vec2& q) const noexcept { return point_ + u_ * q[0] + v_ * q[1]; }

    /// The parallel plane moved by `distance_m` along the normal (same frame).
    Plane offset(double distance_m) const noexcept;

private:
    Vec3 point_;
    Vec3 normal_;
    Vec3 u_;
    Vec3 v_;
};

}  // namespace kerf::cut
