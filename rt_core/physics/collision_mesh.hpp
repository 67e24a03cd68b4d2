// The collision mesh of one rigid body as kerf_physics takes it: flat arrays (the shape the
// display publishes through rt_core/ipc/mesh_mailbox), never OpenMesh. Positions in metres in the
// body frame; triangles counter-clockwise seen from outside (outward normals); one material per
// triangle. A view borrows the caller's arrays; the collision structure copies what it keeps.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "rt_core/physics/vec3.hpp"

namespace kerf::physics {

/// What a triangle's surface is made of; decides feed resistance under the saw. Values equal
/// ipc::TriangleMaterial's, so the mailbox's material bytes may be viewed as Material
/// (validate_mesh refuses values outside the enum).
enum class Material : std::uint8_t {
    kCortical = 0,    ///< dense outer bone (the default surface)
    kCancellous = 1,  ///< spongy inner bone
    kCutSurface = 2,  ///< a cap left by an earlier cut (cancellous inside a cortical rim)
};
std::string_view to_string(Material material) noexcept;

/// One body's mesh, borrowed: x y z per vertex (m, body frame), 3 indices per triangle.
struct CollisionMeshView {
    std::span<const float> positions_m;      ///< 3 floats per vertex, body frame, m
    std::span<const std::uint32_t> indices;  ///< 3 per triangle, outward (CCW) winding
    std::span<const Material> materials;     ///< one per triangle; empty = all kCortical
    RigidTransform world_from_body;          ///< the body's pose when the mesh was published

    std::size_t vertex_count() const noexcept { return positions_m.size() / 3; }
    std::size_t triangle_count() const noexcept { return indices.size() / 3; }
};

/// Why a mesh was refused.
enum class MeshError : std::uint8_t {
    kNone = 0,
    kEmpty,                ///< no triangle
    kPositionsNotTriples,  ///< positions_m.size() is not a multiple of 3
    kIndicesNotTriples,    ///< indices.size() is not a multiple of 3
    kIndexOutOfRange,      ///< an index >= vertex_count()
    kNonFinitePosition,    ///< NaN or infinity in positions_m
    kCoordinateTooLarge,   ///< |coordinate| > kMaxCoordinate_m
    kMaterialCount,        ///< materials neither empty nor one per triangle
    kBadMaterial,          ///< a material value outside the enum
    kTooLarge,             ///< more than kMaxTriangles triangles
    kBadTransform,         ///< world_from_body not finite or not a rotation
};
std::string_view to_string(MeshError error) noexcept;

inline constexpr float kMaxCoordinate_m = 10.0f;                    ///< bound on |x|, |y|, |z|
inline constexpr std::size_t kMaxTriangles = std::size_t{1} << 26;  ///< 67M triangles

/// Details of a refusal: what and where (the first offending element).
struct MeshProblem {
    MeshError error = MeshError::kNone;
    std::size_t index = 0;  ///< the offending float, index, material or triangle
};

/// Checks every size, index, coordinate, material and the transform; kNone when usable.
/// Pure, O(size), allocation-free.
MeshProblem validate_mesh(const CollisionMeshView& mesh) noexcept;

/// validate_mesh's checks that read no element: sizes, counts and the transform. A mesh that
/// passes them and whose every element passes position_ok, index_ok and material_ok passes
/// validate_mesh (for callers that check only the elements that changed since a mesh passed).
MeshProblem validate_mesh_shape(const CollisionMeshView& mesh) noexcept;
/// Whether validate_mesh accepts a coordinate: finite and within kMaxCoordinate_m (branch-free).
inline bool position_ok(float c) noexcept { return std::abs(c) <= kMaxCoordinate_m; }
/// Whether validate_mesh accepts a material value.
inline bool material_ok(Material m) noexcept { return static_cast<std::uint8_t>(m) <= 2; }

/// Whether every element of `values` passes `ok`, tested in fixed-size blocks without branches
/// (the loop vectorises).
template <class T, class Ok>
bool all_pass(std::span<const T> values, const Ok& ok) noexcept {
    constexpr std::size_t kBlock = 256;
    std::size_t i0 = 0;
    for (; i0 + kBlock <= values.size(); i0 += kBlock) {
        unsigned fails = 0;
        for (std::size_t i = 0; i < kBlock; ++i) fails |= ok(values[i0 + i]) ? 0u : 1u;
        if (fails) return false;
    }
    for (std::size_t i = i0; i < values.size(); ++i) {
        if (!ok(values[i])) return false;
    }
    return true;
}

}  // namespace kerf::physics
