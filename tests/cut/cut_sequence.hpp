// A recorded sequence of cuts, replayed on one mesh as a training session would cut it: the
// regression tests that need the earlier cuts of a random sequence to reach the failing one
// (slab_cap_wall_regression_test, slab_rim_needle_regression_test) list them as hex floats.
#pragma once

#include <cstddef>
#include <span>

#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"

namespace kerf::cut::testing {

/// One cut of a sequence.
struct SequenceCut {
    int kind;     ///< 0-3 localised (the plane point is the seed), 4 full, 5 slab
    Vec3 point;   ///< plane point and seed, m
    Vec3 normal;  ///< not normalised (Plane::make does)
};

/// Applies `cuts` in order to `ctx` (capacity grown before each, as the display's idle steps
/// do; slabs `kerf_m` wide); the index of the first that ended in kInternalError, or
/// cuts.size() when none did. Refusals are allowed: they leave the mesh unchanged.
inline std::size_t replay_cuts(CutContext& ctx, std::span<const SequenceCut> cuts, double kerf_m) {
    CrossSection cs;
    SlabCut slab;
    for (std::size_t i = 0; i < cuts.size(); ++i) {
        const SequenceCut& c = cuts[i];
        ctx.grow_capacity();
        const Plane plane = *Plane::make(c.point, c.normal);
        const Seed seed{c.point, mesh::FaceHandle(), -1.0};
        const CutResult r = c.kind < 4    ? slice_by_plane(ctx, plane, seed, cs)
                            : c.kind == 4 ? slice_by_plane(ctx, plane, cs)
                                          : subtract_slab(ctx, plane, kerf_m, seed, slab);
        if (r.status == CutStatus::kInternalError) return i;
    }
    return cuts.size();
}

}  // namespace kerf::cut::testing
