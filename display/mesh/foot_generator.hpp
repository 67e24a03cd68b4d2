// generate_foot() — the built-in synthetic forefoot: Kerf's default scene, so the demo needs no
// external file.
//
// Frame (metres, right foot, like ../shared/meshes/bp3d_right_forefoot_24shells.stl): toes point
// along +z, the hallux (ray 1) lies on the +x side, +y is dorsal (up). Metatarsal bases sit near
// z = 0, toe tips near z = 0.13; the five rays lie side by side at y = 0, x from about +0.030
// (ray 1) to -0.035 (ray 5).
//
// 19 bones: per ray a metatarsal, a proximal, a middle (rays 2-5 only) and a distal phalanx.
// Each bone is two closed shells: a cortical outer surface (a tube with flared, rounded ends,
// outward normals, material kCortical) and a medullary canal inside its shaft (a closed surface
// with inward normals, kCancellous), so a cut across a shaft shows an annulus. 38 shells in all,
// each closed and consistently oriented, no two intersecting; total signed volume > 0.
// Deterministic: the same parameters give the same mesh, bit for bit, on every platform (the
// seed drives a small per-bone variation of length, radius, ellipticity and placement).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/result.hpp"
#include "display/mesh/foot_range.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh {

struct FootParams {
    std::size_t target_triangles =
        200'000;  ///< met within 2 %; [kFootMinTriangles, kFootMaxTriangles]
    std::uint64_t seed = 1;
};

enum class BoneKind : std::uint8_t {
    kMetatarsal,
    kProximalPhalanx,
    kMiddlePhalanx,
    kDistalPhalanx,
};
std::string_view to_string(BoneKind kind) noexcept;

/// Where one bone is, for placing cuts: its axis runs from `base_m` (proximal) to `head_m`.
struct BoneInfo {
    int ray = 1;  ///< 1 = hallux ... 5 = little toe
    BoneKind kind = BoneKind::kMetatarsal;
    Point base_m{0, 0, 0};      ///< proximal end of the axis (the bone's pole)
    Point head_m{0, 0, 0};      ///< distal end of the axis
    double length_m = 0;        ///< |head − base|
    double shaft_radius_m = 0;  ///< outer radius at mid-shaft (mean of the ellipse axes)
    double max_radius_m = 0;    ///< largest outer radius (at the flared ends)
    double canal_radius_m = 0;  ///< medullary canal radius (mean of the ellipse axes)
    double canal_start_m = 0;   ///< canal extent along the axis, from base_m
    double canal_end_m = 0;
    std::size_t first_triangle = 0;  ///< the bone's triangles: outer shell, then canal
    std::size_t triangle_count = 0;
};

struct Foot {
    TriMesh mesh;
    std::vector<BoneInfo> bones;  ///< ray 1 first, proximal to distal within a ray

    /// The first metatarsal (ray 1), where a chevron osteotomy is cut.
    const BoneInfo& first_metatarsal() const { return bones.front(); }
};

/// Builds the forefoot; an error message when the triangle target is out of range.
Result<Foot, std::string> generate_foot(const FootParams& params);

}  // namespace kerf::mesh
