// Library-internal: the editing phase of a slice. Given a checked SectionPlan it splits the
// crossing edges, duplicates the rim vertices, detaches the two sides along the rim and caps both
// sides, in place. It cannot fail on a valid plan (a broken invariant reports kInternalError).
#pragma once

#include "display/cut/cross_section.hpp"
#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"
#include "display/cut/section_plan.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

struct ContextState;

/// A new vertex for edge cut point p, as the edit makes one (add_vertex; every attribute
/// interpolated with p.t from the lower-index endpoint p.a towards p.b, the material the nearer
/// endpoint's).
mesh::VertexHandle make_cut_vertex(mesh::TriMesh& m, const PlanPoint& p);

/// Applies s.plan to s.mesh, fills `out` and adds to `stats`.
CutStatus apply_plan(ContextState& s, const Plane& plane, CrossSection& out, CutStats& stats);

}  // namespace kerf::cut::detail
