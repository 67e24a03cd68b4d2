// The collision mesh kerf-display publishes to kerf-rt after every topology edit: every body of a
// CutSession as plain arrays in the body's frame, with its pose and a material per triangle
// (cap faces are kCutSurface; faces whose corners are all canal wall are kCancellous; the rest
// kCortical).
//
// A withdrawn or aborted cut is closed in the collision mesh (CutSession::withdrawn_cuts()):
// cap vertices within half its kerf of its plane go onto the plane, and both copies of each of
// its rim points are written at their mean, so its two caps coincide and its sides meet edge to
// edge. Why: caps are built on rim points only, so the display's separation opens a withdrawn cut
// as thin wedges from the rim the blade swept across the whole section, and a later cut that
// crosses them leaves its own rim points on the opened caps; a point proxy slid along them up to
// 6.6 mm into bone the blade never touched and trailed the tool by 45 mm (bench_physics
// BM_TickAfterCuts, tests/rt/withdrawn_cut_contact_test.cpp). The rendered mesh keeps the
// opening; the collision mesh is the bone as if the withdrawn kerf (0.8 mm wide) were not there,
// what a tool tip wider than the kerf feels. Triangles keep their count and order (a CutBegin's
// triangle hint indexes them).
//
//   ipc::CollisionMesh out;                             // sized once to the mailbox capacity
//   if (auto ok = export_collision(session, out); ok) writer.publish(out);
#pragma once

#include <cstddef>
#include <string>

#include "config/base/result.hpp"
#include "display/cut/cut_session.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"

namespace kerf::display {

/// Why a mesh of `bodies` bodies, `vertices` vertices and `triangles` triangles (deleted
/// elements included, as OpenMesh counts them) does not fit the mailbox; empty when it fits.
std::string mailbox_misfit(std::size_t bodies, std::size_t vertices, std::size_t triangles);

/// Fills `out` (counts, bodies, vertices, indices, materials; generation left to the writer).
/// Fails, naming the count, when the scene has more bodies, vertices or triangles than the
/// mailbox holds (`out` is then unspecified). O(V + F).
Status<std::string> export_collision(const cut::CutSession& session, ipc::CollisionMesh& out);

}  // namespace kerf::display
