// slice_by_plane — the uniplanar slice (paper §3.3, §3.5-3.7): split every triangle crossing the
// plane, duplicate the cross-section vertices so the two sides share none, cap both sides.
//
//   CutContext ctx(mesh);
//   CrossSection cs;
//   CutResult r = slice_by_plane(ctx, *Plane::make(p, n), Seed{contact_point, hint}, cs);
//   if (!r.ok()) show(to_string(r.status));     // the mesh is unchanged
//
// Editing is in place: no rebuild, no garbage collection; handles of elements away from the cut
// stay valid. Deterministic: the same mesh and cuts give bit-identical results.
//
// Degeneracy rules (tol = CutContext::tolerance_m(), i.e. kRelativeTolerance * mesh scale):
//  - A vertex within tol of the plane is ON it: it becomes a rim vertex as it is (not moved), and
//    no edge is ever interpolated next to it, so no cut makes a zero-area triangle.
//  - An edge crossing the plane (one endpoint above +tol, one below -tol) gets ONE new vertex,
//    interpolated from the endpoint with the lower index (bit-identical for both faces). Position,
//    normal (renormalised), texture coordinates and colour use the same parameter t; the material
//    is the nearer endpoint's (the lower-index one at t = 0.5).
//  - A triangle with all three vertices on the plane (an earlier cap, a flat face) belongs to the
//    side its normal points away from (normal . n < 0: positive side), so a cut coplanar with an
//    earlier cap leaves that cap on its piece and does not cut it again.
//  - A plane that only touches the mesh (vertices, edges or faces on it, nothing crossing) is
//    kPlaneMissesMesh: nothing to separate, the mesh is unchanged.
//  - A cross-section that pinches at an on-plane vertex (two loops touching) or along an
//    on-plane edge (the surface touches the plane along an edge joining two non-neighbouring rim
//    vertices: the cap would need that edge a third time) is refused with
//    kDegenerateCrossSection;
//  - A plane a little beyond tol from a vertex (its crossing edges would cut off a tiny corner)
//    or from a vertex of an already thin triangle (the band an earlier cut left just beside a
//    vertex ring) would split off a triangle of near-zero area, or leave cut points clustered a
//    few tol round the vertex that no cap triangle can join: checked before any edit (either
//    diagonal of the split quad, every cap triangle). That vertex, if within kSnapTolerances tol,
//    is then SNAPPED: taken as on the plane where it is (not moved) and the plan made again
//    (CutStats::vertices_snapped), so a rim vertex lies within tol of the plane, or within
//    kSnapTolerances tol if snapped. Only if no snap helps: kSliverSplit. An open edge where the
//    cut passes gives kNonManifoldInput.
//  - Cuts through earlier caps are ordinary: a cap is surface like any other.
//  - Caps never contain a sliver: rim points straight up to rounding are fanned, bad triangles
//    are flipped away, and a cap that would still need a near-zero-area or tilted triangle is
//    refused (kCapTriangulationFailed; rare, bounded by the sweeps, never on generated shapes).
//  Every check runs before the first edit, so any failure leaves the mesh unchanged.
//
// Localised statuses: kSeedNotOnSurface (no triangle within the seed tolerance that
// Seed::accepts), kSeedFarFromCut (no crossing reached within 20,000 triangles of the seed,
// nearest-to-plane first), kSeedOnInnerBoundary (the seed's loop is a hole with no outer loop
// around it). A seed on a hole (the canal wall, or the inner loop where the plane meets a
// concavity) touches the material between that hole and the innermost outer loop around it: that
// outer loop is cut, as if the seed were on it.
#pragma once

#include "display/cut/cross_section.hpp"
#include "display/cut/cut_context.hpp"
#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"
#include "display/cut/seed.hpp"

namespace kerf::cut {

/// How far from the plane a vertex may be snapped onto it instead of leaving a sliver, in
/// tolerances (CutContext::tolerance_m()).
inline constexpr double kSnapTolerances = 16.0;

/// Full-plane slice: cuts every loop where the plane crosses the mesh. O(n) (classifies all
/// vertices), then O(cross-section) edits.
/// @pre `ctx` was built on the mesh to cut (and rebuilt after any garbage collection).
CutResult slice_by_plane(CutContext& ctx, const Plane& plane, CrossSection& out);

/// Localised slice (§3.7): cuts the loop reached from `seed` (when that loop is a hole, the
/// innermost outer loop around it) and every loop nested inside it (the medullary canal), leaving
/// loops outside it (other toes) bit-identical. Cost is proportional to
/// the cross-section: no pass over all vertices or faces.
/// @pre as above; `seed.point_m` lies on the surface near the plane.
CutResult slice_by_plane(CutContext& ctx, const Plane& plane, const Seed& seed, CrossSection& out);

}  // namespace kerf::cut
