// Library-internal: the editing phase of a slice. Given a checked SectionPlan it splits the
// crossing edges, duplicates the rim vertices, detaches the two sides along the rim and caps both
// sides, in place. It cannot fail on a valid plan (a broken invariant reports kInternalError).
#pragma once

#include "display/cut/cross_section.hpp"
#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"

namespace kerf::cut::detail {

struct ContextState;

/// Applies s.plan to s.mesh, fills `out` and adds to `stats`.
CutStatus apply_plan(ContextState& s, const Plane& plane, CrossSection& out, CutStats& stats);

}  // namespace kerf::cut::detail
