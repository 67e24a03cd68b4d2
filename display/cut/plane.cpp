#include "display/cut/plane.hpp"

#include <cmath>

namespace kerf::cut {

namespace {

bool finite(const Vec3& a) {
    return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}

// u: the cross product of the normal with the coordinate axis least aligned with it.
Vec3 first_axis(const Vec3& n) {
    const double ax = std::abs(n[0]), ay = std::abs(n[1]), az = std::abs(n[2]);
    Vec3 axis(0.0, 0.0, 1.0);
    if (ax <= ay && ax <= az)
        axis = Vec3(1.0, 0.0, 0.0);
    else if (ay <= az)
        axis = Vec3(0.0, 1.0, 0.0);
    Vec3 u = OpenMesh::cross(axis, n);
    return u / u.norm();
}

}  // namespace

Plane::Plane() noexcept
    : point_(0.0, 0.0, 0.0),
      normal_(0.0, 0.0, 1.0),
      u_(first_axis(normal_)),
      v_(OpenMesh::cross(normal_, u_)) {}

Result<Plane, CutStatus> Plane::make(const Vec3& point_m, const Vec3& normal) noexcept {
    if (!finite(point_m) || !finite(normal)) return Err{CutStatus::kInvalidPlane};
    const double len = normal.norm();
    if (!(len > 1e-12) || !std::isfinite(len)) return Err{CutStatus::kInvalidPlane};
    Plane p;
    p.point_ = point_m;
    p.normal_ = normal / len;
    p.u_ = first_axis(p.normal_);
    p.v_ = OpenMesh::cross(p.normal_, p.u_);
    return p;
}

Plane Plane::offset(double distance_m) const noexcept {
    Plane p = *this;
    p.point_ = point_ + normal_ * distance_m;
    return p;
}

}  // namespace kerf::cut
