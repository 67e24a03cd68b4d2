// Internal: the half-edge connectivity OpenMesh's `add_face` would give a triangle list, built on
// flat arrays and written into the TriMesh in one pass.
//
// OpenMesh's `PolyConnectivity::add_face` (OpenMesh 9.0, Debian's libopenmesh) is called once per
// triangle through a shared library built with its assertions on, grows every property vector one
// element at a time and searches each vertex's fan through bounds-checked accessors: about a fifth
// of `kerf cut` on a 1M-triangle file. `HalfedgeBuilder::add_face` is the same algorithm step for
// step (the same checks and refusals, the same new-edge order, the same boundary relinking, the
// same outgoing half-edge per vertex), so every handle, and so every tie a cut breaks by handle
// and every mesh hash, is what `add_face` gives. tests/mesh/halfedge_build_test.cpp compares the
// two element by element on real, generated and random non-manifold triangle lists.
#pragma once

#include <cstdint>
#include <vector>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh::detail {

/// Vertices, edges and faces as `add_vertex` / `add_face` calls on an empty TriMesh would leave
/// them, without the TriMesh until `write_into`.
class HalfedgeBuilder {
public:
    /// Room for this many vertices, edges and faces.
    void reserve(std::size_t vertices, std::size_t edges, std::size_t faces);
    /// A new isolated vertex; its index (vertices are numbered in the order added).
    std::int32_t add_vertex();
    /// What OpenMesh's add_face(a, b, c) does: the new face's index, or -1 (nothing changed) where
    /// OpenMesh refuses it (complex vertex, complex edge, failed patch relinking).
    /// @pre a, b, c are distinct indices of vertices already added
    std::int32_t add_face(std::int32_t a, std::int32_t b, std::int32_t c);

    std::size_t n_vertices() const { return vertex_out_.size(); }
    std::size_t n_edges() const { return halfedges_.size() / 2; }
    std::size_t n_faces() const { return face_halfedge_.size(); }

    /// Sizes `mesh` to this connectivity and writes it: every half-edge's target, face, next and
    /// previous half-edge, every vertex's and face's half-edge. Points and attributes are the
    /// caller's to set.
    /// @pre `mesh` is empty
    void write_into(TriMesh& mesh) const;
    /// Sets every face's and vertex's normal as OpenMesh's update_normals() does, in the same
    /// order of operations (bit for bit), from these arrays instead of the mesh's circulators.
    /// @pre write_into(mesh) and the mesh's points set
    void write_normals(TriMesh& mesh) const;

private:
    struct Halfedge {
        std::int32_t face = -1;
        std::int32_t to = -1;
        std::int32_t next = -1;
        std::int32_t prev = -1;
    };
    static constexpr std::int32_t kNone = -1;

    bool is_boundary_vertex(std::int32_t v) const;
    bool is_boundary_halfedge(std::int32_t h) const { return halfedges_[h].face == kNone; }
    std::int32_t find_halfedge(std::int32_t from, std::int32_t to) const;
    std::int32_t new_edge(std::int32_t from, std::int32_t to);
    void set_next(std::int32_t h, std::int32_t next);
    void adjust_outgoing_halfedge(std::int32_t v);

    std::vector<Halfedge> halfedges_;  ///< 2e from the edge's first vertex to its second, 2e+1 back
    std::vector<std::int32_t> vertex_out_;
    std::vector<std::int32_t> face_halfedge_;
};

}  // namespace kerf::mesh::detail
