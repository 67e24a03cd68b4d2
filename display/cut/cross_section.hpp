// kerf::cut::CrossSection — what a slice made, for capping, gradual separation and rendering.
//
// A slice splits the triangles crossing the plane and then DUPLICATES every cross-section (rim)
// vertex: the positive side keeps one copy, the negative side gets the other, so the two sides
// share no vertex. Each side is closed by its own cap, built on that side's rim vertices (the cap
// shares the rim vertices, so every piece stays one closed 2-manifold in OpenMesh).
//
// Pairing rule: positive.loops[i][j] and negative.loops[i][j] are the two copies of the same rim
// point (bit-identical positions and attributes right after the slice) and loops_2d[i][j] is that
// point in the plane's (u, v) frame. Loops are ordered along the positive side's rim halfedges:
// outer loops run counter-clockwise in (u, v), holes clockwise (loop_is_hole[i]).
//
// Cap faces: positive-side caps face -normal, negative-side caps face +normal; each cap face has
// the face property named kCapFaceProperty set to kCapPositive / kCapNegative (0 elsewhere). The
// renderer shades those faces as cut bone (material kCutSurface, face normal, planar texture
// coordinates (u, v) / texture scale).
#pragma once

#include <cstdint>
#include <vector>

#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

/// Name of the per-face std::uint8_t property that marks cap faces.
inline constexpr const char* kCapFaceProperty = "kerf:cap_face";
inline constexpr std::uint8_t kCapNone = 0;      ///< not a cap face
inline constexpr std::uint8_t kCapPositive = 1;  ///< cap of the positive side (faces -normal)
inline constexpr std::uint8_t kCapNegative = 2;  ///< cap of the negative side (faces +normal)

/// One side of a cut: its rim loops and its cap.
struct CrossSectionSide {
    std::vector<std::vector<mesh::VertexHandle>> loops;  ///< rim vertices of each loop, in order
    std::vector<mesh::VertexHandle> cap_vertices;  ///< every vertex the cap uses (= rim vertices)
    std::vector<mesh::FaceHandle> cap_faces;       ///< the cap's triangles
};

/// The cross-section a slice produced (see the file comment for the pairing rule).
struct CrossSection {
    Plane plane;                              ///< the cutting plane and its (u, v) frame
    CrossSectionSide positive;                ///< the side the normal points into
    CrossSectionSide negative;                ///< the other side
    std::vector<std::vector<Vec2>> loops_2d;  ///< rim points in plane coordinates, m
    std::vector<std::uint8_t> loop_is_hole;   ///< 1 where loop i bounds a hole (canal)

    /// Empties every list (keeps capacity for reuse).
    void clear() noexcept;
};

}  // namespace kerf::cut
