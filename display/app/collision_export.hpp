// The collision mesh kerf-display publishes to kerf-rt after every topology edit: every body of a
// CutSession as plain arrays in the body's frame, with its pose and a material per triangle
// (cap faces are kCutSurface; faces whose corners are all canal wall are kCancellous; the rest
// kCortical).
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
