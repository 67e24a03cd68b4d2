// kerf::firmware_host::Vec3 — the one 3-vector of the device side (firmware_host, kerf-hapsim):
// x, y, z in the device's Cartesian frame, units named by the field (position_m, force_n).
// The other domains have their own, one each: OpenMesh::Vec3d on the mesh side (display/mesh,
// display/cut, where it is spelt cut::Vec3) and physics::Vec3 in the real-time core
// (rt_core/physics/vec3.hpp); code that joins two domains converts field by field.
#pragma once

#include <array>

namespace kerf::firmware_host {

/// A 3-vector of doubles, e.g. a position in m or a force in N.
using Vec3 = std::array<double, 3>;

}  // namespace kerf::firmware_host
