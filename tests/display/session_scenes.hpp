// Small scenes and blade events for the display tests: a thick-walled tube (a long bone with its
// canal) along +z, a second one beside it, and the events of a cut straight across.
#pragma once

#include <cmath>
#include <cstdint>

#include "display/cut/session_events.hpp"
#include "display/mesh/shapes.hpp"

namespace kerf::cut::test {

inline constexpr double kLength = 0.05;        ///< tube length, m
inline constexpr double kOuterRadius = 0.006;  ///< m
inline constexpr double kInnerRadius = 0.003;  ///< m (the canal)
inline constexpr double kCutZ = 0.0401;        ///< between two vertex rings, m
inline constexpr double kKerf = 1.0e-3;        ///< a 1 mm blade
inline constexpr double kSecondX = 0.1;        ///< the second tube's axis, m

/// One tube, 64 segments x 60 rings (~15k triangles).
inline mesh::TriMesh tube(int segments = 64, int rings = 60) {
    return mesh::make_hollow_tube(kLength, kOuterRadius, kInnerRadius, segments, rings);
}

/// Two tubes side by side: body 0 on the z axis, body 1 at x = kSecondX.
inline mesh::TriMesh two_tubes() {
    mesh::TriMesh a = tube();
    const mesh::TriMesh b = tube();
    const int offset = static_cast<int>(a.n_vertices());
    for (const auto v : b.vertices()) {
        const auto w = a.add_vertex(b.point(v) + mesh::Point(kSecondX, 0, 0));
        a.set_normal(w, b.normal(v));
        a.set_texcoord2D(w, b.texcoord2D(v));
        a.set_color(w, b.color(v));
        a.data(w).set_material(b.data(v).material());
    }
    for (const auto f : b.faces()) {
        std::vector<mesh::VertexHandle> corners;
        for (const auto v : b.fv_range(f)) corners.emplace_back(v.idx() + offset);
        a.add_face(corners);
    }
    a.update_face_normals();
    return a;
}

/// The blade lying in z = kCutZ with its length axis at `angle_rad` from +x.
inline BladeFrame blade_across(double angle_rad, double x_m = 0.0) {
    return BladeFrame{Vec3(x_m, 0, kCutZ), Vec3(0, 0, 1),
                      Vec3(std::cos(angle_rad), std::sin(angle_rad), 0)};
}

/// CutBegin across body 0 at z = kCutZ, touching at (kOuterRadius, 0, kCutZ).
inline CutBegin begin_across(std::uint32_t cut_id) {
    CutBegin b;
    b.cut_id = cut_id;
    b.body_id = 0;
    b.blade = blade_across(0.0);
    b.seed_m = Vec3(kOuterRadius, 0, kCutZ);
    b.kerf_width_m = kKerf;
    return b;
}

}  // namespace kerf::cut::test
