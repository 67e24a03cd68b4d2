// Library-internal: Vec3 and Vec2 arithmetic written out on the components, for the cut's hot
// paths. Each function performs the same floating-point operations in the same order as the
// OpenMesh VectorT expression named beside it, so every result is bit-identical; OpenMesh builds
// those from std::transform / std::accumulate loops that gcc -O2 leaves as loops through memory
// (a signed distance cost about 40 instructions instead of 10).
#pragma once

#include <algorithm>
#include <cmath>

#include "display/cut/plane.hpp"

namespace kerf::cut::detail {

/// a - b
inline Vec3 sub(const Vec3& a, const Vec3& b) noexcept {
    return Vec3(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/// OpenMesh::dot(a, b)
inline double dot(const Vec3& a, const Vec3& b) noexcept {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// OpenMesh::cross(a, b)
inline Vec3 cross(const Vec3& a, const Vec3& b) noexcept {
    return Vec3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

/// a.sqrnorm()
inline double sqrnorm(const Vec3& a) noexcept { return a[0] * a[0] + a[1] * a[1] + a[2] * a[2]; }

/// (a - b).sqrnorm()
inline double sqrdist(const Vec3& a, const Vec3& b) noexcept { return sqrnorm(sub(a, b)); }

/// OpenMesh::cross(b - a, c - a).sqrnorm(): twice the area of triangle a, b, c, squared.
inline double twice_area2(const Vec3& a, const Vec3& b, const Vec3& c) noexcept {
    return sqrnorm(cross(sub(b, a), sub(c, a)));
}

/// a.minimize(b)
inline void minimize(Vec3& a, const Vec3& b) noexcept {
    a[0] = std::min(a[0], b[0]), a[1] = std::min(a[1], b[1]), a[2] = std::min(a[2], b[2]);
}

/// a.maximize(b)
inline void maximize(Vec3& a, const Vec3& b) noexcept {
    a[0] = std::max(a[0], b[0]), a[1] = std::max(a[1], b[1]), a[2] = std::max(a[2], b[2]);
}

/// a + (b - a) * t
inline Vec3 lerp(const Vec3& a, const Vec3& b, double t) noexcept {
    return Vec3(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t);
}

/// a - b
inline Vec2 sub(const Vec2& a, const Vec2& b) noexcept { return Vec2(a[0] - b[0], a[1] - b[1]); }

/// OpenMesh::dot(a, b)
inline double dot(const Vec2& a, const Vec2& b) noexcept { return a[0] * b[0] + a[1] * b[1]; }

/// a.sqrnorm()
inline double sqrnorm(const Vec2& a) noexcept { return a[0] * a[0] + a[1] * a[1]; }

/// In-circle test of d against the circle through a, b, c (counter-clockwise): positive when d
/// is inside. The cap code reads its magnitude against sqrnorm(a - d) * sqrnorm(b - d).
inline double in_circle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) noexcept {
    const double adx = a[0] - d[0], ady = a[1] - d[1];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1];
    return (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) -
           (bdx * bdx + bdy * bdy) * (adx * cdy - cdx * ady) +
           (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
}

}  // namespace kerf::cut::detail
