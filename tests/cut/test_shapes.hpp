// Small closed test shapes built in code for the cut tests (outward-oriented, metres). The mesh
// module's generators (display/mesh/shapes.hpp) are used where they fit; these stay for exact
// control over vertex rings (planes through rings, along edges).
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::testing {

using kerf::mesh::TriMesh;
using kerf::mesh::VertexHandle;

namespace detail {

inline VertexHandle add_vertex(TriMesh& m, double x, double y, double z) {
    auto v = m.add_vertex(TriMesh::Point(x, y, z));
    m.set_texcoord2D(v, TriMesh::TexCoord2D(static_cast<float>(x), static_cast<float>(y)));
    m.set_color(v, TriMesh::Color(0.9f, 0.85f, 0.8f));
    return v;
}

inline void quad(TriMesh& m, VertexHandle a, VertexHandle b, VertexHandle c, VertexHandle d) {
    m.add_face(a, b, c);
    m.add_face(a, c, d);
}

// Normals from the geometry (vertex normals = normalised position offsets are not general).
inline void finish(TriMesh& m) {
    m.update_face_normals();
    m.update_vertex_normals();
}

}  // namespace detail

/// UV sphere of `radius_m` at `center`: `rings` latitude bands, `segments` longitudes, two poles.
/// Vertex rings lie in planes z = center.z + radius * cos(pi * i / rings).
inline TriMesh uv_sphere(double radius_m, int rings, int segments,
                         TriMesh::Point center = TriMesh::Point(0, 0, 0)) {
    TriMesh m;
    const double pi = std::numbers::pi;
    auto top = detail::add_vertex(m, center[0], center[1], center[2] + radius_m);
    std::vector<VertexHandle> grid;
    for (int i = 1; i < rings; ++i) {
        const double th = pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double ph = 2 * pi * j / segments;
            grid.push_back(detail::add_vertex(m, center[0] + radius_m * std::sin(th) * std::cos(ph),
                                              center[1] + radius_m * std::sin(th) * std::sin(ph),
                                              center[2] + radius_m * std::cos(th)));
        }
    }
    auto bottom = detail::add_vertex(m, center[0], center[1], center[2] - radius_m);
    auto at = [&](int i, int j) { return grid[(i - 1) * segments + (j % segments)]; };
    for (int j = 0; j < segments; ++j) m.add_face(top, at(1, j), at(1, j + 1));
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j)
            detail::quad(m, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    for (int j = 0; j < segments; ++j) m.add_face(bottom, at(rings - 1, j + 1), at(rings - 1, j));
    detail::finish(m);
    return m;
}

/// Torus around the z axis: major radius `big_r_m`, tube radius `small_r_m`.
inline TriMesh torus(double big_r_m, double small_r_m, int major_segments, int minor_segments) {
    TriMesh m;
    const double pi = std::numbers::pi;
    std::vector<VertexHandle> g;
    for (int i = 0; i < major_segments; ++i) {
        const double a = 2 * pi * i / major_segments;
        for (int j = 0; j < minor_segments; ++j) {
            const double b = 2 * pi * j / minor_segments;
            const double r = big_r_m + small_r_m * std::cos(b);
            g.push_back(
                detail::add_vertex(m, r * std::cos(a), r * std::sin(a), small_r_m * std::sin(b)));
        }
    }
    auto at = [&](int i, int j) {
        return g[(i % major_segments) * minor_segments + (j % minor_segments)];
    };
    for (int i = 0; i < major_segments; ++i)
        for (int j = 0; j < minor_segments; ++j)
            detail::quad(m, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    detail::finish(m);
    return m;
}

/// Hollow tube along z from 0 to `length_m`: outer radius, inner radius (the "canal" is a
/// separate surface component), closed by two annular ends. `rings` bands along z.
inline TriMesh hollow_tube(double outer_r_m, double inner_r_m, double length_m, int rings,
                           int segments) {
    TriMesh m;
    const double pi = std::numbers::pi;
    std::vector<VertexHandle> outer, inner;
    for (int i = 0; i <= rings; ++i) {
        const double z = length_m * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double a = 2 * pi * j / segments;
            outer.push_back(
                detail::add_vertex(m, outer_r_m * std::cos(a), outer_r_m * std::sin(a), z));
        }
    }
    for (int i = 0; i <= rings; ++i) {
        const double z = length_m * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double a = 2 * pi * (j + 0.5) / segments;
            inner.push_back(
                detail::add_vertex(m, inner_r_m * std::cos(a), inner_r_m * std::sin(a), z));
        }
    }
    auto o = [&](int i, int j) { return outer[i * segments + (j % segments)]; };
    auto n = [&](int i, int j) { return inner[i * segments + (j % segments)]; };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            detail::quad(m, o(i, j), o(i, j + 1), o(i + 1, j + 1), o(i + 1, j));  // outward
            detail::quad(m, n(i, j), n(i + 1, j), n(i + 1, j + 1), n(i, j + 1));  // inward
        }
    // Ends: bottom (z = 0) faces -z, top faces +z. The ends join the two surfaces, so the tube
    // is one component; the canal loop is still not reachable through crossing triangles.
    for (int j = 0; j < segments; ++j) {
        m.add_face(o(0, j), n(0, j), o(0, j + 1));
        m.add_face(n(0, j), n(0, j + 1), o(0, j + 1));
        m.add_face(o(rings, j), o(rings, j + 1), n(rings, j));
        m.add_face(n(rings, j), o(rings, j + 1), n(rings, j + 1));
    }
    detail::finish(m);
    return m;
}

/// Axis-aligned box from `lo` to `hi`, each face an n x n grid of quads (two triangles each).
inline TriMesh box(TriMesh::Point lo, TriMesh::Point hi, int n) {
    TriMesh m;
    // Vertices on a (n+1)^3 lattice, only the surface ones created.
    std::vector<VertexHandle> lat((n + 1) * (n + 1) * (n + 1));
    auto id = [&](int i, int j, int k) { return (i * (n + 1) + j) * (n + 1) + k; };
    auto vtx = [&](int i, int j, int k) {
        auto& v = lat[id(i, j, k)];
        if (!v.is_valid())
            v = detail::add_vertex(m, lo[0] + (hi[0] - lo[0]) * i / n,
                                   lo[1] + (hi[1] - lo[1]) * j / n,
                                   lo[2] + (hi[2] - lo[2]) * k / n);
        return v;
    };
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            detail::quad(m, vtx(0, a, b), vtx(0, a, b + 1), vtx(0, a + 1, b + 1),
                         vtx(0, a + 1, b));  // -x
            detail::quad(m, vtx(n, a, b), vtx(n, a + 1, b), vtx(n, a + 1, b + 1),
                         vtx(n, a, b + 1));  // +x
            detail::quad(m, vtx(a, 0, b), vtx(a + 1, 0, b), vtx(a + 1, 0, b + 1),
                         vtx(a, 0, b + 1));  // -y
            detail::quad(m, vtx(a, n, b), vtx(a, n, b + 1), vtx(a + 1, n, b + 1),
                         vtx(a + 1, n, b));  // +y
            detail::quad(m, vtx(a, b, 0), vtx(a, b + 1, 0), vtx(a + 1, b + 1, 0),
                         vtx(a + 1, b, 0));  // -z
            detail::quad(m, vtx(a, b, n), vtx(a + 1, b, n), vtx(a + 1, b + 1, n),
                         vtx(a, b + 1, n));  // +z
        }
    detail::finish(m);
    return m;
}

/// Appends `b` to `a` (separate components), e.g. several "toes" in one mesh.
inline void append(TriMesh& a, const TriMesh& b) {
    std::vector<VertexHandle> map(b.n_vertices());
    for (auto v : b.vertices()) {
        map[v.idx()] = a.add_vertex(b.point(v));
        a.set_normal(map[v.idx()], b.normal(v));
        a.set_texcoord2D(map[v.idx()], b.texcoord2D(v));
        a.set_color(map[v.idx()], b.color(v));
    }
    for (auto f : b.faces()) {
        std::vector<VertexHandle> vs;
        for (auto v : b.fv_range(f)) vs.push_back(map[v.idx()]);
        auto nf = a.add_face(vs);
        a.set_normal(nf, b.normal(f));
    }
}

}  // namespace kerf::cut::testing
