// The planes that were refused on the clean shared bones before vertices next to a sliver were
// snapped onto the plane (issue 10, item 5): found by cut_property_test's long form, which
// prints every refused plane and seed. Each now cuts with every invariant: closed, oriented,
// volume to 1e-9 (uniplanar), rims and caps consistent. Six by snapping at least one vertex;
// four `cap_triangulation_failed` ones, which snapping mended before, now by two flips of the
// cap and no snap (a needle on a near-straight run of rim points: `two_flips` in cap_plan.cpp).
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

enum class Kind { kFull, kLocalised, kSlab };

struct Refused {
    const char* mesh;
    Kind kind;
    const char* was;  ///< the status it got before
    Vec3 point;       ///< plane point, m
    Vec3 normal;
    Vec3 seed;          ///< localised and slab only
    int face;           ///< the seed's face hint, or -1
    bool snaps = true;  ///< mended by snapping; else by the cap's two flips, snapping nothing
};

// Hex floats as printed by cut_property_test ("refused: ...").
const Refused kRefused[] = {
    {"jma_norm01_calcaneus_right.stl",
     Kind::kFull,
     "cap_triangulation_failed",
     {-0x1.04ec9450d7b17p-4, -0x1.c07a2f0611fep-4, -0x1.e42b56a8968dep-4},
     {0x1.a79d7c6e760fp-4, 0x1.7512d1ad6e5dfp-2, 0x1.d9dc62be9df91p-1},
     {0, 0, 0},
     -1,
     false},
    {"tcsm_ksbl_L01_tibia_distal_left.stl",
     Kind::kFull,
     "sliver_split",
     {0x1.3aa23abdb1bc2p-7, -0x1.0beb629ecf3f1p-6, -0x1.504ba90141278p-5},
     {-0x1.7b4a501458857p-2, 0x1.3280931ab37p-8, -0x1.db93940b72aabp-1},
     {0, 0, 0},
     -1},
    {"tcsm_ksbl_L01_tibia_distal_left.stl",
     Kind::kFull,
     "cap_triangulation_failed",
     {-0x1.0b38bed8ea564p-8, -0x1.04c45a3d1d13fp-5, -0x1.44f53ee5a0618p-5},
     {0x1.94ed4b266af41p-1, -0x1.026935aa434f9p-1, -0x1.6269731bfdc6ep-2},
     {0, 0, 0},
     -1,
     false},
    {"tcsm_ksbl_L01_fibula_distal_left.stl",
     Kind::kFull,
     "sliver_split",
     {0x1.6c035d3a69a02p-6, -0x1.abbb4c85b22d6p-6, -0x1.691a01add2ad6p-5},
     {0x1.2ba29f6a8c5d4p-2, 0x1.b5b55558b9b08p-1, 0x1.b6ae2626a4e83p-2},
     {0, 0, 0},
     -1},
    {"tcsm_ksbl_L01_fibula_distal_left.stl",
     Kind::kFull,
     "cap_triangulation_failed",
     {0x1.a223dbc7bc901p-6, -0x1.84024c081cb5dp-6, -0x1.664f2b7440dc9p-5},
     {-0x1.9ab381d129cc6p-2, -0x1.8efcc268ebeb4p-1, -0x1.ed16d3e0cfe6p-2},
     {0, 0, 0},
     -1},
    {"tcsm_ksbl_L01_talus_left.stl",
     Kind::kLocalised,
     "sliver_split",
     {0x1.3939624dc2bd8p-8, -0x1.b3a0ddfda575ap-5, -0x1.4bac2ba4f7f6fp-4},
     {-0x1.bb204c1b019d7p-3, -0x1.c5e786cf1c0cbp-1, 0x1.a2c55302180a9p-2},
     {-0x1.1a0e9f0fb38a9p-6, -0x1.79b2bb0cf87dbp-5, -0x1.3bae111111111p-4},
     -1},
    {"jma_norm01_calcaneus_right.stl",
     Kind::kLocalised,
     "sliver_split",
     {-0x1.8cdd5f2f1e424p-5, -0x1.e48a8076f5d78p-4, -0x1.93a1dba35bba6p-4},
     {-0x1.610acb7ee98a4p-1, -0x1.a4734ee2e90c7p-2, -0x1.3177c2fcd853bp-1},
     {-0x1.cd5b6872b020cp-5, -0x1.49e0a3d70a3d8p-4, -0x1.d64d40da740dbp-4},
     44117},
    {"jma_norm01_calcaneus_right.stl",
     Kind::kLocalised,
     "cap_triangulation_failed",
     {-0x1.8b14fc18f6146p-5, -0x1.a29af4b43e853p-4, -0x1.02050812fd474p-3},
     {-0x1.480d2714dcbfp-3, -0x1.f8f9fe5d276c6p-1, 0x1.46918bf99b9ffp-5},
     {-0x1.2bd4402bb0cf9p-5, -0x1.a5d44c756b2dcp-4, -0x1.8cb478d4fdf3bp-4},
     -1,
     false},
    {"jma_norm01_calcaneus_right.stl",
     Kind::kSlab,
     "sliver_split",
     {-0x1.df690d828a218p-5, -0x1.ecffe18f772eep-4, -0x1.071eff132e1a7p-3},
     {0x1.3e8a40d5402dap-1, 0x1.3e6c91e7a8ae3p-1, -0x1.e6f591395fdc4p-2},
     {-0x1.07b2cc1e098ebp-4, -0x1.b0f653f7ced93p-4, -0x1.da4f867c3ece3p-4},
     14421},
    {"tcsm_ksbl_L01_fibula_distal_left.stl",
     Kind::kSlab,
     "cap_triangulation_failed",
     {0x1.f41676d254fc8p-6, -0x1.890de73a692d4p-7, -0x1.18bd5d750877p-4},
     {-0x1.65fe59f8b1084p-2, 0x1.0b9629f1b5b4ap-1, 0x1.8e1f6060064dp-1},
     {0x1.85c96de8ca11cp-6, -0x1.f0453078263acp-7, -0x1.1f0670a3d70a4p-4},
     -1,
     false},
};

class OnceRefused : public ::testing::TestWithParam<Refused> {};

TEST_P(OnceRefused, NowCutsWithEveryInvariant) {
    const Refused& c = GetParam();
    auto loaded = testing::load_shared_mesh(c.mesh);
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    const double v0 = testing::signed_volume(m);
    CutContext ctx(m);
    const Plane plane = *Plane::make(c.point, c.normal);
    const Seed seed{c.seed, c.face >= 0 ? FaceHandle(c.face) : FaceHandle(), -1.0};
    CrossSection cs;
    SlabCut slab;
    const CutResult r = c.kind == Kind::kFull        ? slice_by_plane(ctx, plane, cs)
                        : c.kind == Kind::kLocalised ? slice_by_plane(ctx, plane, seed, cs)
                                                     : subtract_slab(ctx, plane, 1e-3, seed, slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << c.mesh << " was " << c.was;
    if (c.snaps) {
        EXPECT_GE(r.stats.vertices_snapped, 1u);
    } else {
        EXPECT_EQ(r.stats.vertices_snapped, 0u) << "mended by two flips, not by snapping";
    }
    const auto rep = testing::expect_closed_2_manifold(m);
    testing::expect_face_normals_agree(m);
    if (c.kind == Kind::kSlab) {
        EXPECT_LT(rep.total_volume_m3, v0);
        return;
    }
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
    testing::expect_cross_section_consistent(m, cs, ctx.tolerance_m(), r.stats.vertices_snapped);
}

// Named by mesh, cut kind and the status it once got (unique), e.g.
// jma_norm01_calcaneus_right_full_cap_triangulation_failed.
std::string refused_name(const ::testing::TestParamInfo<Refused>& info) {
    const Refused& c = info.param;
    const std::string stem(c.mesh, std::string_view(c.mesh).find('.'));
    const char* kind = c.kind == Kind::kFull        ? "full"
                       : c.kind == Kind::kLocalised ? "localised"
                                                    : "slab";
    return stem + "_" + kind + "_" + c.was;
}

INSTANTIATE_TEST_SUITE_P(CleanSharedMeshes, OnceRefused, ::testing::ValuesIn(kRefused),
                         refused_name);

}  // namespace
}  // namespace kerf::cut
