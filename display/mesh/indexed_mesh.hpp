// kerf::mesh::IndexedMesh — a plain indexed triangle list: exactly what a file holds, before
// OpenMesh's half-edge structure (which cannot hold every triangle a file may contain) sees it.
// Loaders produce one, `validate()` measures one, `build_tri_mesh()` turns one into a TriMesh.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh {

using Triangle = std::array<std::uint32_t, 3>;

/// Vertices (metres) and triangles as vertex-index triples in winding order.
struct IndexedMesh {
    std::vector<Point> positions_m;
    std::vector<Triangle> triangles;
    std::vector<Material> materials;  ///< empty, or one per vertex
};

/// Welds vertices whose coordinates are bit-identical (no tolerance; -0 counts as +0), giving
/// indices in first-seen order, so the result is deterministic and independent of hashing.
/// A flat open-addressing table of 8-byte slots that point into `out.positions_m` (a node-based
/// map cost a fifth of loading a 1M-triangle STL, and a node per vertex).
class VertexWelder {
public:
    /// Room for `vertices` distinct vertices before the table regrows (a hint; a closed mesh
    /// has about half as many vertices as triangles).
    void reserve(std::size_t vertices);
    /// Index of the vertex at `p` (metres), adding it to `out` when new. Every call on one
    /// welder must pass the same `out`.
    std::uint32_t weld(const Point& p, IndexedMesh& out);

private:
    struct Slot {
        std::uint32_t index_plus_one = 0;  ///< 0: empty
        std::uint32_t tag = 0;             ///< the hash's high half, compared before the point
    };
    void rehash(std::size_t slot_count, const IndexedMesh& out);
    std::vector<Slot> slots_;
    std::size_t used_ = 0;
};

/// A TriMesh built from an IndexedMesh, and what could not be represented as given.
struct BuiltMesh {
    TriMesh mesh;
    /// Triangles OpenMesh's `add_face` refused (non-manifold edge, complex vertex, repeated
    /// index): each was still added, with its own three copies of its corner vertices, so no
    /// triangle is lost, but it is disconnected from its neighbours. Zero for a clean 2-manifold.
    std::size_t detached_triangles = 0;
};

/// Builds the half-edge mesh: vertices in order, then triangles in order, then face and vertex
/// normals from the winding. Vertex materials come from `materials` (kCortical when absent).
/// @pre every index in `in.triangles` is < in.positions_m.size()
BuiltMesh build_tri_mesh(const IndexedMesh& in);
/// The same, into `out` where it lives (no copy of the mesh: OpenMesh meshes have no move
/// constructor, so moving a TriMesh copies it). Returns the detached triangles. With
/// `spare_faces`, room for that many more faces, half as many vertices and twice as many edges is
/// reserved (address space only: no page of it is touched), so that the headroom a CutContext
/// keeps costs no copy of the mesh.
/// @pre `out` is empty (make_mesh())
std::size_t build_tri_mesh_into(const IndexedMesh& in, TriMesh& out, std::size_t spare_faces = 0);

/// Faces of room an edited mesh keeps beyond its own: an eighth of `faces`, at least 65,536
/// (cut::CutContext keeps this much headroom resident, with half as many vertices and twice as
/// many edges, so that no cut grows an array).
std::size_t edit_headroom_faces(std::size_t faces) noexcept;

/// The indexed form of a TriMesh (deleted elements skipped, indices compacted in order).
IndexedMesh to_indexed(const TriMesh& mesh);

}  // namespace kerf::mesh
