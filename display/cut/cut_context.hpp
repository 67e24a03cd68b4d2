// kerf::cut::CutContext — the per-mesh state every cut reuses: scratch properties created once on
// the mesh, a spatial index of faces built once and updated incrementally by each cut, and buffers
// that keep their capacity. Create one per mesh and pass it to every cut on that mesh.
//
//   kerf::cut::CutContext ctx(mesh);                 // O(n) once: bounding box and face index
//   CrossSection cs;
//   auto r = slice_by_plane(ctx, plane, seed, cs);   // O(cross-section) per localised cut
//
// Rules: the context must outlive none of the mesh (it holds a reference); after
// `mesh.garbage_collection()` or any edit made outside kerf::cut that moves vertices by more than
// `note_vertices_moved()` allows, call `rebuild()`. Not thread-safe (one cutting thread per mesh).
#pragma once

#include <memory>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

namespace detail {
struct ContextState;
}

class CutContext {
public:
    /// Adds the scratch properties to `mesh`, measures its scale and indexes its faces (O(n)).
    explicit CutContext(mesh::TriMesh& mesh);
    ~CutContext();
    CutContext(const CutContext&) = delete;
    CutContext& operator=(const CutContext&) = delete;

    /// The mesh this context cuts.
    mesh::TriMesh& mesh() noexcept;

    /// Bounding-box diagonal of the mesh when the context was (re)built, m.
    double scale_m() const noexcept;

    /// On-plane tolerance used by every cut: kRelativeTolerance * scale_m(), m.
    double tolerance_m() const noexcept;

    /// Widens spatial queries after vertices were moved (e.g. gradual separation) by up to
    /// `max_distance_m` each since the index was built. Cheap; call after each batch of moves.
    void note_vertices_moved(double max_distance_m) noexcept;

    /// Re-measures and re-indexes the mesh (O(n)); required after garbage_collection().
    void rebuild();

    /// Faces the cuts can still add before the reserved capacity runs out. When it does, the
    /// cut that needs more doubles it inside the call: O(mesh), about 0.6 s at 1.5M elements.
    std::size_t spare_faces() const noexcept;

    /// Doubles the reserved (resident) capacity now, O(mesh), so that no cut has to: call it
    /// from idle time (between frames) when spare_faces() runs low.
    void grow_capacity();

    /// Library-internal state (used by the kerf::cut implementation files).
    detail::ContextState& state() noexcept { return *state_; }

private:
    std::unique_ptr<detail::ContextState> state_;
};

}  // namespace kerf::cut
