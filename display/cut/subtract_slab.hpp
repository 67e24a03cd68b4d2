// subtract_slab — biplanar subtraction (paper §3.4): remove the slab of material between two
// parallel planes a kerf width apart, within the localised cross-section, and cap both walls.
//
//   SlabCut slab;
//   CutResult r = subtract_slab(ctx, blade_plane, 1.0e-3, seed, slab);   // a 1 mm blade
//
// Planes: lower = plane.offset(-kerf/2), upper = plane.offset(+kerf/2). What is removed is exactly
// the slab component that holds the seed: the connected part of the material between the planes
// that the seed's face reaches. Its walls are cut on every loop that bounds it, on both planes (a
// slab through the bridge of a U meets the lower plane in two loops: both are cut), with the
// loops nested in them (the canal); a component that reaches only one plane (a tip ending inside
// the slab) has that wall alone. Found on the unedited mesh by walking the slab surface from the
// seed's face to a first wall loop, then from the loops found until no new wall loop appears. A
// seed whose face lies outside the slab starts from the lower plane's crossing nearest it.
// Everything of that component, including the two inner caps, is deleted (marked only; garbage
// collection stays the caller's choice). Material that ends inside the slab (a tip thinner than the
// kerf) is removed with it. Failure: every status the slices can return, with the mesh unchanged.
// Both walls are planned on the unedited mesh; the second is planned again after the first is cut
// (the first's split changed faces it crosses), and a refusal there undoes the first edit (the
// walls are then tried the other way round).
#pragma once

#include "display/cut/cross_section.hpp"
#include "display/cut/cut_context.hpp"
#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"
#include "display/cut/slice_by_plane.hpp"

namespace kerf::cut {

/// The two walls a slab subtraction leaves.
struct SlabCut {
    CrossSection lower;  ///< slice on the lower plane: its negative side is the remaining wall
    CrossSection upper;  ///< slice on the upper plane: its positive side is the remaining wall
};

/// Removes the slab |signed distance to `plane`| < kerf_width_m / 2 reached from `seed`.
/// @pre kerf_width_m > 0 and finite (else kInvalidArgument), much larger than ctx.tolerance_m().
CutResult subtract_slab(CutContext& ctx, const Plane& plane, double kerf_width_m, const Seed& seed,
                        SlabCut& out);

}  // namespace kerf::cut
