// kerf::mesh::bone_size_warning — catches a file read in the wrong unit: STL carries none, so a
// metres file read as millimetres (the default) loads as a 0.2 mm "foot". Used by `kerf mesh info`
// and `kerf cut`, which print it as a warning on stderr.
#pragma once

#include <string>

#include "config/base/length_unit.hpp"

namespace kerf::mesh {

/// Sizes a bone (or a whole foot) plausibly has: largest bounding-box side, metres.
inline constexpr double kMinBoneSize_m = 0.002;
inline constexpr double kMaxBoneSize_m = 1.0;

/// A warning when a mesh whose largest bounding-box side is `size_m` (read as `units`) is too
/// small or too large for a bone, naming the unit that would make it one ("" when plausible).
std::string bone_size_warning(double size_m, LengthUnit units);

}  // namespace kerf::mesh
