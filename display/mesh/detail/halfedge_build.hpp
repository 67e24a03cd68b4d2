// Internal: the half-edge connectivity OpenMesh's `add_face` would give a triangle list, built on
// the TriMesh's own arrays.
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
/// them, written straight into that mesh's arrays (no copy of the connectivity: 54 MB less at a
/// 1M-triangle load's peak). The arrays grow in steps and hold unlinked spare elements until
/// `finish()`; nothing may read the mesh before it.
class HalfedgeBuilder {
public:
    /// @pre `mesh` is empty
    explicit HalfedgeBuilder(TriMesh& mesh) : m_(mesh) {}
    /// `count` new isolated vertices, numbered from n_vertices() on.
    void add_vertices(std::size_t count);
    /// A new isolated vertex; its index (vertices are numbered in the order added).
    std::int32_t add_vertex();
    /// What OpenMesh's add_face(a, b, c) does: the new face's index, or -1 (nothing changed) where
    /// OpenMesh refuses it (complex vertex, complex edge, failed patch relinking).
    /// @pre a, b, c are distinct indices of vertices already added
    std::int32_t add_face(std::int32_t a, std::int32_t b, std::int32_t c);

    std::size_t n_vertices() const { return vertices_; }
    std::size_t n_edges() const { return edges_; }
    std::size_t n_faces() const { return faces_; }

    /// Trims the mesh to the elements added. Points and attributes are the caller's to set.
    void finish();
    /// Sets every face's and vertex's normal as OpenMesh's update_normals() does, in the same
    /// order of operations (bit for bit), reading the half-edge arrays directly instead of through
    /// the mesh's circulators.
    /// @pre finish() and the mesh's points set
    void write_normals() const;

private:
    static constexpr std::int32_t kNone = -1;

    // The mesh's half-edge fields by index.
    std::int32_t face(std::int32_t h) const { return m_.face_handle(HalfedgeHandle(h)).idx(); }
    std::int32_t to(std::int32_t h) const { return m_.to_vertex_handle(HalfedgeHandle(h)).idx(); }
    std::int32_t next(std::int32_t h) const {
        return m_.next_halfedge_handle(HalfedgeHandle(h)).idx();
    }
    std::int32_t prev(std::int32_t h) const {
        return m_.prev_halfedge_handle(HalfedgeHandle(h)).idx();
    }
    std::int32_t out(std::int32_t v) const { return m_.halfedge_handle(VertexHandle(v)).idx(); }
    void set_out(std::int32_t v, std::int32_t h) {
        m_.set_halfedge_handle(VertexHandle(v), HalfedgeHandle(h));
    }

    bool is_boundary_vertex(std::int32_t v) const;
    bool is_boundary_halfedge(std::int32_t h) const { return face(h) == kNone; }
    std::int32_t find_halfedge(std::int32_t from, std::int32_t to) const;
    std::int32_t new_edge(std::int32_t from, std::int32_t to);
    void set_next(std::int32_t h, std::int32_t next);
    void adjust_outgoing_halfedge(std::int32_t v);
    /// Grows the mesh's arrays to hold at least these counts (in steps).
    void make_room(std::size_t vertices, std::size_t edges, std::size_t faces);

    struct Counts {
        std::size_t vertices = 0, edges = 0, faces = 0;
    };
    TriMesh& m_;
    std::size_t vertices_ = 0;  ///< the elements added
    std::size_t edges_ = 0;
    std::size_t faces_ = 0;
    Counts room_;  ///< the mesh's sizes: the elements added and the spare ones after them
};

}  // namespace kerf::mesh::detail
