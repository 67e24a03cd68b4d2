// Strict checkers for meshes after cuts, shared by every cut test (in the spirit of manifold's
// `CheckStrictly` and geometry-central's validate-after-every-flip).
//
//   const auto report = kerf::cut::testing::expect_closed_2_manifold(mesh);
//   EXPECT_EQ(report.piece_volumes_m3.size(), 2u);
//
// "Closed, consistently oriented 2-manifold" here means, over the faces not marked deleted:
//  - every undirected edge {a, b} is used by exactly two faces, once as a->b and once as b->a;
//  - OpenMesh agrees: no face halfedge has a boundary opposite, and every used vertex's one-ring
//    (its circulator) visits exactly the faces that use it (one fan, no pinch);
//  - no triangle is non-finite or of near-zero area (< kMinRelativeArea * bbox diagonal^2).
// Each piece (face-connected component) gets its signed volume (a canal shell on its own is
// negative: its normals face inwards); flipped triangles are caught by expect_face_normals_agree.
#pragma once

#include <gtest/gtest.h>

#include "display/mesh/tri_mesh.hpp"
#include "tests/cut/mesh_invariants.hpp"

namespace kerf::cut::testing {

/// Runs check_closed_2_manifold(), reports its failures through gtest and returns the
/// measurements.
inline MeshReport expect_closed_2_manifold(const kerf::mesh::TriMesh& mesh) {
    MeshReport r = check_closed_2_manifold(mesh);
    if (!r.ok) ADD_FAILURE() << "mesh check: " << r.failures << " failure(s):\n" << r.failures_log;
    return r;
}

/// Every non-deleted face's stored normal agrees with its winding (no flipped triangle).
inline void expect_face_normals_agree(const kerf::mesh::TriMesh& mesh) {
    int failures = 0;
    int first = -1;
    for (auto f : mesh.faces()) {
        auto it = mesh.cfv_iter(f);
        const auto a = mesh.point(*it++);
        const auto b = mesh.point(*it++);
        const auto c = mesh.point(*it);
        const auto n = OpenMesh::cross(b - a, c - a);
        if (!(OpenMesh::dot(n, mesh.normal(f)) > 0.0) && failures++ == 0) first = f.idx();
    }
    if (failures > 0)
        ADD_FAILURE() << failures << " face(s) whose winding disagrees with the stored normal "
                      << "(flipped triangles), first: face " << first;
}

}  // namespace kerf::cut::testing
