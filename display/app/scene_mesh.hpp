// The scene's bones as one mesh in the world frame: what kerf-display (and the tests that check
// it) start every CutSession from. Deterministic: the same configuration gives the same mesh.
#pragma once

#include <string>

#include "config/base/result.hpp"
#include "config/load_config.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::display {

/// Loads or generates every body of `config.scene` (files in their units, the built-in foot from
/// its seed), places each by its rigid transform and appends them in scene order.
/// Fails with one line naming the body and what went wrong.
Result<mesh::TriMesh, std::string> build_scene_mesh(const config::Config& config);

}  // namespace kerf::display
