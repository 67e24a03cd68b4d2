// kerf::cut::Seed — where the blade first touched the bone: the start of a localised cut
// (slice_by_plane, subtract_slab). Lengths in metres.
#pragma once

#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

/// Where the blade first touched: a point on the surface and, optionally, its triangle.
struct Seed {
    Vec3 point_m;                ///< contact point, m (within seed tolerance of the surface)
    mesh::FaceHandle face_hint;  ///< the triangle containing it, if known (else invalid)
    double tolerance_m = -1.0;   ///< max seed-to-surface distance; < 0: 1e-3 * mesh scale
};

}  // namespace kerf::cut
