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

#include <cstdint>
#include <memory>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

namespace detail {
struct ContextState;
}

class CutContext {
public:
    /// Adds the scratch properties to `mesh`, measures its scale, indexes its faces (O(n)) and
    /// reserves the headroom for cuts, which the first four grow_step() calls write (resident).
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

    /// Faces the cuts can still add before the reserved capacity runs out.
    std::size_t spare_faces() const noexcept;

    /// One bounded step of capacity growth, for idle time (between frames): when the spare room
    /// of one element kind (vertices, edges, faces, the face index) is below half its target,
    /// grows that kind alone (O(that array): tens of ms at 1M faces) to a headroom of an eighth
    /// of the mesh, at least `min_spare_faces` faces (half as many vertices, twice as many edges),
    /// and makes it resident; or, first, hangs the faces the last cuts added to the face index
    /// on its leaves (O(those faces x depth)), or writes one kind of the headroom the build
    /// reserved (O(that room)). Returns whether it did something. Called often
    /// enough, no cut ever grows capacity (a cut that finds too little room grows everything
    /// itself: O(mesh)).
    bool grow_step(std::size_t min_spare_faces = 0);

    /// Every grow_step() that is due, now.
    void grow_capacity(std::size_t min_spare_faces = 0);

    /// Cuts that found too little room and grew capacity inside the cut (0 when idle time
    /// kept up).
    std::uint64_t growths_in_cuts() const noexcept;

    /// Library-internal state (used by the kerf::cut implementation files).
    detail::ContextState& state() noexcept { return *state_; }

private:
    std::unique_ptr<detail::ContextState> state_;
};

}  // namespace kerf::cut
