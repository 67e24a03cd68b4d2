// Internal: surfaces of revolution as index grids, shared by shapes.cpp and foot_generator.cpp.
#pragma once

#include <vector>

#include "display/mesh/indexed_mesh.hpp"

namespace kerf::mesh::detail {

/// An orthonormal frame: a point = origin + axial·axis + radial·(cos θ·u + sin θ·w).
/// @pre u × w == axis
struct AxisFrame {
    Point origin;
    Point axis;
    Point u;
    Point w;
};

/// One ring of a profile: distance along the axis and radius (metres). Radius 0 makes a pole.
struct ProfileSample {
    double axial_m;
    double radius_m;
};

/// Appends a ring of `segments` vertices (one vertex when radius is 0); returns its first index.
std::uint32_t add_ring(IndexedMesh& out, const AxisFrame& f, const ProfileSample& s, int segments,
                       Material material);

/// Appends the triangles joining ring `a` to ring `b` (b further along the axis). Either ring
/// may be a single pole vertex. `outward` = normals away from the axis for a < b in axial order.
void join_rings(IndexedMesh& out, std::uint32_t a, bool a_pole, std::uint32_t b, bool b_pole,
                int segments, bool outward);

/// Appends a closed surface of revolution; the first and last samples must have radius 0.
/// `outward` false reverses it (a cavity). Triangles: 2 · segments · (samples − 2).
/// @pre profile.size() >= 3; profile.front() and profile.back() have radius 0
void add_closed_revolved(IndexedMesh& out, const AxisFrame& f,
                         const std::vector<ProfileSample>& profile, int segments, bool outward,
                         Material material);

}  // namespace kerf::mesh::detail
