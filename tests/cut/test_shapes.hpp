// What the cut tests build beside the mesh module's shapes (display/mesh/shapes.hpp: make_box,
// make_uv_sphere, make_torus, make_hollow_tube, used wherever they fit): a UV sphere with an exact
// number of vertex rings (make_uv_sphere takes a triangle count), for planes through a ring, and
// append() for several components in one mesh. Outward-oriented, metres.
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
/// Vertex rings lie in planes z = center.z + radius * cos(pi * i / rings). Texture coordinates
/// are (x, y), so interpolation along an edge can be checked.
inline TriMesh uv_sphere_by_rings(double radius_m, int rings, int segments,
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
