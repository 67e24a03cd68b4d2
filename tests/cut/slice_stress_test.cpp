// Stress sweeps on the real bone meshes in KERF_SHARED_MESHES (label `stress`: excluded from the
// sanitizer runs, still part of the normal ctest run). Skips visibly when the meshes are absent.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/slice_sweep.hpp"

namespace kerf::cut {
namespace {

using namespace kerf::cut::testing;
using mesh::TriMesh;

class RealMeshSweep : public ::testing::TestWithParam<const char*> {};

TEST_P(RealMeshSweep, RandomPlanesAndSeedsGiveClosedPiecesThatConserveVolume) {
    auto loaded = testing::load_shared_mesh(GetParam());
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    const TriMesh shape = std::move(*loaded);
    const auto base = expect_closed_2_manifold(shape);
    ASSERT_TRUE(base.ok) << GetParam() << " is not clean before cutting";
    std::mt19937_64 rng(std::hash<std::string>{}(GetParam()));
    const SweepCounts full = sweep_random_planes(shape, rng, 12, false);
    const SweepCounts local = sweep_random_planes(shape, rng, 12, true);
    const SweepCounts seq = sweep_sequence(shape, rng, 6);
    EXPECT_EQ(full.failed + local.failed + seq.failed, 0);
    const int cuts = full.cut + local.cut + seq.cut;
    const int cap_refusals = full.cap_refusals + local.cap_refusals + seq.cap_refusals;
    EXPECT_LE(20 * cap_refusals, cuts) << cap_refusals << " cap refusals in " << cuts << " cuts";
    EXPECT_GT(full.cut + local.cut, 12);
    RecordProperty("cuts", full.cut + local.cut + seq.cut);
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RealMeshSweep,
                         ::testing::Values("bp3d_right_first_metatarsal.stl",
                                           "jma_norm01_calcaneus_right.stl",
                                           "jma_norm01_talus_right.stl",
                                           "tcsm_ksbl_L01_talus_left.stl",
                                           "tcsm_ksbl_L01_tibia_distal_left.stl",
                                           "tcsm_ksbl_L01_fibula_distal_left.stl"),
                         [](const ::testing::TestParamInfo<const char*>& param_info) {
                             const std::string name = param_info.param;
                             return name.substr(0, name.find('.'));  // the mesh file's stem
                         });

TEST(RealMeshes, ACutThroughTheMissingTriangleOfTheOpenFootIsRefusedUnchanged) {
    auto loaded =
        testing::load_shared_mesh("opensim_gait2392_foot_OPEN_metres.stl", LengthUnit::kMetre);
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    // The hole: a boundary halfedge; cut through its edge's midpoint.
    mesh::HalfedgeHandle hole;
    for (auto h : m.halfedges())
        if (m.is_boundary(h)) hole = h;
    ASSERT_TRUE(hole.is_valid());
    const Vec3 a = m.point(m.from_vertex_handle(hole)), b = m.point(m.to_vertex_handle(hole));
    const Plane plane = *Plane::make((a + b) * 0.5, b - a);
    const auto before = snapshot(m);
    CutContext ctx(m);
    CrossSection cs;
    const auto r = slice_by_plane(ctx, plane, cs);
    EXPECT_EQ(r.status, CutStatus::kNonManifoldInput) << to_string(r.status);
    EXPECT_TRUE(snapshot(m) == before);
}

TEST(RealMeshes, SlabThroughTheFirstMetatarsalShaftRemovesTheKerf) {
    auto loaded = testing::load_shared_mesh("bp3d_right_first_metatarsal.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    Vec3 lo(1e9, 1e9, 1e9), hi(-1e9, -1e9, -1e9);
    for (auto v : m.vertices()) lo.minimize(m.point(v)), hi.maximize(m.point(v));
    const Plane plane = *Plane::make((lo + hi) * 0.5, Vec3(0.1, 0.05, 1));
    std::mt19937_64 rng(5);
    const Seed seed = random_seed(m, plane.offset(-0.0005), rng);
    const double v0 = signed_volume(m);
    CutContext ctx(m);
    SlabCut slab;
    const auto r = subtract_slab(ctx, plane, 0.001, seed, slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 2u);
    EXPECT_LT(rep.total_volume_m3, v0);
    expect_face_normals_agree(m);
}

}  // namespace
}  // namespace kerf::cut
