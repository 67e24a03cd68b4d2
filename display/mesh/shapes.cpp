#include "display/mesh/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "display/mesh/detail/revolve.hpp"
#include "display/mesh/indexed_mesh.hpp"

namespace kerf::mesh {
namespace {

constexpr double kPi = std::numbers::pi;

const detail::AxisFrame kZFrame{Point{0, 0, 0}, Point{0, 0, 1}, Point{1, 0, 0}, Point{0, 1, 0}};

TriMesh finish(const IndexedMesh& in) { return build_tri_mesh(in).mesh; }

// Grid coordinate k of `divisions` along one axis; the ends are exact so faces weld.
double grid(double lo, double hi, int k, int divisions) {
    if (k == 0) return lo;
    if (k == divisions) return hi;
    return lo + (hi - lo) * k / divisions;
}

// One box face: the axis it is normal to, on the min (sign -1) or max (sign +1) side.
void add_box_face(IndexedMesh& out, VertexWelder& welder, const Point& lo, const Point& hi,
                  int normal_axis, int sign, int d) {
    int u = (normal_axis + 1) % 3;  // u × v == +normal for this cyclic order
    int v = (normal_axis + 2) % 3;
    if (sign < 0) std::swap(u, v);
    auto corner = [&](int i, int j) {
        Point p;
        p[normal_axis] = sign > 0 ? hi[normal_axis] : lo[normal_axis];
        p[u] = grid(lo[u], hi[u], i, d);
        p[v] = grid(lo[v], hi[v], j, d);
        return welder.weld(p, out);
    };
    for (int i = 0; i < d; ++i) {
        for (int j = 0; j < d; ++j) {
            const std::uint32_t a = corner(i, j), b = corner(i + 1, j);
            const std::uint32_t c = corner(i + 1, j + 1), e = corner(i, j + 1);
            out.triangles.push_back({a, b, c});
            out.triangles.push_back({a, c, e});
        }
    }
}

// Annulus between two rings at the same axial position; `facing_back` = normal along -axis.
void add_rim(IndexedMesh& out, std::uint32_t outer, std::uint32_t inner, int segments,
             bool facing_back) {
    const auto n = static_cast<std::uint32_t>(segments);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % n;
        if (facing_back) {
            out.triangles.push_back({inner + i, outer + j, outer + i});
            out.triangles.push_back({inner + i, inner + j, outer + j});
        } else {
            out.triangles.push_back({inner + i, outer + i, outer + j});
            out.triangles.push_back({inner + i, outer + j, inner + j});
        }
    }
}

}  // namespace

TriMesh make_box(const Point& min_m, const Point& max_m, int divisions) {
    const int d = std::max(divisions, 1);
    IndexedMesh out;
    VertexWelder welder;
    for (int axis = 0; axis < 3; ++axis) {
        add_box_face(out, welder, min_m, max_m, axis, -1, d);
        add_box_face(out, welder, min_m, max_m, axis, +1, d);
    }
    return finish(out);
}

TriMesh make_uv_sphere(double radius_m, std::size_t target_triangles, const Point& centre_m) {
    // 2 m (n - 1) triangles for n latitude bands and m meridians, m close to 2n.
    const double t = static_cast<double>(std::max<std::size_t>(target_triangles, 24));
    const int bands = std::max(3, static_cast<int>(std::lround(std::sqrt(t / 4.0))));
    const int meridians = std::max(3, static_cast<int>(std::lround(t / (2.0 * (bands - 1)))));
    std::vector<detail::ProfileSample> profile;
    for (int k = 0; k <= bands; ++k) {
        const double phi = kPi * k / bands;
        const double r = (k == 0 || k == bands) ? 0.0 : radius_m * std::sin(phi);
        profile.push_back({-radius_m * std::cos(phi), r});
    }
    detail::AxisFrame frame = kZFrame;
    frame.origin = centre_m;
    IndexedMesh out;
    detail::add_closed_revolved(out, frame, profile, meridians, true, Material::kCortical);
    return finish(out);
}

TriMesh make_torus(double major_radius_m, double minor_radius_m, int major_segments,
                   int minor_segments) {
    IndexedMesh out;
    const auto m = static_cast<std::uint32_t>(major_segments);
    const auto n = static_cast<std::uint32_t>(minor_segments);
    for (std::uint32_t i = 0; i < m; ++i) {
        const double theta = 2.0 * kPi * i / m;
        for (std::uint32_t j = 0; j < n; ++j) {
            const double phi = 2.0 * kPi * j / n;
            const double rho = major_radius_m + minor_radius_m * std::cos(phi);
            out.positions_m.push_back(Point{rho * std::cos(theta), rho * std::sin(theta),
                                            minor_radius_m * std::sin(phi)});
        }
    }
    auto at = [&](std::uint32_t i, std::uint32_t j) { return (i % m) * n + (j % n); };
    for (std::uint32_t i = 0; i < m; ++i) {
        for (std::uint32_t j = 0; j < n; ++j) {
            out.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            out.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return finish(out);
}

TriMesh make_hollow_tube(double length_m, double outer_radius_m, double inner_radius_m,
                         int segments, int rings) {
    IndexedMesh out;
    std::vector<std::uint32_t> outer, inner;
    for (int k = 0; k <= rings; ++k) {
        const double z = k == rings ? length_m : length_m * k / rings;
        outer.push_back(
            detail::add_ring(out, kZFrame, {z, outer_radius_m}, segments, Material::kCortical));
        inner.push_back(
            detail::add_ring(out, kZFrame, {z, inner_radius_m}, segments, Material::kCancellous));
    }
    for (std::size_t k = 0; k + 1 < outer.size(); ++k) {
        detail::join_rings(out, outer[k], false, outer[k + 1], false, segments, true);
        detail::join_rings(out, inner[k], false, inner[k + 1], false, segments, false);
    }
    add_rim(out, outer.front(), inner.front(), segments, true);
    add_rim(out, outer.back(), inner.back(), segments, false);
    return finish(out);
}

double inscribed_polygon_area(double radius_m, int segments) noexcept {
    return 0.5 * segments * radius_m * radius_m * std::sin(2.0 * kPi / segments);
}

}  // namespace kerf::mesh
