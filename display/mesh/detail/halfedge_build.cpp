// HalfedgeBuilder::add_face and the normals follow OpenMesh 9.0's PolyConnectivity::add_face and
// update_normals step for step, so this file is a derivative of OpenMesh, whose licence (BSD
// 3-clause) asks that its notice be kept:
//
//   OpenMesh. Copyright (c) 2001-2022, RWTH-Aachen University, Department of Computer Graphics and
//   Multimedia. All rights reserved. www.openmesh.org
//
//   Redistribution and use in source and binary forms, with or without modification, are permitted
//   provided that the following conditions are met:
//   1. Redistributions of source code must retain the above copyright notice, this list of
//      conditions and the following disclaimer.
//   2. Redistributions in binary form must reproduce the above copyright notice, this list of
//      conditions and the following disclaimer in the documentation and/or other materials
//      provided with the distribution.
//   3. Neither the name of the copyright holder nor the names of its contributors may be used to
//      endorse or promote products derived from this software without specific prior written
//      permission.
//
//   THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS "AS IS" AND ANY EXPRESS OR
//   IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE IMPLIED WARRANTIES OF MERCHANTABILITY
//   AND FITNESS FOR A PARTICULAR PURPOSE ARE DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDER OR
//   CONTRIBUTORS BE LIABLE FOR ANY DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR
//   CONSEQUENTIAL DAMAGES (INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR
//   SERVICES; LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER CAUSED AND ON ANY
//   THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY, OR TORT (INCLUDING NEGLIGENCE OR
//   OTHERWISE) ARISING IN ANY WAY OUT OF THE USE OF THIS SOFTWARE, EVEN IF ADVISED OF THE
//   POSSIBILITY OF SUCH DAMAGE.
#include "display/mesh/detail/halfedge_build.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>

namespace kerf::mesh::detail {

void HalfedgeBuilder::make_room(std::size_t vertices, std::size_t edges, std::size_t faces) {
    // Steps of a few hundred kB: each step's elements are constructed just before add_face
    // writes them, so they are still in cache (a step is not a reallocation: build_tri_mesh_into
    // reserves the mesh's arrays first). The mesh's sizes are kept here: n_vertices() and the
    // like are virtual calls.
    if (vertices <= room_.vertices && edges <= room_.edges && faces <= room_.faces) return;
    constexpr std::size_t kStep = std::size_t{1} << 14;
    const auto grown = [](std::size_t have, std::size_t need) {
        return need <= have ? have : std::max(need, have + kStep);
    };
    room_ = {grown(room_.vertices, vertices), grown(room_.edges, edges), grown(room_.faces, faces)};
    m_.resize(room_.vertices, room_.edges, room_.faces);
}

void HalfedgeBuilder::add_vertices(std::size_t count) {
    // Exactly this many: the vertices the caller numbers are not spare.
    vertices_ += count;
    if (vertices_ > room_.vertices) {
        room_.vertices = vertices_;
        m_.resize(room_.vertices, room_.edges, room_.faces);
    }
}

std::int32_t HalfedgeBuilder::add_vertex() {
    make_room(vertices_ + 1, edges_, faces_);
    return static_cast<std::int32_t>(vertices_++);
}

void HalfedgeBuilder::finish() { m_.resize(vertices_, edges_, faces_); }

// OpenMesh: is_boundary(VertexHandle): no outgoing half-edge, or one without a face.
bool HalfedgeBuilder::is_boundary_vertex(std::int32_t v) const {
    const std::int32_t h = out(v);
    return h == kNone || face(h) == kNone;
}

// OpenMesh: find_halfedge() walks the outgoing half-edges clockwise (next of the opposite) from
// the vertex's half-edge until it is back at the start or meets an unset link.
std::int32_t HalfedgeBuilder::find_halfedge(std::int32_t from, std::int32_t to_vertex) const {
    const std::int32_t start = out(from);
    std::int32_t h = start;
    while (h != kNone) {
        if (to(h) == to_vertex) return h;
        h = next(h ^ 1);
        if (h == start) break;
    }
    return kNone;
}

// OpenMesh: new_edge(start, end) appends an edge whose first half-edge points to `end` (a new
// element's links are all unset).
std::int32_t HalfedgeBuilder::new_edge(std::int32_t from, std::int32_t to_vertex) {
    make_room(vertices_, edges_ + 1, faces_);
    const auto h = static_cast<std::int32_t>(2 * edges_++);
    m_.set_vertex_handle(HalfedgeHandle(h), VertexHandle(to_vertex));
    m_.set_vertex_handle(HalfedgeHandle(h + 1), VertexHandle(from));
    return h;
}

// OpenMesh: set_next_halfedge_handle() also sets the previous link of `next`.
void HalfedgeBuilder::set_next(std::int32_t h, std::int32_t next_h) {
    m_.set_next_halfedge_handle(HalfedgeHandle(h), HalfedgeHandle(next_h));
}

// OpenMesh: the first boundary half-edge clockwise from the vertex's half-edge becomes it.
void HalfedgeBuilder::adjust_outgoing_halfedge(std::int32_t v) {
    const std::int32_t start = out(v);
    std::int32_t h = start;
    while (h != kNone) {
        if (is_boundary_halfedge(h)) {
            set_out(v, h);
            return;
        }
        h = next(h ^ 1);
        if (h == start) return;
    }
}

// PolyConnectivity::add_face(const VertexHandle*, size_t) for n = 3, statement for statement.
std::int32_t HalfedgeBuilder::add_face(std::int32_t a, std::int32_t b, std::int32_t c) {
    constexpr std::size_t n = 3;
    const std::array<std::int32_t, n> v{a, b, c};
    struct EdgeData {
        std::int32_t halfedge = kNone;
        bool is_new = false;
        bool needs_adjust = false;
    };
    std::array<EdgeData, n> edge{};
    std::array<std::pair<std::int32_t, std::int32_t>, 6 * n> next_cache{};
    std::size_t cached = 0;

    // Test for topological errors.
    for (std::size_t i = 0, ii = 1; i < n; ++i, ++ii, ii %= n) {
        if (!is_boundary_vertex(v[i])) return kNone;  // complex vertex
        edge[i].halfedge = find_halfedge(v[i], v[ii]);
        edge[i].is_new = edge[i].halfedge == kNone;
        edge[i].needs_adjust = false;
        if (!edge[i].is_new && !is_boundary_halfedge(edge[i].halfedge)) return kNone;  // edge
    }

    // Re-link patches if necessary.
    for (std::size_t i = 0, ii = 1; i < n; ++i, ++ii, ii %= n) {
        if (edge[i].is_new || edge[ii].is_new) continue;
        const std::int32_t inner_prev = edge[i].halfedge;
        const std::int32_t inner_next = edge[ii].halfedge;
        if (next(inner_prev) == inner_next) continue;
        // Search a free gap, between boundary_prev and boundary_next.
        const std::int32_t outer_prev = inner_next ^ 1;
        std::int32_t boundary_prev = outer_prev;
        do {
            boundary_prev = next(boundary_prev) ^ 1;
        } while (!is_boundary_halfedge(boundary_prev));
        const std::int32_t boundary_next = next(boundary_prev);
        if (boundary_prev == inner_prev) return kNone;  // patch re-linking failed
        const std::int32_t patch_start = next(inner_prev);
        const std::int32_t patch_end = prev(inner_next);
        next_cache[cached++] = {boundary_prev, patch_start};
        next_cache[cached++] = {patch_end, boundary_next};
        next_cache[cached++] = {inner_prev, inner_next};
    }

    // Create missing edges.
    for (std::size_t i = 0, ii = 1; i < n; ++i, ++ii, ii %= n) {
        if (edge[i].is_new) edge[i].halfedge = new_edge(v[i], v[ii]);
    }

    // Create the face.
    make_room(vertices_, edges_, faces_ + 1);
    const auto f = static_cast<std::int32_t>(faces_++);
    m_.set_halfedge_handle(FaceHandle(f), HalfedgeHandle(edge[n - 1].halfedge));

    // Set up the half-edges.
    for (std::size_t i = 0, ii = 1; i < n; ++i, ++ii, ii %= n) {
        const std::int32_t vh = v[ii];
        const std::int32_t inner_prev = edge[i].halfedge;
        const std::int32_t inner_next = edge[ii].halfedge;
        const int id = (edge[i].is_new ? 1 : 0) | (edge[ii].is_new ? 2 : 0);
        const std::int32_t vh_out = out(vh);
        if (id != 0) {
            const std::int32_t outer_prev = inner_next ^ 1;
            const std::int32_t outer_next = inner_prev ^ 1;
            switch (id) {
                case 1: {  // prev is new, next is old
                    const std::int32_t boundary_prev = prev(inner_next);
                    next_cache[cached++] = {boundary_prev, outer_next};
                    set_out(vh, outer_next);
                    break;
                }
                case 2: {  // next is new, prev is old
                    const std::int32_t boundary_next = next(inner_prev);
                    next_cache[cached++] = {outer_prev, boundary_next};
                    set_out(vh, boundary_next);
                    break;
                }
                default: {  // both are new
                    if (vh_out == kNone) {
                        set_out(vh, outer_next);
                        next_cache[cached++] = {outer_prev, outer_next};
                    } else {
                        const std::int32_t boundary_next = vh_out;
                        const std::int32_t boundary_prev = prev(boundary_next);
                        next_cache[cached++] = {boundary_prev, outer_next};
                        next_cache[cached++] = {outer_prev, boundary_next};
                    }
                    break;
                }
            }
            next_cache[cached++] = {inner_prev, inner_next};  // inner link
        } else {
            edge[ii].needs_adjust = vh_out == inner_next;
        }
        m_.set_face_handle(HalfedgeHandle(edge[i].halfedge), FaceHandle(f));
    }

    // Process the next-half-edge cache, then adjust the vertices' half-edges.
    for (std::size_t i = 0; i < cached; ++i) set_next(next_cache[i].first, next_cache[i].second);
    for (std::size_t i = 0; i < n; ++i) {
        if (edge[i].needs_adjust) adjust_outgoing_halfedge(v[i]);
    }
    return f;
}

void HalfedgeBuilder::write_normals() const {
    // TriMeshT::calc_face_normal(f): the corners from the face's half-edge on, through
    // PolyMeshT's three-point form (which TriMeshT hides).
    const TriMesh::PolyMesh& poly = m_;
    for (std::size_t f = 0; f < faces_; ++f) {
        const FaceHandle fh(static_cast<int>(f));
        const HalfedgeHandle h0 = m_.halfedge_handle(fh);
        const HalfedgeHandle h1 = m_.next_halfedge_handle(h0);
        const HalfedgeHandle h2 = m_.next_halfedge_handle(h1);
        m_.set_normal(fh, poly.calc_face_normal(m_.point(m_.to_vertex_handle(h0)),
                                                m_.point(m_.to_vertex_handle(h1)),
                                                m_.point(m_.to_vertex_handle(h2))));
    }
    // PolyMeshT::calc_vertex_normal(v): the faces around v summed from zero, clockwise from its
    // half-edge (as ConstVertexFaceIter visits them), then scaled to unit length unless zero.
    for (std::size_t v = 0; v < vertices_; ++v) {
        TriMesh::Normal n(0.0, 0.0, 0.0);
        const std::int32_t start = out(static_cast<std::int32_t>(v));
        for (std::int32_t h = start; h != kNone;) {
            const std::int32_t f = face(h);
            if (f != kNone) n += m_.normal(FaceHandle(f));
            h = next(h ^ 1);
            if (h == start) break;
        }
        const double length = OpenMesh::norm(n);
        if (length != 0.0) n *= (1.0 / length);
        m_.set_normal(VertexHandle(static_cast<int>(v)), n);
    }
}

}  // namespace kerf::mesh::detail
