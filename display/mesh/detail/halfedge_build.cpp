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

#include <array>
#include <cstddef>
#include <utility>

namespace kerf::mesh::detail {

void HalfedgeBuilder::reserve(std::size_t vertices, std::size_t edges, std::size_t faces) {
    vertex_out_.reserve(vertices);
    halfedges_.reserve(2 * edges);
    face_halfedge_.reserve(faces);
}

std::int32_t HalfedgeBuilder::add_vertex() {
    vertex_out_.push_back(kNone);
    return static_cast<std::int32_t>(vertex_out_.size() - 1);
}

// OpenMesh: is_boundary(VertexHandle): no outgoing half-edge, or one without a face.
bool HalfedgeBuilder::is_boundary_vertex(std::int32_t v) const {
    const std::int32_t h = vertex_out_[static_cast<std::size_t>(v)];
    return h == kNone || halfedges_[static_cast<std::size_t>(h)].face == kNone;
}

// OpenMesh: find_halfedge() walks the outgoing half-edges clockwise (next of the opposite) from
// the vertex's half-edge until it is back at the start or meets an unset link.
std::int32_t HalfedgeBuilder::find_halfedge(std::int32_t from, std::int32_t to) const {
    const std::int32_t start = vertex_out_[static_cast<std::size_t>(from)];
    std::int32_t h = start;
    while (h != kNone) {
        if (halfedges_[static_cast<std::size_t>(h)].to == to) return h;
        h = halfedges_[static_cast<std::size_t>(h ^ 1)].next;
        if (h == start) break;
    }
    return kNone;
}

// OpenMesh: new_edge(start, end) appends an edge whose first half-edge points to `end`.
std::int32_t HalfedgeBuilder::new_edge(std::int32_t from, std::int32_t to) {
    const auto h = static_cast<std::int32_t>(halfedges_.size());
    halfedges_.push_back({kNone, to, kNone, kNone});
    halfedges_.push_back({kNone, from, kNone, kNone});
    return h;
}

// OpenMesh: set_next_halfedge_handle() also sets the previous link of `next`.
void HalfedgeBuilder::set_next(std::int32_t h, std::int32_t next) {
    halfedges_[static_cast<std::size_t>(h)].next = next;
    halfedges_[static_cast<std::size_t>(next)].prev = h;
}

// OpenMesh: the first boundary half-edge clockwise from the vertex's half-edge becomes it.
void HalfedgeBuilder::adjust_outgoing_halfedge(std::int32_t v) {
    const std::int32_t start = vertex_out_[static_cast<std::size_t>(v)];
    std::int32_t h = start;
    while (h != kNone) {
        if (is_boundary_halfedge(h)) {
            vertex_out_[static_cast<std::size_t>(v)] = h;
            return;
        }
        h = halfedges_[static_cast<std::size_t>(h ^ 1)].next;
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
    const auto at = [this](std::int32_t h) -> Halfedge& {
        return halfedges_[static_cast<std::size_t>(h)];
    };

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
        if (at(inner_prev).next == inner_next) continue;
        // Search a free gap, between boundary_prev and boundary_next.
        const std::int32_t outer_prev = inner_next ^ 1;
        std::int32_t boundary_prev = outer_prev;
        do {
            boundary_prev = at(boundary_prev).next ^ 1;
        } while (!is_boundary_halfedge(boundary_prev));
        const std::int32_t boundary_next = at(boundary_prev).next;
        if (boundary_prev == inner_prev) return kNone;  // patch re-linking failed
        const std::int32_t patch_start = at(inner_prev).next;
        const std::int32_t patch_end = at(inner_next).prev;
        next_cache[cached++] = {boundary_prev, patch_start};
        next_cache[cached++] = {patch_end, boundary_next};
        next_cache[cached++] = {inner_prev, inner_next};
    }

    // Create missing edges.
    for (std::size_t i = 0, ii = 1; i < n; ++i, ++ii, ii %= n) {
        if (edge[i].is_new) edge[i].halfedge = new_edge(v[i], v[ii]);
    }

    // Create the face.
    const auto f = static_cast<std::int32_t>(face_halfedge_.size());
    face_halfedge_.push_back(edge[n - 1].halfedge);

    // Set up the half-edges.
    for (std::size_t i = 0, ii = 1; i < n; ++i, ++ii, ii %= n) {
        const std::int32_t vh = v[ii];
        const std::int32_t inner_prev = edge[i].halfedge;
        const std::int32_t inner_next = edge[ii].halfedge;
        const int id = (edge[i].is_new ? 1 : 0) | (edge[ii].is_new ? 2 : 0);
        std::int32_t& out = vertex_out_[static_cast<std::size_t>(vh)];
        if (id != 0) {
            const std::int32_t outer_prev = inner_next ^ 1;
            const std::int32_t outer_next = inner_prev ^ 1;
            switch (id) {
                case 1: {  // prev is new, next is old
                    const std::int32_t boundary_prev = at(inner_next).prev;
                    next_cache[cached++] = {boundary_prev, outer_next};
                    out = outer_next;
                    break;
                }
                case 2: {  // next is new, prev is old
                    const std::int32_t boundary_next = at(inner_prev).next;
                    next_cache[cached++] = {outer_prev, boundary_next};
                    out = boundary_next;
                    break;
                }
                default: {  // both are new
                    if (out == kNone) {
                        out = outer_next;
                        next_cache[cached++] = {outer_prev, outer_next};
                    } else {
                        const std::int32_t boundary_next = out;
                        const std::int32_t boundary_prev = at(boundary_next).prev;
                        next_cache[cached++] = {boundary_prev, outer_next};
                        next_cache[cached++] = {outer_prev, boundary_next};
                    }
                    break;
                }
            }
            next_cache[cached++] = {inner_prev, inner_next};  // inner link
        } else {
            edge[ii].needs_adjust = out == inner_next;
        }
        at(edge[i].halfedge).face = f;
    }

    // Process the next-half-edge cache, then adjust the vertices' half-edges.
    for (std::size_t i = 0; i < cached; ++i) set_next(next_cache[i].first, next_cache[i].second);
    for (std::size_t i = 0; i < n; ++i) {
        if (edge[i].needs_adjust) adjust_outgoing_halfedge(v[i]);
    }
    return f;
}

void HalfedgeBuilder::write_into(TriMesh& m) const {
    m.resize(n_vertices(), n_edges(), n_faces());
    for (std::size_t h = 0; h < halfedges_.size(); ++h) {
        const Halfedge& e = halfedges_[h];
        const HalfedgeHandle hh(static_cast<int>(h));
        m.set_vertex_handle(hh, VertexHandle(e.to));
        m.set_face_handle(hh, FaceHandle(e.face));
        if (e.next != kNone) m.set_next_halfedge_handle(hh, HalfedgeHandle(e.next));
    }
    // set_next_halfedge_handle() set each target's previous link from the last half-edge written
    // before it, which need not be the last one add_face linked: write the previous links as built.
    for (std::size_t h = 0; h < halfedges_.size(); ++h) {
        const std::int32_t prev = halfedges_[h].prev;
        if (prev != kNone)
            m.set_prev_halfedge_handle(HalfedgeHandle(static_cast<int>(h)), HalfedgeHandle(prev));
    }
    for (std::size_t v = 0; v < vertex_out_.size(); ++v)
        m.set_halfedge_handle(VertexHandle(static_cast<int>(v)), HalfedgeHandle(vertex_out_[v]));
    for (std::size_t f = 0; f < face_halfedge_.size(); ++f)
        m.set_halfedge_handle(FaceHandle(static_cast<int>(f)), HalfedgeHandle(face_halfedge_[f]));
}

void HalfedgeBuilder::write_normals(TriMesh& m) const {
    // TriMeshT::calc_face_normal(f): the corners from the face's half-edge on, through
    // PolyMeshT's three-point form (which TriMeshT hides).
    const TriMesh::PolyMesh& poly = m;
    for (std::size_t f = 0; f < face_halfedge_.size(); ++f) {
        const Halfedge& h0 = halfedges_[static_cast<std::size_t>(face_halfedge_[f])];
        const Halfedge& h1 = halfedges_[static_cast<std::size_t>(h0.next)];
        const Halfedge& h2 = halfedges_[static_cast<std::size_t>(h1.next)];
        m.set_normal(
            FaceHandle(static_cast<int>(f)),
            poly.calc_face_normal(m.point(VertexHandle(h0.to)), m.point(VertexHandle(h1.to)),
                                  m.point(VertexHandle(h2.to))));
    }
    // PolyMeshT::calc_vertex_normal(v): the faces around v summed from zero, clockwise from its
    // half-edge (as ConstVertexFaceIter visits them), then scaled to unit length unless zero.
    for (std::size_t v = 0; v < vertex_out_.size(); ++v) {
        TriMesh::Normal n(0.0, 0.0, 0.0);
        const std::int32_t start = vertex_out_[v];
        for (std::int32_t h = start; h != kNone;) {
            const std::int32_t f = halfedges_[static_cast<std::size_t>(h)].face;
            if (f != kNone) n += m.normal(FaceHandle(f));
            h = halfedges_[static_cast<std::size_t>(h ^ 1)].next;
            if (h == start) break;
        }
        const double length = OpenMesh::norm(n);
        if (length != 0.0) n *= (1.0 / length);
        m.set_normal(VertexHandle(static_cast<int>(v)), n);
    }
}

}  // namespace kerf::mesh::detail
