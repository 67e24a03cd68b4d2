// The size range of the built-in forefoot generator (foot_generator.hpp), on its own and
// dependency-free so the scene loader (config/scene.cpp) checks a scene's `target_triangles`
// against the generator's own range without linking the mesh library.
#pragma once

#include <cstddef>

namespace kerf::mesh {

/// Fewest triangles generate_foot() builds.
inline constexpr std::size_t kFootMinTriangles = 10'000;
/// Most triangles generate_foot() builds.
inline constexpr std::size_t kFootMaxTriangles = 4'000'000;

}  // namespace kerf::mesh
