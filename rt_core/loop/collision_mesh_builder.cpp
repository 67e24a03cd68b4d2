#include "rt_core/loop/collision_mesh_builder.hpp"

#include <algorithm>

namespace kerf::rt {

Status<std::string> append_body(ipc::CollisionMesh& mesh, std::span<const float> positions_m,
                                std::span<const std::uint32_t> indices,
                                std::span<const std::uint8_t> materials,
                                const std::array<float, 16>& world_from_body) {
    const std::size_t vertices = positions_m.size() / 3;
    if (mesh.body_count >= ipc::kMeshMaxBodies ||
        mesh.vertex_count + vertices > ipc::kMeshMaxVertices ||
        mesh.index_count + indices.size() > ipc::kMeshMaxIndices) {
        return Err{"body " + std::to_string(mesh.body_count) + " (" + std::to_string(vertices) +
                   " vertices, " + std::to_string(indices.size() / 3) +
                   " triangles) does not fit the collision mesh capacity (" +
                   std::to_string(ipc::kMeshMaxVertices) + " vertices, " +
                   std::to_string(ipc::kMeshMaxTriangles) + " triangles over all bodies)"};
    }
    if (positions_m.size() % 3 != 0 || indices.size() % 3 != 0 ||
        materials.size() != indices.size() / 3) {
        return Err{"body " + std::to_string(mesh.body_count) +
                   ": arrays are not whole vertices / triangles / one material per triangle"};
    }
    ipc::MeshBodyEntry& e = mesh.bodies[mesh.body_count];
    e = ipc::MeshBodyEntry{};
    e.vertex_offset = mesh.vertex_count;
    e.vertex_count = std::uint32_t(vertices);
    e.index_offset = mesh.index_count;
    e.index_count = std::uint32_t(indices.size());
    std::copy(world_from_body.begin(), world_from_body.end(), e.world_from_body);
    std::copy(positions_m.begin(), positions_m.end(),
              mesh.vertices_m.begin() + 3 * mesh.vertex_count);
    std::copy(indices.begin(), indices.end(), mesh.indices.begin() + mesh.index_count);
    std::copy(materials.begin(), materials.end(), mesh.materials.begin() + mesh.index_count / 3);
    mesh.vertex_count += e.vertex_count;
    mesh.index_count += e.index_count;
    ++mesh.body_count;
    return {};
}

physics::Vec3 device_origin_above(const ipc::CollisionMesh& mesh, double clearance_m) {
    physics::Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (std::uint32_t b = 0; b < mesh.body_count; ++b) {
        const ipc::MeshBodyEntry& e = mesh.bodies[b];
        const auto pose = physics::RigidTransform::from_column_major(e.world_from_body);
        for (std::uint32_t v = e.vertex_offset; v < e.vertex_offset + e.vertex_count; ++v) {
            const physics::Vec3 p = pose.apply(
                {mesh.vertices_m[3 * v], mesh.vertices_m[3 * v + 1], mesh.vertices_m[3 * v + 2]});
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
        }
    }
    return {(lo.x + hi.x) / 2, hi.y + clearance_m, (lo.z + hi.z) / 2};
}

}  // namespace kerf::rt
