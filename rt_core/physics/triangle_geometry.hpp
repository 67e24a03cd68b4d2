// Exact per-triangle primitives the collision structure is built from (and tests compare with):
// closest point on a triangle, segment-triangle crossing, point-box distance. Double precision,
// inline, noexcept.
#pragma once

#include <algorithm>

#include "rt_core/physics/vec3.hpp"

namespace kerf::physics {

/// Nearest point to `p` on triangle (a, b, c) (Ericson, Real-Time Collision Detection §5.1.5).
inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                      const Vec3& c) noexcept {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double den = d1 - d3;
        return den > 0 ? a + ab * (d1 / den) : a;
    }
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double den = d2 - d6;
        return den > 0 ? a + ac * (d2 / den) : a;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double den = (d4 - d3) + (d5 - d6);
        return den > 0 ? b + (c - b) * ((d4 - d3) / den) : b;
    }
    const double sum = va + vb + vc;
    if (!(sum > 0)) return a;  // degenerate triangle: a vertex is as good as any point
    const double v = vb / sum, w = vc / sum;
    return a + ab * v + ac * w;
}

/// Crossing parameter t in [0, t_max) of segment o + t d with triangle (a, b, c), or -1.
/// Edges and vertices count as inside (a hair of overlap), so a segment cannot slip between two
/// triangles sharing an edge. `front_only`: only crossings against the outward normal count.
inline double segment_triangle_t(const Vec3& o, const Vec3& d, double t_max, const Vec3& a,
                                 const Vec3& b, const Vec3& c, bool front_only) noexcept {
    constexpr double kEdgeSlack = 1e-9;
    const Vec3 e1 = b - a, e2 = c - a;
    const Vec3 n = cross(e1, e2);
    const double dn = dot(d, n);
    if (dn == 0 || (front_only && dn > 0)) return -1;
    const Vec3 pvec = cross(d, e2);
    const double det = dot(e1, pvec);
    if (det == 0) return -1;
    const double inv = 1.0 / det;
    const Vec3 tvec = o - a;
    const double u = dot(tvec, pvec) * inv;
    if (u < -kEdgeSlack || u > 1 + kEdgeSlack) return -1;
    const Vec3 qvec = cross(tvec, e1);
    const double v = dot(d, qvec) * inv;
    if (v < -kEdgeSlack || u + v > 1 + kEdgeSlack) return -1;
    const double t = dot(e2, qvec) * inv;
    return (t >= 0 && t < t_max) ? t : -1;
}

/// Squared distance from `p` to the box [lo, hi].
inline double box_distance2(const Vec3& p, const float lo[3], const float hi[3]) noexcept {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double v = p[i];
        const double e = v < lo[i] ? lo[i] - v : (v > hi[i] ? v - hi[i] : 0.0);
        d2 += e * e;
    }
    return d2;
}

/// Whether segment o + t d, t in [0, t_max], meets box [lo, hi] (slab test; inv_d = 1/d).
inline bool segment_hits_box(const Vec3& o, const Vec3& inv_d, double t_max, const float lo[3],
                             const float hi[3]) noexcept {
    double t0 = 0, t1 = t_max;
    for (int i = 0; i < 3; ++i) {
        double a = (lo[i] - o[i]) * inv_d[i], b = (hi[i] - o[i]) * inv_d[i];
        if (a > b) std::swap(a, b);
        if (a != a) a = -1e300;  // 0 * inf: the segment lies in the slab's boundary plane
        if (b != b) b = 1e300;
        t0 = std::max(t0, a), t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

}  // namespace kerf::physics
