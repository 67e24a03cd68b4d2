// Sever detection: global components, and the localised lockstep search after real cuts.
#include "display/cut/components.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::TriMesh;

/// Appends a copy of `part` to `into` (a second shell in the same mesh).
void append(TriMesh& into, const TriMesh& part) {
    const auto base = static_cast<int>(into.n_vertices());
    for (const auto v : part.vertices()) into.add_vertex(part.point(v));
    for (const auto f : part.faces()) {
        std::vector<mesh::VertexHandle> vs;
        for (const auto v : part.fv_range(f)) vs.emplace_back(v.idx() + base);
        into.add_face(vs);
    }
}

/// Slices `m` by the full plane and expects success.
CrossSection slice(TriMesh& m, Vec3 point, Vec3 normal) {
    CutContext ctx(m);
    CrossSection cs;
    const auto r = slice_by_plane(ctx, *Plane::make(point, normal), cs);
    EXPECT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    testing::expect_closed_2_manifold(m);
    return cs;
}

double sum_volume(const std::vector<Body>& bodies) {
    double v = 0.0;
    for (const auto& b : bodies) v += b.volume_m3;
    return v;
}

TEST(Components, ASphereIsOneBodyWithItsVolumeAndBox) {
    const TriMesh m = mesh::make_uv_sphere(0.01, 4000);
    const auto bodies = find_components(m);
    ASSERT_EQ(bodies.size(), 1u);
    EXPECT_EQ(bodies[0].faces.size(), m.n_faces());
    EXPECT_EQ(bodies[0].vertices.size(), m.n_vertices());
    EXPECT_NEAR(bodies[0].volume_m3, testing::signed_volume(m), 1e-15);
    EXPECT_NEAR(bodies[0].bbox_max_m[2], 0.01, 1e-12);
    EXPECT_NEAR(bodies[0].bbox_min_m[2], -0.01, 1e-12);
}

TEST(Components, SeparateShellsAreSeparateBodiesInFaceOrder) {
    TriMesh m = mesh::make_uv_sphere(0.01, 500);
    append(m, mesh::make_box({0.1, 0, 0}, {0.2, 0.1, 0.1}));
    const auto bodies = find_components(m);
    ASSERT_EQ(bodies.size(), 2u);
    EXPECT_LT(bodies[0].faces.front(), bodies[1].faces.front());
    EXPECT_NEAR(bodies[1].volume_m3, 1e-3, 1e-15);
    EXPECT_NEAR(bodies[1].bbox_min_m[0], 0.1, 1e-15);
}

TEST(Components, MakeBodyListsVerticesInIndexOrderWhateverTheStampsHold) {
    // Two tetrahedra with interleaved vertices (A: 0 2 4 6, B: 1 3 5 7), faces listing them out
    // of order. A's stamps are scanned over 0..6; B, given the same stamp, finds A's 2 4 6 in
    // its range too and must still list only its own four (the sorted way).
    TriMesh m = mesh::make_mesh();
    for (int i = 0; i < 8; ++i) {
        const double x = (i % 2 == 0) ? 0.0 : 1.0;
        const int k = i / 2;
        m.add_vertex(mesh::Point(x + (k == 1 ? 0.1 : 0.0), k == 2 ? 0.1 : 0.0, k == 3 ? 0.1 : 0.0));
    }
    const auto tet = [&](int off) {
        const auto v = [&](int k) { return mesh::VertexHandle(2 * k + off); };
        std::vector<mesh::FaceHandle> faces = {
            m.add_face(v(3), v(1), v(0)), m.add_face(v(0), v(2), v(3)),
            m.add_face(v(1), v(3), v(2)), m.add_face(v(0), v(1), v(2))};
        return faces;
    };
    const auto a = tet(0), b = tet(1);
    std::vector<std::uint32_t> seen(m.n_vertices(), 0);
    const Body body_a = make_body(m, a, seen, 1);
    const Body body_b = make_body(m, b, seen, 1);
    const std::vector<mesh::VertexHandle> want_a = {mesh::VertexHandle(0), mesh::VertexHandle(2),
                                                    mesh::VertexHandle(4), mesh::VertexHandle(6)};
    const std::vector<mesh::VertexHandle> want_b = {mesh::VertexHandle(1), mesh::VertexHandle(3),
                                                    mesh::VertexHandle(5), mesh::VertexHandle(7)};
    EXPECT_EQ(body_a.vertices, want_a);
    EXPECT_EQ(body_b.vertices, want_b);
    EXPECT_EQ(body_b.faces.size(), 4u);
}

TEST(Components, DeletedFacesBelongToNoBody) {
    TriMesh m = mesh::make_uv_sphere(0.01, 500);
    append(m, mesh::make_box({0.1, 0, 0}, {0.2, 0.1, 0.1}));
    for (const auto f : m.faces()) {
        if (m.point(m.to_vertex_handle(m.halfedge_handle(f)))[0] > 0.05) m.delete_face(f, true);
    }
    const auto bodies = find_components(m);
    ASSERT_EQ(bodies.size(), 1u);
    EXPECT_LT(bodies[0].bbox_max_m[0], 0.011);
}

TEST(Components, AFullCutOfASphereSeversItAndTheVolumesAddUp) {
    TriMesh m = mesh::make_uv_sphere(0.01, 4000);
    const double v0 = testing::signed_volume(m);
    const CrossSection cs = slice(m, Vec3(0, 0, 0.006), Vec3(0.1, 0.05, 1));
    const auto bodies = find_components(m);
    ASSERT_EQ(bodies.size(), 2u);
    EXPECT_NEAR(sum_volume(bodies), v0, 1e-9 * v0);
    // Localised: the cap side (the small one) closes first and is the severed body.
    PieceFinder finder(m);
    const SeverReport r = finder.find_pieces(cs);
    ASSERT_EQ(r.severed.size(), 1u);
    const Body& cap = r.severed[0];
    EXPECT_GT(cap.bbox_min_m[2], 0.004);
    EXPECT_NEAR(cap.volume_m3, std::min(bodies[0].volume_m3, bodies[1].volume_m3), 1e-18);
    EXPECT_LT(r.faces_visited, 2 * cap.faces.size() + 8);  // never walked the big half whole
}

TEST(Components, CuttingARingOnceLeavesOneBodyAndTwiceSeversIt) {
    TriMesh m = mesh::make_torus(0.02, 0.005, 96, 32);
    const double v0 = testing::signed_volume(m);
    const auto plane = *Plane::make(Vec3(0, 0.0003, 0), Vec3(0.01, 1, 0));
    // A localised cut of the plane y ~ 0 through the ring near x = +R: a C shape, one piece.
    CrossSection first;
    {
        CutContext ctx(m);
        const auto res = slice_by_plane(
            ctx, plane, Seed{Vec3(0.025, 0.0003, 0), mesh::FaceHandle(), -1.0}, first);
        ASSERT_EQ(res.status, CutStatus::kOk) << to_string(res.status);
    }
    EXPECT_EQ(find_components(m).size(), 1u);
    PieceFinder finder(m);
    SeverReport r = finder.find_pieces(first);
    EXPECT_TRUE(r.severed.empty());
    EXPECT_EQ(r.piece_of_seed, std::vector<std::uint32_t>(2, SeverReport::kRemainder));
    // The same plane near x = -R cuts the ring through: two pieces now.
    CrossSection second;
    {
        CutContext ctx(m);
        const auto res = slice_by_plane(
            ctx, plane, Seed{Vec3(-0.025, 0.0003, 0), mesh::FaceHandle(), -1.0}, second);
        ASSERT_EQ(res.status, CutStatus::kOk) << to_string(res.status);
    }
    const auto report = testing::expect_closed_2_manifold(m);
    const auto bodies = find_components(m);
    ASSERT_EQ(bodies.size(), 2u);
    EXPECT_EQ(report.piece_volumes_m3.size(), 2u);
    EXPECT_NEAR(sum_volume(bodies), v0, 1e-9 * std::abs(v0));
    r = finder.find_pieces(second);
    ASSERT_GE(r.severed.size(), 1u);
    EXPECT_NEAR(r.severed[0].volume_m3, bodies[0].volume_m3, 1e-3 * std::abs(v0));
}

TEST(Components, AHollowTubeCutAcrossGivesTwoBodiesFoundFromBothLoops) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, 48, 20);
    const double v0 = testing::signed_volume(m);
    const CrossSection cs = slice(m, Vec3(0, 0, 0.0101), Vec3(0, 0, 1));
    ASSERT_EQ(cs.positive.loops.size(), 2u);  // outer wall and canal
    const auto bodies = find_components(m);
    ASSERT_EQ(bodies.size(), 2u);
    EXPECT_NEAR(sum_volume(bodies), v0, 1e-9 * v0);
    PieceFinder finder(m);
    const SeverReport r = finder.find_pieces(cs);
    ASSERT_EQ(r.severed.size(), 1u);
    EXPECT_LT(r.severed[0].bbox_max_m[2], 0.0102);  // the short end, z < 10.1 mm
    // Both seeds on the short side (outer loop and canal) belong to the severed piece.
    int on_piece = 0;
    for (const auto p : r.piece_of_seed) on_piece += p == 0 ? 1 : 0;
    EXPECT_EQ(on_piece, 2);
}

TEST(Components, CavityShellsJoinTheBoneAroundThem) {
    // A bone as the foot generator makes it: an outer shell and an inward-facing canal shell.
    TriMesh m = mesh::make_uv_sphere(0.01, 2000);
    TriMesh canal = mesh::make_uv_sphere(0.004, 800);
    for (const auto f : canal.faces()) {  // turn it inside out: a cavity
        std::vector<mesh::VertexHandle> vs;
        for (const auto v : canal.fv_range(f)) vs.push_back(v);
        canal.delete_face(f, false);
        canal.add_face(vs[0], vs[2], vs[1]);
    }
    canal.garbage_collection();
    append(m, canal);
    append(m, mesh::make_box({0.1, 0, 0}, {0.2, 0.1, 0.1}));
    const auto shells = find_components(m);
    ASSERT_EQ(shells.size(), 3u);
    const auto bodies = group_cavities(shells);
    ASSERT_EQ(bodies.size(), 2u);
    EXPECT_EQ(bodies[0].faces.size(), shells[0].faces.size() + shells[1].faces.size());
    EXPECT_EQ(bodies[0].vertices.size(), shells[0].vertices.size() + shells[1].vertices.size());
    // The cavity's faces and vertices merged in: both lists still in index order.
    EXPECT_TRUE(std::is_sorted(bodies[0].faces.begin(), bodies[0].faces.end()));
    EXPECT_TRUE(std::is_sorted(bodies[0].vertices.begin(), bodies[0].vertices.end()));
    EXPECT_NEAR(bodies[0].volume_m3, shells[0].volume_m3 + shells[1].volume_m3, 1e-18);
    EXPECT_LT(bodies[0].volume_m3, shells[0].volume_m3);
    EXPECT_NEAR(bodies[1].volume_m3, 1e-3, 1e-15);
}

TEST(Components, InvalidOrDeletedSeedsAreIgnored) {
    TriMesh m = mesh::make_uv_sphere(0.01, 500);
    PieceFinder finder(m);
    const std::vector<mesh::FaceHandle> seeds{mesh::FaceHandle(), mesh::FaceHandle(1 << 30),
                                              mesh::FaceHandle(0)};
    const SeverReport r = finder.find_pieces(seeds);
    ASSERT_EQ(r.piece_of_seed.size(), 3u);
    EXPECT_EQ(r.piece_of_seed[0], SeverReport::kRemainder);
    EXPECT_EQ(r.piece_of_seed[1], SeverReport::kRemainder);
    // A single valid search is the only one open: it is the remainder at once, nothing walked.
    EXPECT_EQ(r.piece_of_seed[2], SeverReport::kRemainder);
    EXPECT_EQ(r.faces_visited, 0u);
}

}  // namespace
}  // namespace kerf::cut
