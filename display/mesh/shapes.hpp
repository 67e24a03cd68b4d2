// Simple closed shapes generated in code, for tests and demos: every one is watertight,
// consistently oriented with outward normals (positive signed volume), deterministic, and
// carries face and vertex normals. Lengths in metres.
#pragma once

#include <cstddef>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh {

/// Axis-aligned box from `min_m` to `max_m`, each face split into divisions × divisions
/// squares (12 · divisions² triangles).
/// @pre min_m < max_m in every coordinate; divisions >= 1
TriMesh make_box(const Point& min_m, const Point& max_m, int divisions = 1);

/// Latitude-longitude sphere around `centre_m` with about `target_triangles` triangles (at
/// least 24; exact count 2·m·(n−1) for n latitude bands and m ≈ 2n meridians, within a few
/// percent of the target above ~500).
/// @pre radius_m > 0
TriMesh make_uv_sphere(double radius_m, std::size_t target_triangles,
                       const Point& centre_m = Point{0.0, 0.0, 0.0});

/// Ring torus around the z axis through the origin: 2 · major_segments · minor_segments
/// triangles, genus 1.
/// @pre 0 < minor_radius_m < major_radius_m; major_segments >= 3; minor_segments >= 3
TriMesh make_torus(double major_radius_m, double minor_radius_m, int major_segments,
                   int minor_segments);

/// Thick-walled tube along +z from z = 0 to z = length_m: an outer cylinder (outward normals,
/// material kCortical), an inner canal cylinder (normals towards the axis, kCancellous) and an
/// annular rim at each end, so every cross-section z = c, 0 < c < length, is an annulus.
/// One closed shell of genus 1; 4 · segments · rings + 4 · segments triangles.
/// @pre 0 < inner_radius_m < outer_radius_m; length_m > 0; segments >= 3; rings >= 1
TriMesh make_hollow_tube(double length_m, double outer_radius_m, double inner_radius_m,
                         int segments, int rings);

/// Volume enclosed by a regular polygon-prism approximation, for tests: the area of a regular
/// `segments`-gon inscribed in a circle of `radius_m`.
double inscribed_polygon_area(double radius_m, int segments) noexcept;

}  // namespace kerf::mesh
