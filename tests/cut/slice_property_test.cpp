// Property tests: many random planes and seeds, repeated and crossing cuts; every result must
// pass the strict checks, and every refusal must leave the mesh unchanged.
#include <gtest/gtest.h>

#include <random>

#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/slice_sweep.hpp"
#include "tests/cut/test_shapes.hpp"

namespace kerf::cut {
namespace {

using namespace kerf::cut::testing;

TEST(SliceProperty, RandomFullPlaneCutsOfSpheresToriTubesAndBoxesAreClosedAndConserveVolume) {
    const TriMesh shapes[] = {
        mesh::make_uv_sphere(0.01, 3000), mesh::make_torus(0.03, 0.01, 48, 24),
        mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20),
        mesh::make_box(TriMesh::Point(0, 0, 0), TriMesh::Point(0.02, 0.01, 0.03), 4)};
    std::mt19937_64 rng(20261122);
    for (const TriMesh& shape : shapes) {
        const SweepCounts c = sweep_random_planes(shape, rng, 25, /*localised=*/false);
        EXPECT_GT(c.cut, 10);
        EXPECT_EQ(c.failed, 0);
        EXPECT_EQ(c.cap_refusals, 0);
        EXPECT_EQ(c.sliver_refusals, 0);
    }
}

TEST(SliceProperty, RandomLocalisedCutsFromRandomSeedsAreClosedAndConserveVolume) {
    const TriMesh shapes[] = {mesh::make_uv_sphere(0.01, 3000),
                              mesh::make_torus(0.03, 0.01, 48, 24),
                              mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20)};
    std::mt19937_64 rng(7);
    for (const TriMesh& shape : shapes) {
        const SweepCounts c = sweep_random_planes(shape, rng, 25, /*localised=*/true);
        EXPECT_GT(c.cut, 10);
        EXPECT_EQ(c.failed, 0);
        EXPECT_EQ(c.cap_refusals, 0);
        EXPECT_EQ(c.sliver_refusals, 0);
    }
}

TEST(SliceProperty, SequencesOfCrossingCutsThroughEarlierCapsStayClosed) {
    const TriMesh shapes[] = {mesh::make_uv_sphere(0.01, 2000),
                              mesh::make_hollow_tube(0.05, 0.01, 0.006, 32, 10)};
    std::mt19937_64 rng(99);
    int cap_refusals = 0;
    for (const TriMesh& shape : shapes)
        for (int run = 0; run < 6; ++run) {
            const SweepCounts c = sweep_sequence(shape, rng, 5);
            EXPECT_EQ(c.failed, 0);
            std::printf("crossing: cap %d sliver %d\n", c.cap_refusals, c.sliver_refusals);
            cap_refusals += c.cap_refusals;
            EXPECT_EQ(c.sliver_refusals, 0);
        }
    // gcc gives 0 cap refusals in these 60 cuts since near vertices are snapped onto the plane;
    // clang -O1 (the ASan build) still refuses one cap (the mesh verified unchanged): at most 1.
    EXPECT_LE(cap_refusals, 1);
}

TEST(SliceProperty, ChevronTwoPlanesMeetingAtAnApexCutThroughTheFirstCap) {
    auto m = mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20);
    const double v0 = signed_volume(m);
    CutContext ctx(m);
    CrossSection cs;
    const Vec3 apex(0.0, 0.0, 0.025);
    const auto r1 = slice_by_plane(ctx, *Plane::make(apex, Vec3(1, 0, 1)), cs);
    ASSERT_TRUE(r1.ok()) << to_string(r1.status);
    const auto r2 = slice_by_plane(ctx, *Plane::make(apex, Vec3(-1, 0, 1)), cs);
    ASSERT_TRUE(r2.ok()) << to_string(r2.status);
    EXPECT_GT(r2.stats.faces_split, 0u);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 4u);
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
    expect_face_normals_agree(m);
    expect_cross_section_consistent(m, cs, ctx.tolerance_m());
}

TEST(SliceProperty, TheSameCutsGiveABitIdenticalMesh) {
    auto run = [] {
        auto m = mesh::make_torus(0.03, 0.01, 48, 24);
        CutContext ctx(m);
        CrossSection cs;
        EXPECT_TRUE(
            slice_by_plane(ctx, *Plane::make(Vec3(0.001, 0, 0), Vec3(1, 0.2, 0.1)), cs).ok());
        EXPECT_TRUE(
            slice_by_plane(ctx, *Plane::make(Vec3(0, 0.002, 0), Vec3(0.1, 1, 0.3)), cs).ok());
        return snapshot(m);
    };
    EXPECT_TRUE(run() == run());
}

}  // namespace
}  // namespace kerf::cut
