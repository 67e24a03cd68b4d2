// Library-internal: a slice across an earlier cap puts one chord into that cap instead of
// splitting the cap's triangles one by one.
//
// The faces of an earlier cap are coplanar. Where the new plane crosses a run of them (entering
// through an edge or vertex of the cap's rim or of a crease, leaving through another, crossing
// only inner edges of the cap between: edges whose two faces carry the same cap tag and the same
// stored cap normal), the plan would put a cut point on every inner edge crossed: those points lie
// on the line where the two planes meet, the new cap's rim gets a collinear run across the old
// cap (fanned from a far apex: needles), and a thin triangle of the old cap crossed near one end
// is split into a sliver. Instead, before the plan is finished, the two ends of the run become
// vertices (an end on an edge splits that edge, as the edit would) and the segment between them
// is made an edge of the old cap by flipping the inner edges it crosses (Sloan's constrained edge
// insertion; each flip trades the diagonal of a convex planar quad, so the surface stays where it
// is). The plan made again then meets the old cap only along that edge: two rim points, no split
// cap triangle. Every edit is recorded in an EditUndo first; a run that cannot take its chord (an
// end or a crossed vertex too close to the line, no crossed quad convex, a resulting triangle too
// small or tilted, the chord's faces not on both sides of the plane, flips moving more than a
// rounding's volume) is undone alone and left to the usual split; when no chord is put in, or the
// plan on them is refused, every chord is undone and the slice is planned the usual way.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "display/cut/cut_result.hpp"
#include "display/cut/edit_undo.hpp"
#include "display/cut/plane.hpp"

namespace kerf::cut::detail {

struct ContextState;

/// Whether the selected loops of s.plan cross an inner edge of an earlier cap (both its faces cap
/// faces with the same tag and the same stored normal). O(points of the selected loops).
bool crosses_cap_inner_edges(const ContextState& s);

/// Puts into the mesh the chord of `plane` across every run of inner cap edges the selected loops
/// of s.plan cross that takes one (see the file comment), recording every edit in `undo` before it
/// is made (a run that fails is undone to a checkpoint of its own). The number of chords put in;
/// 0 leaves the mesh as it was.
std::uint32_t insert_cap_chords(ContextState& s, const Plane& plane, EditUndo& undo);

/// plan_snapped (section_plan.hpp) through the chords: when the slice crosses inner edges of an
/// earlier cap, the chords are put in (recorded in `undo`) and the slice planned on that mesh;
/// when that is refused or no chord can be put in, the chords are undone and the slice is planned
/// on the mesh as it was, exactly as plan_snapped would have planned it. With no earlier cap
/// (`s.cap_faces` empty) or s.cap_chords off it is plan_snapped. On kOk the plan is current,
/// `chords` says how many chords it stands on (0: none, the mesh is as it was) and `undo` holds
/// their records (a caller that refuses later restores it).
CutStatus plan_through_caps(ContextState& s, const Plane& plane, std::vector<std::int32_t>& snapped,
                            const std::function<CutStatus()>& plan, EditUndo& undo,
                            std::uint32_t& chords, bool merges_first_last = true);

}  // namespace kerf::cut::detail
