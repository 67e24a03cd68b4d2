// validate() — measures a triangle mesh: counts, closedness, manifoldness, orientation,
// degenerate triangles, shells (connected components), bounding box, area and volume.
//
// Definitions (they match the checker behind ../shared/meshes/README.md):
// - an edge is a boundary edge when one triangle uses it, manifold when two do, non-manifold
//   when three or more do; the mesh is *closed* when every edge is manifold;
// - it is *oriented* when every manifold edge is traversed once in each direction;
// - a vertex is non-manifold when the triangles around it form more than one fan (two cones
//   touching at their tips), or it lies on a non-manifold edge;
// - a triangle is degenerate when two of its indices are equal or twice its area is at most
//   kDegenerateTwiceAreaRelative × (bounding-box diagonal)²;
// - shells are the connected components of triangles sharing vertices;
// - signed volume is measured about the bounding-box centre (exact for closed shells; for an
//   open mesh it is a number, not a volume); positive means outward normals.
// Deterministic: the same mesh gives the same report, bit for bit.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "config/base/length_unit.hpp"
#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh {

/// The project's one degenerate-triangle threshold: a triangle is degenerate when twice its area
/// is at most this × (bounding-box diagonal)². validate() counts such triangles; kerf::cut never
/// makes one (it checks every triangle a cut creates against this, relative to the diagonal of
/// the mesh it cuts, which bounds every piece's); the cut tests check every mesh with it.
inline constexpr double kDegenerateTwiceAreaRelative = 1e-12;

/// One connected component.
struct ShellSummary {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;
    bool closed = false;
    long euler_characteristic = 0;  ///< V − E + F; genus = (2 − χ) / 2 when closed
    double area_m2 = 0.0;
    double volume_m3 = 0.0;
};

struct ValidationReport {
    std::size_t vertices = 0;               ///< vertices after welding
    std::size_t unreferenced_vertices = 0;  ///< vertices no triangle uses
    std::size_t triangles = 0;
    std::size_t edges = 0;  ///< distinct undirected edges
    std::size_t boundary_edges = 0;
    std::size_t non_manifold_edges = 0;
    std::size_t non_manifold_vertices = 0;
    std::size_t misoriented_edges = 0;  ///< manifold edges traversed twice the same way
    std::size_t degenerate_triangles = 0;
    std::size_t detached_triangles = 0;  ///< set by loaders: triangles OpenMesh refused
    bool closed = false;
    bool oriented = false;
    Point bbox_min_m{0.0, 0.0, 0.0};
    Point bbox_max_m{0.0, 0.0, 0.0};
    double area_m2 = 0.0;
    double volume_m3 = 0.0;
    std::vector<ShellSummary> shells;  ///< largest first (triangles, then first triangle)
    /// Endpoints of the first boundary edges (at most 16), to say where a hole is.
    std::vector<std::array<Point, 2>> boundary_samples_m;
};

/// Measures an indexed mesh (what a file holds).
/// @pre every triangle index < in.positions_m.size()
ValidationReport validate(const IndexedMesh& in);

/// Measures a half-edge mesh (deleted elements are ignored).
ValidationReport validate(const TriMesh& mesh);

/// Several lines for people, lengths shown in `units` (mm for most bone files).
std::string format_report_text(const ValidationReport& r,
                               LengthUnit units = LengthUnit::kMillimetre);

/// One JSON object, SI units (keys end in _m, _m2, _m3).
std::string format_report_json(const ValidationReport& r);

}  // namespace kerf::mesh
