// append_body() — packs one body's plain arrays into an ipc::CollisionMesh, the form both the
// mailbox and kerf-rt's start-up scene take, so the scene kerf-rt loads itself and the meshes the
// display publishes go through the same validation and the same WorldBuilder. Non-RT.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "config/base/result.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/physics/vec3.hpp"

namespace kerf::rt {

/// Appends a body (positions m body frame, 3 indices per triangle, a TriangleMaterial per
/// triangle, column-major world_from_body). Refuses what the mailbox could not hold.
Status<std::string> append_body(ipc::CollisionMesh& mesh, std::span<const float> positions_m,
                                std::span<const std::uint32_t> indices,
                                std::span<const std::uint8_t> materials,
                                const std::array<float, 16>& world_from_body);

/// Where kerf-rt puts the device origin in the world: `clearance_m` above (+y) the top of the
/// mesh's world bounds, over their centre, so the tool starts outside the bone and reaches it by
/// moving down (-y).
physics::Vec3 device_origin_above(const ipc::CollisionMesh& mesh, double clearance_m = 0.02);

}  // namespace kerf::rt
