// Separator — gradual separation after a uniplanar slice (paper §3.6, §3.9): as the blade sweeps
// the cross-section, the two sides open into a kerf, with no fold, no flip and no new triangle.
//
//   CrossSection cs;
//   slice_by_plane(ctx, plane, seed, cs);                       // nothing visible changes yet
//   auto sep = Separator::make(ctx, cs, 1.0e-3);                // 1 mm kerf: O(band) once
//   sep->sweep(footprint_in_plane_coords);                      // per CutProgress: O(affected)
//
// Swept region: the union of the convex polygons given to sweep(), in the plane's (u, v) frame
// (metres), e.g. the blade's footprint at each progress event, or the convex hull of two
// consecutive footprints to cover the motion between them. It only grows.
//
// Displacement: every vertex of a cut side within kBandDepthKerfs kerfs of the plane (found once
// from the rim, so other bones crossing the plane never move) moves along the normal, away from
// the plane, by
//     g = kerf/2 * (1 - |d| / D) * m(x),   D = kBandDepthKerfs * kerf,
// where d is its distance to the plane and m(x) is 1 where its (u, v) position is swept, falling
// linearly to 0 within one kerf outside the swept region. Hence: the duplicated rim vertices (and
// both caps, which use them) move exactly kerf/2 each way once swept; every vertex nearer the
// plane than kerf/2 ends beyond the offset plane (the paper's "move nearby vertices too", done as
// a strictly monotone map d -> d + g with slope >= 1 - kerf/(2D) = 3/4 instead of a collapse, so
// no triangle becomes flat or zero-area). Moves are along the normal only, so every triangle keeps
// its projection onto the plane: a cap triangle can never flip.
// Partly swept (a withdrawn cut), the caps, built on rim points only, rise as wedges from the
// swept rim across the section: over a point a cap triangle is at the weight its corners'
// weights interpolate to, which can be far above m(x) there. A wall that leans over the cap near
// the plane (a vertex a few um above it) is therefore raised with the cap: at every corner of the
// overlay of each such wall face's projection with the cap triangles (the wall is linear over
// its face, the cap over each triangle, so these points decide) the wall keeps at least half of
// its gap above the cap, its corners' weights raised as needed (rim points of the wall too,
// which raises their cap triangles in turn). Weights only grow and 1 everywhere clears every cap,
// so this ends (cap_clearance.hpp). Without it the cap went through the wall and a later cut
// through it met a cross-section that crossed itself (cap_triangulation_failed). Fully swept, the
// gap is exactly the kerf. Where the walls meet the plane at right angles this is the biplanar
// result (the shifted band covers exactly the wall left by the slab); slanted walls differ from it
// by at most slope * kerf/2 (the tests compare volumes with subtract_slab()).
#pragma once

#include <memory>
#include <span>

#include "config/base/result.hpp"
#include "display/cut/cross_section.hpp"
#include "display/cut/cut_context.hpp"
#include "display/cut/cut_result.hpp"

namespace kerf::cut {

/// Depth of the band of vertices that moves, in kerfs (D above).
inline constexpr double kBandDepthKerfs = 2.0;

/// How far a vertex held back (keep_off, or a corner of an earlier cap's triangle that reaches
/// past the band) holds its neighbours back, in kerfs: their share of the lift grows by one over
/// this distance from it (along the band's edges).
inline constexpr double kKeepOffRampKerfs = 8.0;

/// What the separation has done so far.
struct SeparationStats {
    std::uint32_t band_vertices = 0;     ///< vertices that may move (both sides, rim included)
    std::uint32_t rim_pairs = 0;         ///< duplicated cross-section vertex pairs
    std::uint32_t rim_pairs_swept = 0;   ///< pairs fully apart (m = 1)
    std::uint32_t moved_last_sweep = 0;  ///< vertices moved by the last sweep() call
};

class Separator {
public:
    /// Plans the separation of the cut `cut` (just made on ctx.mesh()) for a blade `kerf_width_m`
    /// wide: finds the band on both sides and indexes it in the plane, and indexes the band's
    /// faces near the plane and the cap triangles (cost of the band and the caps only; the walls
    /// over a cap triangle are found when one of its corners first moves).
    /// @pre `cut` is the CrossSection of the latest slice of ctx.mesh(), unedited since.
    /// Fails with kInvalidArgument for a non-positive or non-finite kerf, or an empty cut.
    static Result<Separator, CutStatus> make(CutContext& ctx, const CrossSection& cut,
                                             double kerf_width_m);

    Separator(Separator&&) noexcept;
    Separator& operator=(Separator&&) noexcept;
    ~Separator();

    /// Keeps the band off an earlier cut's plane `other` (a withdrawn cut, whose sides this
    /// localised cut may have sliced on one side only): a band vertex inside the box [lo, hi]
    /// that would move towards `other` moves less, stopping two tolerances short of it, and one
    /// on it (within the tolerance) does not move, so no side of the earlier cut passes through
    /// the other one, left in place. The kerf then opens less there. A vertex held back holds its
    /// band neighbours back too, less with distance (its share of the lift plus the distance
    /// over kKeepOffRampKerfs kerfs, along the band's edges): where one corner of a face stayed
    /// and the next moved by the full lift, faces folded over the earlier cut's cap (a thin
    /// wedge of bone). Call before the first sweep. O(band), plus O(v log v) for the v vertices
    /// held back and their neighbours within the ramp.
    void keep_off(const Plane& other, const Vec3& lo, const Vec3& hi);

    /// Adds a convex polygon (either orientation, >= 3 points, plane coordinates, m) to the swept
    /// region and moves the vertices it affects. Cost proportional to the band vertices within a
    /// kerf of the polygon, plus the wall faces over the cap triangles whose corners moved.
    /// Ignores (returns false for) a degenerate or non-finite polygon.
    bool sweep(std::span<const Vec2> convex_polygon_m);

    /// Sweeps everything: the cut is complete and the kerf fully open.
    void sweep_all();

    /// Statistics so far.
    const SeparationStats& stats() const noexcept;

    /// The vertices the last sweep()/sweep_all() moved. Normals are NOT updated here (that would
    /// triple a step's cost): whoever draws the mesh refreshes the faces around these.
    std::span<const mesh::VertexHandle> moved_vertices() const noexcept;

private:
    struct State;
    explicit Separator(std::unique_ptr<State> s) noexcept;
    std::unique_ptr<State> s_;
};

}  // namespace kerf::cut
