// Exact per-triangle primitives the collision structure is built from (and tests compare with):
// closest point on a triangle, segment-triangle crossing, point-box distance. Double precision,
// inline, noexcept.
#pragma once

#include <algorithm>
#include <cmath>

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

/// A segment's crossing of one triangle (segment_crossing).
struct TriangleCrossing {
    double t = -1;  ///< at o + t d, t in [0, 1); -1: no crossing
    int sign = 0;   ///< +1 leaving (along the outward normal), -1 entering
};

/// Whether segment o + t d, t in [0, 1), crosses triangle (a, b, c), decided watertight for
/// counting: in the plane across the segment (Woop, Benthin & Wald 2013's shear), each edge's
/// side test is antisymmetric bit for bit (the neighbour sharing the edge gets the negated value),
/// and a value of exactly 0 is decided as if the segment were moved by an infinitesimal offset
/// (symbolic perturbation). A segment through a shared edge or vertex therefore crosses exactly
/// one triangle there, or, where it grazes, none or an entering and a leaving one: over a closed
/// outward mesh whose shared corners are bit-identical, the crossings' signs sum to the winding
/// number at o minus that at o + d. Triangles seen edge-on never cross.
inline TriangleCrossing segment_crossing(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b,
                                         const Vec3& c) noexcept {
    int kz = std::abs(d.x) > std::abs(d.y) ? 0 : 1;
    if (std::abs(d.z) > std::abs(d[kz])) kz = 2;
    if (d[kz] == 0) return {};
    const int kx = (kz + 1) % 3, ky = (kz + 2) % 3;
    const double sx = d[kx] / d[kz], sy = d[ky] / d[kz];
    struct P2 {
        double x, y;
    };
    const auto project = [&](const Vec3& p) {
        const Vec3 q = p - o;
        return P2{q[kx] - sx * q[kz], q[ky] - sy * q[kz]};
    };
    // The side of the (perturbed) segment's trace from edge p -> q: +1, -1, or 0 (p == q).
    const auto side = [](const P2& p, const P2& q) {
        const double e = p.x * q.y - p.y * q.x;
        if (e != 0) return e > 0 ? 1 : -1;
        if (p.y != q.y) return p.y > q.y ? 1 : -1;
        if (p.x != q.x) return q.x > p.x ? 1 : -1;
        return 0;
    };
    const P2 pa = project(a), pb = project(b), pc = project(c);
    const int s = side(pa, pb);
    if (s == 0 || side(pb, pc) != s || side(pc, pa) != s) return {};
    const Vec3 n = cross(b - a, c - a);
    const double dn = dot(d, n);
    if (dn == 0) return {};
    const double t = dot(a - o, n) / dn;
    if (!(t >= 0 && t < 1)) return {};
    return {t, dn > 0 ? 1 : -1};
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
