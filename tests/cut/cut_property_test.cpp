// The cut property test (issue 10): random cuts of every kind — full plane, localised, chevron
// (two localised planes meeting on a line, the second through the first one's cap), biplanar
// slab — on every clean mesh in KERF_SHARED_MESHES, each on a fresh copy, and after every cut:
// closed, consistently oriented 2-manifold; no triangle below the one degenerate threshold
// (mesh::kDegenerateTwiceAreaRelative); volumes to 1e-9 (a slab's removed volume against two
// full-plane slices and the piece between them); every piece written as float32 STL and read
// back is a closed 2-manifold with no degenerate triangle (every 8th cut: OBJ, PLY and OFF too).
// Refusals are counted by status (a plane that misses the bone is no refusal) and printed with
// their planes and seeds; on these clean bones there must be none. New vertices within the
// tolerance of another vertex are counted too: there must be none (issue 10 item 2).
//
// KERF_PROPERTY_CUTS cuts per (mesh, kind): 42 in kerf_cut_stress_tests (6 meshes x 4 kinds =
// 1,008 cuts, label stress), 3 in kerf_cut_property_tests (72 cuts, the always-run slice).
// Planes come in two families (slice_sweep.hpp DrawOrder): the gcc draw order, always run, and
// clang's old order, 1,008 more cuts in kerf_cut_stress_tests when the environment sets
// KERF_PROPERTY_BOTH_DRAW_ORDERS (skipped otherwise: CI has no time for both):
//   KERF_PROPERTY_BOTH_DRAW_ORDERS=1 build/bin/kerf_cut_stress_tests --gtest_filter='*CutProperty*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "display/cut/components.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "display/mesh/validate.hpp"
#include "tests/cut/chevron_checks.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/slice_sweep.hpp"

#ifndef KERF_PROPERTY_CUTS
#define KERF_PROPERTY_CUTS 3
#endif

namespace kerf::cut {
namespace {

using namespace kerf::cut::testing;
using mesh::FaceHandle;
using mesh::TriMesh;

enum class Kind { kFull, kLocalised, kChevron, kSlab };

std::string kind_name(Kind k) {
    switch (k) {
        case Kind::kFull:
            return "full";
        case Kind::kLocalised:
            return "localised";
        case Kind::kChevron:
            return "chevron";
        case Kind::kSlab:
            return "slab";
    }
    return "?";
}

constexpr double kKerfM = 0.001;

struct Tally {
    int cuts = 0;
    int close_vertices = 0;  ///< cuts that left a new vertex within tol of another
    std::map<std::string, int> refusals;
};

class CutProperty : public ::testing::TestWithParam<std::tuple<const char*, Kind, DrawOrder>> {};

TEST_P(CutProperty, EveryCutIsClosedOrientedNonDegenerateConservesVolumeAndRoundTrips) {
    const auto [name, kind, order] = GetParam();
    if (order != DrawOrder::kZyx && std::getenv("KERF_PROPERTY_BOTH_DRAW_ORDERS") == nullptr)
        GTEST_SKIP() << "the second plane family runs with KERF_PROPERTY_BOTH_DRAW_ORDERS=1 (it "
                        "doubles this test's time, which CI has no room for)";
    auto loaded = testing::load_shared_mesh(name);
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    const TriMesh shape = std::move(*loaded);
    ASSERT_TRUE(check_closed_2_manifold(shape).ok) << name << " is not clean";
    const double v0 = signed_volume(shape);
    std::mt19937_64 rng(std::hash<std::string>{}(std::string(name) + kind_name(kind)));
    Tally tally;
    for (int i = 0; i < KERF_PROPERTY_CUTS; ++i) {
        const std::string what = std::string(name) + " " + kind_name(kind) + " " +
                                 to_string(order) + " #" + std::to_string(i);
        SCOPED_TRACE(what);
        TriMesh m = shape;
        const auto first_new = static_cast<int>(m.n_vertices());
        CutContext ctx(m);
        const Plane plane = random_plane(m, rng, order);
        CutStatus st = CutStatus::kOk;
        double expected_volume = v0;
        Seed used_seed{Vec3(0, 0, 0), FaceHandle(), 0.0};
        double used_angle = 0.0;
        if (kind == Kind::kFull) {
            CrossSection cs;
            st = slice_by_plane(ctx, plane, cs).status;
        } else if (kind == Kind::kLocalised) {
            const Seed seed = random_seed(m, plane, rng);
            if (seed.tolerance_m == 0.0) continue;
            used_seed = seed;
            CrossSection cs;
            st = slice_by_plane(ctx, plane, seed, cs).status;
        } else if (kind == Kind::kChevron) {
            const Seed seed = random_seed(m, plane, rng);
            if (seed.tolerance_m == 0.0) continue;
            used_seed = seed;
            CrossSection cs;
            st = slice_by_plane(ctx, plane, seed, cs).status;
            if (st == CutStatus::kOk) {
                // The second limb: a plane through the seed's line on the first plane, 20 to 70
                // degrees from it, seeded where the two planes meet on the surface.
                std::uniform_real_distribution<double> angle(20.0, 70.0);
                const double a = angle(rng) * M_PI / 180.0;
                used_angle = a;
                const Plane second = chevron_second_limb(plane, seed.point_m, a);
                const Seed seed2 = seed_on_both(m, second, plane);
                if (seed2.tolerance_m == 0.0) continue;
                st = slice_by_plane(ctx, second, seed2, cs).status;
            }
        } else {
            const Seed seed = random_seed(m, plane.offset(-0.5 * kKerfM), rng);
            if (seed.tolerance_m == 0.0) continue;
            used_seed = seed;
            SlabCut slab;
            st = subtract_slab(ctx, plane, kKerfM, seed, slab).status;
            if (st == CutStatus::kOk) {
                const double removed =
                    slab_reference_removed_volume(shape, plane, kKerfM, seed.point_m);
                ASSERT_GE(removed, 0.0) << "a reference slice failed";
                expected_volume = v0 - removed;
            }
        }
        if (st == CutStatus::kPlaneMissesMesh) continue;  // the random plane missed the bone
        if (st != CutStatus::kOk) {
            ++tally.refusals[std::string(to_string(st))];
            const Vec3 &p = plane.point(), &n = plane.normal(), &q = used_seed.point_m;
            std::printf(
                "refused: %s %s: plane {%a, %a, %a} {%a, %a, %a} seed {%a, %a, %a} face %d "
                "angle %a\n",
                what.c_str(), std::string(to_string(st)).c_str(), p[0], p[1], p[2], n[0], n[1],
                n[2], q[0], q[1], q[2], used_seed.face_hint.idx(), used_angle);
            continue;
        }
        ++tally.cuts;
        double nearest = 1e300;
        if (close_new_vertices(m, first_new, ctx.tolerance_m(), nearest) > 0) {
            ++tally.close_vertices;
            std::printf("close vertices: %s: nearest %.3g m, tolerance %.3g m\n", what.c_str(),
                        nearest, ctx.tolerance_m());
        }
        const MeshReport rep = expect_closed_2_manifold(m);
        EXPECT_NEAR(rep.total_volume_m3, expected_volume, 1e-9 * v0);
        expect_face_normals_agree(m);
        expect_pieces_round_trip(m, mesh::Format::kStl, what);
        if (i % 8 == 0)
            for (auto f : {mesh::Format::kObj, mesh::Format::kPly, mesh::Format::kOff})
                expect_pieces_round_trip(m, f, what);
    }
    std::string refused;
    int total_refused = 0;
    for (const auto& [status, n] : tally.refusals)
        refused += " " + status + "=" + std::to_string(n), total_refused += n;
    RecordProperty("cuts", tally.cuts);
    RecordProperty("refusals", total_refused);
    std::printf("%s %s %s: %d cuts, %d refused%s\n", name, kind_name(kind).c_str(),
                to_string(order), tally.cuts, total_refused, refused.c_str());
    // No refusal on these clean bones: 0 of 1,008 in the long form (22 before vertices next to a
    // sliver were snapped onto the plane, see slice_by_plane.hpp).
    EXPECT_EQ(total_refused, 0) << "refusals on a clean bone:" << refused;
    // No cut leaves two vertices within tol (issue 10 item 2; the last two, chevrons 0.36 and 0.63
    // tol apart, are in chevron_regression_test.cpp).
    EXPECT_EQ(tally.close_vertices, 0) << "cuts leaving vertices within the tolerance";
}

// The always-run slice cuts the gcc-order planes only; the stress form both families.
#ifdef KERF_PROPERTY_BOTH_ORDERS
constexpr DrawOrder kDrawOrders[] = {DrawOrder::kZyx, DrawOrder::kXyz};
#else
constexpr DrawOrder kDrawOrders[] = {DrawOrder::kZyx};
#endif

INSTANTIATE_TEST_SUITE_P(
    CleanSharedMeshes, CutProperty,
    ::testing::Combine(
        ::testing::Values("bp3d_right_first_metatarsal.stl", "jma_norm01_calcaneus_right.stl",
                          "jma_norm01_talus_right.stl", "tcsm_ksbl_L01_talus_left.stl",
                          "tcsm_ksbl_L01_tibia_distal_left.stl",
                          "tcsm_ksbl_L01_fibula_distal_left.stl"),
        ::testing::Values(Kind::kFull, Kind::kLocalised, Kind::kChevron, Kind::kSlab),
        ::testing::ValuesIn(kDrawOrders)),
    [](const auto& param_info) {
        std::string n = std::get<0>(param_info.param);
        n = n.substr(0, n.find('.'));
        n += "_" + kind_name(std::get<1>(param_info.param));
        // The first family keeps its old names.
        if (std::get<2>(param_info.param) != DrawOrder::kZyx)
            n += std::string("_") + to_string(std::get<2>(param_info.param));
        return n;
    });

}  // namespace
}  // namespace kerf::cut
