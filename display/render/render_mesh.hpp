// kerf::render::RenderMesh — the flat, GL-ready copy of a TriMesh that the renderer uploads: float
// vertices (position, normal, plane coordinates, material, body) and a uint32 index per triangle
// corner, each in arrays with fixed capacity, plus the ranges that changed since the last upload.
// No GL here: the display builds and updates it on the cutting thread; the renderer uploads it.
//
//   RenderMesh rm = RenderMesh::build(mesh);          // O(n) once, everything dirty
//   ... cut ...                                        // kerf::cut edits `mesh` in place
//   rm.update_after_edit(mesh, sep.moved_vertices());  // O(edit): new + touched elements dirty
//   renderer.upload(rm);                               // glBufferSubData of the dirty ranges only
//
// Layout: TriMesh vertex i is GL vertex i; TriMesh face f is triangle f (indices 3f..3f+2; a
// deleted face is the degenerate triangle 0,0,0). Cap faces (face property kCapFaceProperty set)
// get three vertices of their own in the cap region, after the mesh-vertex capacity, so that they
// are flat, shaded with the cap's own normal and carry plane coordinates (u, v) for the pores.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "display/cut/session_changes.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::render {

/// What the fragment shader draws a vertex as (the `material` attribute).
enum class SurfaceKind : std::uint8_t {
    kCortical = 0,     ///< outer bone surface
    kCanal = 1,        ///< medullary canal wall (mesh::Material::kCancellous)
    kCutCortical = 2,  ///< cap corner on a cortical rim: dense cut bone
    kCutCanal = 3,     ///< cap corner on a canal rim: porous cut bone (pores grow towards it)
};

/// One GL vertex, 36 bytes, attributes at fixed offsets (see Renderer).
struct RenderVertex {
    float position[3];    ///< body frame, m
    float normal[3];      ///< unit
    float plane_uv[2];    ///< cap corners: plane coordinates, m; elsewhere 0
    std::uint8_t kind;    ///< SurfaceKind, as a normalised-free integer attribute
    std::uint8_t body;    ///< rigid body index (< kMaxBodies): which transform moves it
    std::uint8_t pad[2];  ///< 0
};
static_assert(sizeof(RenderVertex) == 36);

/// Most rigid bodies one mesh may hold (body 0 is the scene; severed pieces get 1, 2, ...):
/// 32 body matrices are 128 of the 256 vertex uniform vectors every GLES 3 implementation has.
/// A vertex of a body >= kMaxBodies is drawn with body 0's transform.
inline constexpr int kMaxBodies = 32;

/// Half-open element ranges [first, first + count) that changed, merged and sorted.
class DirtyRanges {
public:
    struct Range {
        std::uint32_t first;
        std::uint32_t count;
    };
    /// Marks element `i` changed (amortised O(1); merged on `ranges()`).
    void mark(std::uint32_t i);
    /// Marks [first, first + count) changed.
    void mark_range(std::uint32_t first, std::uint32_t count);
    /// The changed ranges, sorted; neighbours closer than `kMergeGap` elements are merged so that
    /// a scattered edit costs a few uploads, not thousands.
    std::span<const Range> ranges();
    /// Elements covered by ranges().
    std::uint64_t element_count();
    bool empty() const noexcept { return marks_.empty() && merged_.empty(); }
    void clear() noexcept;

    static constexpr std::uint32_t kMergeGap = 64;

private:
    std::vector<Range> marks_;
    std::vector<Range> merged_;
};

/// Counts of one sync of the RenderMesh with its TriMesh.
struct MeshSyncStats {
    std::uint32_t vertices_written = 0;  ///< mesh + cap vertices rewritten
    std::uint32_t faces_written = 0;     ///< triangles whose indices were rewritten
    bool rebuilt = false;                ///< capacity ran out: everything rebuilt and dirty
};

class RenderMesh {
public:
    /// Converts `mesh` (double, metres) to floats with room for `growth` times its vertices and
    /// faces (cuts append), cap vertices included. Everything is dirty.
    static RenderMesh build(const mesh::TriMesh& mesh, double growth = 2.0);

    /// Refreshes what an edit changed: elements appended since the last sync, the faces around
    /// every new vertex (a split or a rim duplicate rewires only those), every vertex in `moved`
    /// (separation) with its faces, and every face in `touched` (e.g. deleted by a slab).
    /// Cost proportional to the edit. Rebuilds (and says so) when the capacity is exceeded.
    MeshSyncStats update_after_edit(const mesh::TriMesh& mesh,
                                    std::span<const mesh::VertexHandle> moved = {},
                                    std::span<const mesh::FaceHandle> touched = {});

    /// Compares every element with `mesh` and marks only what differs: O(n), the safe choice
    /// after edits whose extent is unknown (garbage_collection(), a loaded snapshot).
    MeshSyncStats update_all(const mesh::TriMesh& mesh);

    /// Applies what a cut::CutSession reports (take_changes()): rewrites the listed vertices
    /// (and the cap corners on them) and faces; `everything` compares all (update_all()).
    /// Bodies are not read here: call assign_bodies() when `changes.bodies` is set.
    MeshSyncStats apply(const mesh::TriMesh& mesh, const cut::SessionChanges& changes);

    /// Re-reads every vertex's body from `body_of(VertexHandle) -> uint32` (O(n); after a cut
    /// severed pieces). Bodies >= kMaxBodies are stored as 0.
    template <class BodyOf>
    void assign_bodies(const mesh::TriMesh& mesh, BodyOf&& body_of) {
        for (auto v : mesh.vertices()) {
            const auto b = static_cast<std::uint32_t>(body_of(v));
            set_one_body(mesh, v, b < kMaxBodies ? static_cast<std::uint8_t>(b) : 0);
        }
    }

    /// Puts vertices `vertices` (and the cap corners on them) into rigid body `body`.
    /// @pre body < kMaxBodies
    void set_body(const mesh::TriMesh& mesh, std::span<const mesh::VertexHandle> vertices,
                  std::uint8_t body);

    /// Vertex array: mesh vertices [0, vertex_capacity()), then cap corners.
    std::span<const RenderVertex> vertices() const noexcept { return vertices_; }
    /// Index array: 3 per face slot, capacity face_capacity() * 3.
    std::span<const std::uint32_t> indices() const noexcept { return indices_; }
    /// Triangles to draw (face slots in use, deleted ones degenerate).
    std::uint32_t triangle_count() const noexcept { return face_count_; }
    /// Mesh vertices in use (deleted ones included): [0, vertex_count()) of the vertex array.
    std::uint32_t vertex_count() const noexcept { return vertex_count_; }
    std::uint32_t vertex_capacity() const noexcept { return vertex_capacity_; }
    std::uint32_t face_capacity() const noexcept { return face_capacity_; }
    /// Cap corners in use (3 per cap face).
    std::uint32_t cap_vertex_count() const noexcept { return cap_used_; }

    /// Vertex elements changed since the renderer last uploaded.
    DirtyRanges& dirty_vertices() noexcept { return dirty_vertices_; }
    /// Index elements (not triangles) changed since the renderer last uploaded.
    DirtyRanges& dirty_indices() noexcept { return dirty_indices_; }
    /// True when buffers must be (re)allocated: set by build() and capacity rebuilds.
    bool needs_realloc() const noexcept { return needs_realloc_; }
    void clear_realloc() noexcept { needs_realloc_ = false; }
    /// Bumped by every rebuild (lets a renderer notice a new capacity).
    std::uint64_t generation() const noexcept { return generation_; }

private:
    void set_one_body(const mesh::TriMesh& m, mesh::VertexHandle v, std::uint8_t body);
    void write_vertex_and_caps(const mesh::TriMesh& m, mesh::VertexHandle v);
    void write_vertex(const mesh::TriMesh& m, mesh::VertexHandle v);
    void write_face(const mesh::TriMesh& m, mesh::FaceHandle f);
    std::uint32_t cap_slot(std::uint32_t face);
    bool fits(const mesh::TriMesh& m) const noexcept;
    /// Rebuilds with more capacity when `m` no longer fits (filling `s`); true if it did.
    bool rebuild_if_full(const mesh::TriMesh& m, MeshSyncStats& s);
    /// Ends a sync: rebuilds with a larger cap region if a cap face found no room.
    MeshSyncStats finish_sync(const mesh::TriMesh& m, MeshSyncStats s);
    void rebuild(const mesh::TriMesh& m, double growth);

    std::vector<RenderVertex> vertices_;
    std::vector<std::uint32_t> indices_;
    std::vector<std::uint32_t> cap_slot_of_face_;  ///< first cap corner of face f, or kNoSlot
    std::vector<std::uint8_t> body_of_vertex_;
    std::uint32_t vertex_capacity_ = 0, face_capacity_ = 0, cap_capacity_ = 0;
    std::uint32_t vertex_count_ = 0, face_count_ = 0, cap_used_ = 0;
    DirtyRanges dirty_vertices_, dirty_indices_;
    std::uint32_t cap_min_ = 3 * 1024;  ///< least cap corners reserved; doubles on overflow
    bool cap_overflow_ = false;         ///< a cap face found no corners left in this sync
    bool needs_realloc_ = true;
    std::uint64_t generation_ = 0;
    double growth_ = 2.0;
};

}  // namespace kerf::render
