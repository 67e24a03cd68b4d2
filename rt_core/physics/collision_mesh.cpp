// Validation of collision mesh input (collision_mesh.hpp).
#include "rt_core/physics/collision_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

/// The index of the first element of `values` for which `fails` holds, or values.size(): whole
/// blocks are passed by all_pass, the first failing one is rescanned.
template <class T, class Fails>
std::size_t first_failing(std::span<const T> values, const Fails& fails) noexcept {
    constexpr std::size_t kBlock = 256;
    const auto ok = [&](const T& v) { return !fails(v); };
    std::size_t i0 = 0;
    while (i0 + kBlock <= values.size() && all_pass(values.subspan(i0, kBlock), ok)) i0 += kBlock;
    for (std::size_t i = i0; i < values.size(); ++i) {
        if (fails(values[i])) return i;
    }
    return values.size();
}

/// validate_mesh's checks in its order; the elements' (positions, indices, materials) only when
/// `elements` is set (validate_mesh_shape leaves them out).
MeshProblem validate(const CollisionMeshView& mesh, bool elements) noexcept {
    if (mesh.positions_m.size() % 3 != 0)
        return {MeshError::kPositionsNotTriples, mesh.positions_m.size()};
    if (mesh.indices.size() % 3 != 0) return {MeshError::kIndicesNotTriples, mesh.indices.size()};
    if (mesh.indices.empty()) return {MeshError::kEmpty, 0};
    if (mesh.triangle_count() > kMaxTriangles) return {MeshError::kTooLarge, mesh.triangle_count()};
    const std::span<const float> positions = mesh.positions_m;
    const std::size_t bad_position =
        elements ? first_failing(positions, [](float c) { return !position_ok(c); })
                 : positions.size();
    if (bad_position < positions.size()) {
        return {std::isfinite(positions[bad_position]) ? MeshError::kCoordinateTooLarge
                                                       : MeshError::kNonFinitePosition,
                bad_position};
    }
    const std::size_t vertices = mesh.vertex_count();
    if (elements && vertices <= std::numeric_limits<std::uint32_t>::max()) {
        const auto limit = static_cast<std::uint32_t>(vertices);
        const std::size_t bad_index =
            first_failing(mesh.indices, [limit](std::uint32_t i) { return i >= limit; });
        if (bad_index < mesh.indices.size()) return {MeshError::kIndexOutOfRange, bad_index};
    }
    if (!mesh.materials.empty()) {
        if (mesh.materials.size() != mesh.triangle_count()) {
            return {MeshError::kMaterialCount, mesh.materials.size()};
        }
        const std::size_t bad_material =
            elements ? first_failing(mesh.materials, [](Material m) { return !material_ok(m); })
                     : mesh.materials.size();
        if (bad_material < mesh.materials.size()) return {MeshError::kBadMaterial, bad_material};
    }
    if (!is_rotation(mesh.world_from_body.rotation) ||
        !is_finite(mesh.world_from_body.translation)) {
        return {MeshError::kBadTransform, 0};
    }
    return {};
}

}  // namespace

MeshProblem validate_mesh(const CollisionMeshView& mesh) noexcept { return validate(mesh, true); }

MeshProblem validate_mesh_shape(const CollisionMeshView& mesh) noexcept {
    return validate(mesh, false);
}

}  // namespace kerf::physics
