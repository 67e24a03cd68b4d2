// load_scene_arrays() — the meshes of a scene as plain indexed arrays, for processes that must not
// see OpenMesh (kerf-rt builds its collision structure from these). The same loader and generator
// as the display use, so both start from the same deterministic mesh; only the return type differs.
// This header includes no OpenMesh header.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "config/expand_path.hpp"
#include "config/scene.hpp"

namespace kerf::mesh {

/// One body: positions in its own frame (m), triangles, a material per triangle
/// (mesh::Material values: 0 cortical, 1 cancellous, 2 cut surface) and its placement.
struct BodyArrays {
    std::string name;
    std::vector<float> positions_m;           ///< x y z per vertex, body frame, m
    std::vector<std::uint32_t> indices;       ///< 3 per triangle, file winding (outward)
    std::vector<std::uint8_t> materials;      ///< one per triangle
    std::array<float, 16> world_from_body{};  ///< column-major rigid transform, translation in m
};

/// Loads or generates every body of `scene` (files found through `vars`). Errors name the body
/// and what failed.
Result<std::vector<BodyArrays>, std::string> load_scene_arrays(const config::Scene& scene,
                                                               const config::PathVars& vars);

}  // namespace kerf::mesh
