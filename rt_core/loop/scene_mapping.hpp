// kerf::rt::apply_scene_mapping — the scene's [device_mapping] and [planned_cut]
// (config/scene.hpp) turned into the loop's settings, at start-up (non-RT):
//
//   x_world = origin_m + scale * R * x_device      velocities alike; forces go back by R^T
//
// The origin defaults to 20 mm above the scene's bounds, over their centre (device_origin_above),
// so the tool starts outside the bone and reaches it by moving down. The planned cut gives the
// blade's orientation when the device senses none: columns u = edge, v = normal x edge, n = normal.
#pragma once

#include <array>
#include <string>

#include "config/scene.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/loop/haptic_loop.hpp"

namespace kerf::rt {

/// The rotation matrix of a unit quaternion (w, x, y, z).
physics::Mat3 rotation_from_quaternion(const std::array<double, 4>& wxyz) noexcept;

/// The blade axes of a planned cut: columns edge, normal x edge, normal (world frame).
physics::Mat3 blade_axes_of(const config::PlannedCut& cut) noexcept;

/// Sets settings.device_origin_in_world_m, motion_scale, blade.world_from_device and (with a
/// planned cut) blade.planned from `scene`; `mesh` is the scene's collision mesh (world frame).
void apply_scene_mapping(const config::Scene& scene, const ipc::CollisionMesh& mesh,
                         LoopSettings& settings);

/// One line for kerf-rt's start report: origin, scale, rotation, planned cut (units stated).
std::string describe_mapping(const config::Scene& scene, const LoopSettings& settings);

}  // namespace kerf::rt
