// Library-internal: a bounded undo of the edits of one or more planned slices, so that a cut made
// of several edits (the slab's two walls) can still refuse with the mesh unchanged when a later
// step fails after an earlier edit.
//
//   EditUndo undo;
//   undo.record(s);                    // s.plan is the plan about to be applied
//   apply_plan(s, plane, cs, stats);
//   ...                                // a later step refuses:
//   undo.restore(s);                   // the mesh, its face tree and cap list as before record()
//
// What applying a plan can change in existing elements is bounded by its cut points: the split of
// a crossing edge rewrites the edge's two faces; detaching the rim and capping rewrites the faces
// around each on-plane rim vertex (and the split faces); a merge's split and collapse rewrite the
// merged edge's faces and the faces around the vertex it collapses into; flipping a needle
// diagonal on the rim (subtract_slab) rewrites two faces that hold a rim vertex; a chord put
// into an earlier cap (cap_chords) rewrites the faces of the crossed cap edges and of the two
// edges it ends on, which record_faces() is given. record() saves
// those faces whole (the face, its three edges with both halfedges, its three vertices, their
// statuses, the face normal) and the array sizes; everything added since is dropped on restore.
// A checkpoint() taken between records can be restored alone (restore_to): the edits recorded
// after it are undone, the earlier ones kept. O(faces around the selected loops' cut points).
#pragma once

#include <cstddef>
#include <vector>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

struct ContextState;

class EditUndo {
public:
    /// Saves what applying s.plan can change; the first call also saves the sizes to return to.
    void record(const ContextState& s);
    /// Saves the given faces whole (invalid handles are skipped), as record() saves the faces of
    /// a plan; the first call also saves the sizes to return to.
    void record_faces(const ContextState& s, const std::vector<mesh::FaceHandle>& faces);

    /// Where the records stand: restore_to() undoes what was recorded after it.
    struct Checkpoint {
        bool sized = false;
        std::size_t vertices = 0, edges = 0, faces = 0, cap_faces = 0;
        std::size_t tree_pending = 0, tree_hung = 0;
        std::size_t faces_saved = 0, edges_saved = 0, vertices_saved = 0;
    };
    /// The current sizes (of the mesh, the cap list, the face tree's inserts and the records).
    Checkpoint checkpoint(const ContextState& s) const;
    /// Puts back what was recorded after `c` and drops what was added since, leaving the records
    /// made before `c` (no flush of the face tree in between).
    void restore_to(ContextState& s, const Checkpoint& c);
    /// Puts the mesh, the face tree's inserts and the cap face list back as they were at the
    /// first record(), then forgets every record.
    void restore(ContextState& s);
    /// Whether anything is recorded.
    bool empty() const noexcept { return !sized_; }

private:
    void save_face(const mesh::TriMesh& m, mesh::FaceHandle f);
    void size_once(const ContextState& s);

    struct FaceRecord {
        int face;
        OpenMesh::ArrayItems::Face item;
        OpenMesh::Attributes::StatusInfo status;
        mesh::TriMesh::Normal normal;
    };
    struct EdgeRecord {
        int edge;
        OpenMesh::ArrayItems::Edge item;
        OpenMesh::Attributes::StatusInfo status, h0, h1;
    };
    struct VertexRecord {
        int vertex;
        OpenMesh::ArrayItems::Vertex item;
        OpenMesh::Attributes::StatusInfo status;
    };
    bool sized_ = false;
    std::size_t vertices_ = 0, edges_ = 0, faces_ = 0, cap_faces_ = 0;
    std::size_t tree_pending_ = 0, tree_hung_ = 0;
    std::vector<FaceRecord> faces_saved_;
    std::vector<EdgeRecord> edges_saved_;
    std::vector<VertexRecord> vertices_saved_;
};

}  // namespace kerf::cut::detail
