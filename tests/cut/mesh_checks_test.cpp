// The strict checker must itself catch what it claims to catch.
#include "tests/cut/mesh_checks.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <numbers>

#include "display/cut/mesh_hash.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/test_shapes.hpp"

namespace kerf::cut::testing {
namespace {

TEST(MeshChecks, TestShapesAreClosedOrientedWithTheExpectedVolumes) {
    const double pi = std::numbers::pi;
    auto s = uv_sphere_by_rings(1.0, 64, 128);
    auto rs = expect_closed_2_manifold(s);
    ASSERT_EQ(rs.piece_volumes_m3.size(), 1u);
    EXPECT_NEAR(rs.total_volume_m3, 4.0 / 3.0 * pi, 0.01);
    auto t = mesh::make_torus(0.03, 0.01, 48, 24);
    EXPECT_NEAR(expect_closed_2_manifold(t).total_volume_m3, 2 * pi * pi * 0.03 * 0.01 * 0.01,
                2e-6);
    auto tube = mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20);
    auto rt = expect_closed_2_manifold(tube);
    EXPECT_NEAR(rt.total_volume_m3, pi * (1e-4 - 3.6e-5) * 0.05, 2e-7);
    auto b = mesh::make_box(TriMesh::Point(0, 0, 0), TriMesh::Point(1, 2, 3), 3);
    EXPECT_NEAR(expect_closed_2_manifold(b).total_volume_m3, 6.0, 1e-12);
    expect_face_normals_agree(b);
}

TEST(MeshChecks, CountsPiecesSeparately) {
    auto m = uv_sphere_by_rings(1.0, 8, 16);
    append(m, uv_sphere_by_rings(0.5, 8, 16, TriMesh::Point(5, 0, 0)));
    auto r = expect_closed_2_manifold(m);
    ASSERT_EQ(r.piece_volumes_m3.size(), 2u);
    EXPECT_GT(r.piece_volumes_m3[0], 7.0 * r.piece_volumes_m3[1]);
}

TEST(MeshChecks, ReportsAnOpenSurface) {
    auto m = mesh::make_box(TriMesh::Point(0, 0, 0), TriMesh::Point(1, 1, 1), 1);
    m.delete_face(*m.faces().begin(), false);
    EXPECT_NONFATAL_FAILURE(expect_closed_2_manifold(m), "open surface");
}

TEST(MeshChecks, ReportsANearZeroAreaTriangle) {
    TriMesh m;
    auto a = m.add_vertex(TriMesh::Point(0, 0, 0));
    auto b = m.add_vertex(TriMesh::Point(1, 0, 0));
    auto c = m.add_vertex(TriMesh::Point(0.5, 1e-17, 0));
    auto d = m.add_vertex(TriMesh::Point(0.5, 0.5, 1));
    m.add_face(a, c, b);
    m.add_face(a, b, d);
    m.add_face(b, c, d);
    m.add_face(c, a, d);
    EXPECT_NONFATAL_FAILURE(expect_closed_2_manifold(m), "near-zero area");
}

TEST(MeshChecks, ReportsAFlippedTriangle) {
    auto m = mesh::make_box(TriMesh::Point(0, 0, 0), TriMesh::Point(1, 1, 1), 1);
    auto f = *m.faces().begin();
    m.set_normal(f, -m.normal(f));
    EXPECT_NONFATAL_FAILURE(expect_face_normals_agree(m), "winding disagrees");
}

// The slab and sequence references are copies made by extract_faces and compared by mesh_hash,
// which reads every vertex attribute: a copy that left one unwritten (colour and material were)
// hashed differently from run to run (valgrind: uninitialised reads).
TEST(MeshChecks, ExtractFacesCopiesEveryAttributeTheHashReads) {
    auto m = uv_sphere_by_rings(1.0, 8, 16);
    for (auto v : m.vertices()) {
        const auto i = static_cast<unsigned char>(v.idx());
        m.set_normal(v, TriMesh::Normal(0, 0, 1));
        m.set_texcoord2D(v, TriMesh::TexCoord2D(0.25f * i, 0.5f));
        m.set_color(v, TriMesh::Color(i, static_cast<unsigned char>(255 - i), 7));
        m.data(v).set_material(v.idx() % 2 ? mesh::Material::kCancellous
                                           : mesh::Material::kCutSurface);
    }
    const TriMesh all = extract_faces(m, [](mesh::FaceHandle) { return true; });
    ASSERT_EQ(all.n_vertices(), m.n_vertices());
    // The copy numbers vertices in the order the faces first use them: compare by position.
    std::size_t matched = 0;
    for (auto w : all.vertices()) {
        for (auto v : m.vertices()) {
            if (m.point(v) != all.point(w)) continue;
            EXPECT_EQ(all.normal(w), m.normal(v));
            EXPECT_EQ(all.texcoord2D(w), m.texcoord2D(v));
            EXPECT_EQ(all.color(w), m.color(v));
            EXPECT_EQ(all.data(w).material(), m.data(v).material());
            ++matched;
            break;
        }
    }
    EXPECT_EQ(matched, all.n_vertices());
    const TriMesh again = extract_faces(m, [](mesh::FaceHandle) { return true; });
    EXPECT_EQ(mesh_hash(again), mesh_hash(all));
}

}  // namespace
}  // namespace kerf::cut::testing
