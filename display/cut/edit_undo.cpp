#include "display/cut/edit_undo.hpp"

#include "display/cut/context_state.hpp"

namespace kerf::cut::detail {

using mesh::EdgeHandle;
using mesh::FaceHandle;
using mesh::TriMesh;
using mesh::VertexHandle;

void EditUndo::save_face(const TriMesh& m, FaceHandle f) {
    if (!f.is_valid()) return;
    faces_saved_.push_back({f.idx(), m.face(f), m.status(f), m.normal(f)});
    for (auto h : m.fh_range(f)) {
        const EdgeHandle e = m.edge_handle(h);
        edges_saved_.push_back({e.idx(), m.edge(e), m.status(e), m.status(m.halfedge_handle(e, 0)),
                                m.status(m.halfedge_handle(e, 1))});
        const VertexHandle v = m.to_vertex_handle(h);
        vertices_saved_.push_back({v.idx(), m.vertex(v), m.status(v)});
    }
}

void EditUndo::size_once(const ContextState& s) {
    if (sized_) return;
    const TriMesh& m = s.mesh;
    sized_ = true;
    vertices_ = m.n_vertices(), edges_ = m.n_edges(), faces_ = m.n_faces();
    cap_faces_ = s.cap_faces.size();
    tree_pending_ = s.tree.pending(), tree_hung_ = s.tree.hung();
}

void EditUndo::record_faces(const ContextState& s, const std::vector<FaceHandle>& faces) {
    size_once(s);
    for (const FaceHandle f : faces) save_face(s.mesh, f);
}

EditUndo::Checkpoint EditUndo::checkpoint(const ContextState& s) const {
    const TriMesh& m = s.mesh;
    return Checkpoint{sized_,
                      m.n_vertices(),
                      m.n_edges(),
                      m.n_faces(),
                      s.cap_faces.size(),
                      s.tree.pending(),
                      s.tree.hung(),
                      faces_saved_.size(),
                      edges_saved_.size(),
                      vertices_saved_.size()};
}

void EditUndo::record(const ContextState& s) {
    const TriMesh& m = s.mesh;
    size_once(s);
    auto save_edge_faces = [&](std::int32_t edge) {
        const EdgeHandle e(edge);
        save_face(m, m.face_handle(m.halfedge_handle(e, 0)));
        save_face(m, m.face_handle(m.halfedge_handle(e, 1)));
    };
    for (const PlanLoop& l : s.plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const CutPointKey k = s.plan.points[i].key;
            if (k.edge)
                save_edge_faces(k.id);
            else
                for (auto f : m.vf_range(VertexHandle(k.id))) save_face(m, f);
        }
    }
    // A merge splits its edge and collapses the new vertex into the kept point: the faces
    // around that point (an on-plane vertex; a split vertex's faces are its edge's, saved above).
    for (const MergedPoint& mp : s.plan.merged) save_edge_faces(mp.point.key.id);
}

void EditUndo::restore(ContextState& s) {
    if (!sized_) return;
    Checkpoint start;
    start.vertices = vertices_, start.edges = edges_, start.faces = faces_;
    start.cap_faces = cap_faces_, start.tree_pending = tree_pending_, start.tree_hung = tree_hung_;
    restore_to(s, start);
}

void EditUndo::restore_to(ContextState& s, const Checkpoint& c) {
    if (!sized_) return;
    TriMesh& m = s.mesh;
    const std::size_t vertices = c.vertices, edges = c.edges, faces = c.faces;
    m.resize(vertices, edges, faces);
    // Newest first: an element saved twice ends with its oldest (original) state.
    for (auto it = vertices_saved_.rbegin();
         it != vertices_saved_.rend() - static_cast<std::ptrdiff_t>(c.vertices_saved); ++it) {
        if (static_cast<std::size_t>(it->vertex) >= vertices) continue;
        const VertexHandle v(it->vertex);
        m.vertex(v) = it->item;
        m.status(v) = it->status;
    }
    for (auto it = edges_saved_.rbegin();
         it != edges_saved_.rend() - static_cast<std::ptrdiff_t>(c.edges_saved); ++it) {
        if (static_cast<std::size_t>(it->edge) >= edges) continue;
        const EdgeHandle e(it->edge);
        m.edge(e) = it->item;
        m.status(e) = it->status;
        m.status(m.halfedge_handle(e, 0)) = it->h0;
        m.status(m.halfedge_handle(e, 1)) = it->h1;
    }
    for (auto it = faces_saved_.rbegin();
         it != faces_saved_.rend() - static_cast<std::ptrdiff_t>(c.faces_saved); ++it) {
        if (static_cast<std::size_t>(it->face) >= faces) continue;
        const FaceHandle f(it->face);
        m.face(f) = it->item;
        m.status(f) = it->status;
        m.set_normal(f, it->normal);
    }
    s.cap_faces.resize(c.cap_faces);
    s.tree.drop_inserts(c.tree_pending, c.tree_hung);
    sized_ = c.sized;
    faces_saved_.resize(c.faces_saved);
    edges_saved_.resize(c.edges_saved);
    vertices_saved_.resize(c.vertices_saved);
}

}  // namespace kerf::cut::detail
