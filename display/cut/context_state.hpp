// Library-internal: what a CutContext holds. Scratch properties are created on the mesh once and
// reused by every cut through generation stamps (no clearing pass, no property churn per cut).
#pragma once

#include <cstdint>
#include <vector>

#include "display/cut/face_grid.hpp"
#include "display/cut/section_plan.hpp"
#include "display/cut/triangulate.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

struct ContextState {
    explicit ContextState(mesh::TriMesh& m);
    ~ContextState();
    ContextState(const ContextState&) = delete;
    ContextState& operator=(const ContextState&) = delete;

    /// Measures the mesh and rebuilds the face index.
    void rebuild();
    /// Starts a new stamp generation (resets every stamp on wrap-around).
    void next_generation();
    /// Makes room for `vertices`, `edges`, `faces` more elements without reallocating during the
    /// edit (capacity doubles when it runs out, so growth is amortised and cuts stay cheap).
    void ensure_capacity(std::size_t vertices, std::size_t edges, std::size_t faces);
    /// Doubles the capacity (at least room for that many more) and makes it resident.
    void grow(std::size_t vertices, std::size_t edges, std::size_t faces);
    /// Reserves the capacity recorded in reserved_* and writes every element of it once (grow
    /// to it, shrink back), so that the pages are resident before a cut needs them: a cut that
    /// first-touches fresh memory spends a third of its time in page faults (measured on the
    /// 1M foot). Costs resident memory equal to the capacity, O(capacity) time, at load.
    void reserve_resident();

    bool vertex_marked(mesh::VertexHandle v) const {
        return mesh.property(v_stamp, v) == generation;
    }
    bool edge_marked(mesh::EdgeHandle e) const { return mesh.property(e_stamp, e) == generation; }
    bool face_marked(mesh::FaceHandle f) const { return mesh.property(f_stamp, f) == generation; }
    void mark_face(mesh::FaceHandle f) { mesh.property(f_stamp, f) = generation; }

    mesh::TriMesh& mesh;
    double scale_m = 0.0;
    double tolerance_m = 0.0;
    double max_edge_m =
        0.0;  ///< longest non-cap edge (+ vertex moves noted since): full-slice reach
    FaceGrid grid;
    std::vector<mesh::FaceHandle> cap_faces;  ///< every cap face made so far (not in the grid)

    OpenMesh::VPropHandleT<std::uint32_t> v_stamp;
    OpenMesh::VPropHandleT<std::int32_t> v_node;
    OpenMesh::EPropHandleT<std::uint32_t> e_stamp;
    OpenMesh::EPropHandleT<std::int32_t> e_node;
    OpenMesh::FPropHandleT<std::uint32_t> f_stamp;
    OpenMesh::FPropHandleT<std::uint8_t> cap;  ///< named kCapFaceProperty
    std::uint32_t generation = 1;
    std::size_t reserved_vertices = 0, reserved_edges = 0, reserved_faces = 0;

    SectionPlan plan;
    Triangulator triangulator;
    std::vector<std::uint32_t> heap;  ///< seed search scratch
};

}  // namespace kerf::cut::detail
