// kerf::cut::Seed — where the blade first touched the bone: the start of a localised cut
// (slice_by_plane, subtract_slab). Lengths in metres.
#pragma once

#include <functional>

#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

/// Default seed tolerance (Seed::tolerance_m < 0), relative to the mesh scale (its bounding-box
/// diagonal).
inline constexpr double kSeedRelativeTolerance = 1e-3;

/// Where the blade first touched: a point on the surface and, optionally, its triangle.
struct Seed {
    Vec3 point_m;                ///< contact point, m (within seed tolerance of the surface)
    mesh::FaceHandle face_hint;  ///< the triangle containing it, if known (else invalid)
    /// Max seed-to-surface distance, m; < 0: kSeedRelativeTolerance * the mesh scale.
    double tolerance_m = -1.0;
    /// When set, the only faces the seed may lie on (e.g. one body's, where pieces lie close).
    std::function<bool(mesh::FaceHandle)> accepts = {};
};

}  // namespace kerf::cut
