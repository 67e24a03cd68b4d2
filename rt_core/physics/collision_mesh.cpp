// Validation of collision mesh input (collision_mesh.hpp).
#include "rt_core/physics/collision_mesh.hpp"

#include <cmath>

namespace kerf::physics {

std::string_view to_string(Material material) noexcept {
    switch (material) {
        case Material::kCortical:
            return "cortical";
        case Material::kCancellous:
            return "cancellous";
        case Material::kCutSurface:
            return "cut surface";
    }
    return "unknown material";
}

std::string_view to_string(MeshError error) noexcept {
    switch (error) {
        case MeshError::kNone:
            return "no error";
        case MeshError::kEmpty:
            return "mesh has no triangle";
        case MeshError::kPositionsNotTriples:
            return "position count is not a multiple of 3";
        case MeshError::kIndicesNotTriples:
            return "index count is not a multiple of 3";
        case MeshError::kIndexOutOfRange:
            return "triangle index out of range";
        case MeshError::kNonFinitePosition:
            return "position is not finite";
        case MeshError::kCoordinateTooLarge:
            return "coordinate beyond 10 m";
        case MeshError::kMaterialCount:
            return "material count differs from triangle count";
        case MeshError::kBadMaterial:
            return "material value outside the enum";
        case MeshError::kTooLarge:
            return "too many triangles";
        case MeshError::kBadTransform:
            return "world_from_body is not a finite rotation";
    }
    return "unknown mesh error";
}

namespace {

bool is_rotation(const Mat3& r) noexcept {
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (!std::isfinite(r.m[i][j])) return false;
            const double d = dot(r.column(i), r.column(j)) - (i == j ? 1.0 : 0.0);
            if (std::abs(d) > 1e-4) return false;
        }
    }
    return dot(cross(r.column(0), r.column(1)), r.column(2)) > 0;
}

}  // namespace

MeshProblem validate_mesh(const CollisionMeshView& mesh) noexcept {
    if (mesh.positions_m.size() % 3 != 0)
        return {MeshError::kPositionsNotTriples, mesh.positions_m.size()};
    if (mesh.indices.size() % 3 != 0) return {MeshError::kIndicesNotTriples, mesh.indices.size()};
    if (mesh.indices.empty()) return {MeshError::kEmpty, 0};
    if (mesh.triangle_count() > kMaxTriangles) return {MeshError::kTooLarge, mesh.triangle_count()};
    for (std::size_t i = 0; i < mesh.positions_m.size(); ++i) {
        const float c = mesh.positions_m[i];
        if (!std::isfinite(c)) return {MeshError::kNonFinitePosition, i};
        if (std::abs(c) > kMaxCoordinate_m) return {MeshError::kCoordinateTooLarge, i};
    }
    const std::size_t vertices = mesh.vertex_count();
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= vertices) return {MeshError::kIndexOutOfRange, i};
    }
    if (!mesh.materials.empty()) {
        if (mesh.materials.size() != mesh.triangle_count()) {
            return {MeshError::kMaterialCount, mesh.materials.size()};
        }
        for (std::size_t i = 0; i < mesh.materials.size(); ++i) {
            if (static_cast<std::uint8_t>(mesh.materials[i]) > 2)
                return {MeshError::kBadMaterial, i};
        }
    }
    if (!is_rotation(mesh.world_from_body.rotation) ||
        !is_finite(mesh.world_from_body.translation)) {
        return {MeshError::kBadTransform, 0};
    }
    return {};
}

}  // namespace kerf::physics
