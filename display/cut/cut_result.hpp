// The outcome of a cut: a status value and statistics, never an exception. On any status other
// than kOk the mesh is exactly as it was before the call.
#pragma once

#include <cstdint>
#include <string_view>

namespace kerf::cut {

/// Why a cut did or did not happen.
enum class CutStatus : std::uint8_t {
    kOk = 0,               ///< the mesh was cut
    kPlaneMissesMesh,      ///< no triangle crosses the plane (a plane that only touches is a miss)
    kSeedNotOnSurface,     ///< the seed point lies on no triangle (within the seed tolerance)
    kSeedFarFromCut,       ///< no crossing triangle is reachable from the seed near the plane
    kSeedOnInnerBoundary,  ///< the seed's loop is a hole with no outer loop around it (a lone
                           ///< inward-facing shell)
    kNonManifoldInput,     ///< an open edge or broken fan where the cut passes
    kInvalidPlane,         ///< non-finite point or normal, or a zero normal
    kInvalidArgument,      ///< e.g. a non-positive or non-finite kerf width
    kDegenerateCrossSection,  ///< the cross-section pinches at a vertex or along an edge
    kCapTriangulationFailed,  ///< a cap polygon could not be triangulated without slivers
    kSliverSplit,             ///< the plane passes so near a vertex of a thin triangle that a split
                              ///< part would have near-zero area: a plane moved by a hair cuts
    kInternalError,           ///< an invariant broke; please report (mesh may have been edited)
};

/// Lower-case name of `s`, e.g. "plane_misses_mesh".
std::string_view to_string(CutStatus s) noexcept;

/// What a cut did. Counts are of elements created; time is wall time of the call.
struct CutStats {
    std::uint32_t faces_split = 0;        ///< original triangles that were split by the plane(s)
    std::uint32_t vertices_added = 0;     ///< edge-crossing vertices plus duplicates
    std::uint32_t vertices_merged = 0;    ///< cut points within the on-plane tolerance of their
                                          ///< loop neighbour, collapsed into it (each moved
                                          ///< the surface by at most tolerance_m)
    std::uint32_t vertices_snapped = 0;   ///< vertices a little beyond the tolerance taken as on
                                          ///< the plane (unmoved) instead of leaving a sliver
    std::uint32_t triangles_added = 0;    ///< triangles created: split parts plus caps
    std::uint32_t triangles_removed = 0;  ///< triangles deleted (biplanar slab only)
    std::uint32_t cap_triangles = 0;      ///< triangles of all caps
    std::uint32_t loops = 0;              ///< cross-section loops cut (outer loops plus holes)
    std::uint32_t cap_chords = 0;         ///< chords put into earlier caps the plane crossed
                                          ///< (their inner edges flipped instead of split)
    std::uint32_t pieces = 0;             ///< pieces, when the operation computed them (else 0)
    std::int64_t time_ns = 0;             ///< wall time of the operation
};

/// A status and the statistics of the operation that produced it.
struct CutResult {
    CutStatus status = CutStatus::kOk;
    CutStats stats;

    bool ok() const noexcept { return status == CutStatus::kOk; }
};

}  // namespace kerf::cut
