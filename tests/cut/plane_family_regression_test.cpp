// The three stress cuts that failed on the second family of random planes (slice_sweep.hpp
// DrawOrder::kXyz, the order clang drew them in), now cut with every invariant:
//  - two seeds on a hole of the cross-section (where the plane meets a concavity of the bone, the
//    section is a ring): refused with seed_on_inner_boundary before; now the outer loop around
//    the hole is cut, as the paper's "contiguous cross-section containing the starting point";
//  - a full slice whose pieces each reloaded from float32 STL with 1 degenerate triangle: a cap
//    triangle 1.6 um long and 9 nm high passed the cutter's area check in double and lost 79 %
//    of its area to float32 rounding; the check now bounds that rounding.
// Planes and seeds are the hex floats cut_property_test printed.
#include <gtest/gtest.h>

#include <string>

#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "tests/cut/chevron_checks.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

enum class Kind { kFull, kLocalised, kSlab };

struct NewPlaneCase {
    const char* name;  ///< test name
    const char* mesh;
    Kind kind;
    Vec3 point;  ///< plane point, m
    Vec3 normal;
    Vec3 seed;  ///< localised and slab only, m
    int face;   ///< the seed's face hint, or -1
};

const NewPlaneCase kCases[] = {
    {"MetatarsalLocalisedSeedOnAHole",
     "bp3d_right_first_metatarsal.stl",
     Kind::kLocalised,
     {0x1.09b49619a669bp-3, 0x1.c7ec8362e0f01p-4, 0x1.e293a05a0de16p-5},
     {0x1.fb83ea71c84e5p-1, -0x1.0405898063c14p-3, -0x1.29d75f8428f0bp-5},
     {0x1.088f872b020c5p-3, 0x1.d1ed9f0fb38a9p-4, 0x1.250189e60f04cp-5},
     1012},
    {"TalusSlabSeedOnAHole",
     "tcsm_ksbl_L01_talus_left.stl",
     Kind::kSlab,
     {0x1.08fe004f2d304p-6, -0x1.944a0247384fp-6, -0x1.26825753e097ap-4},
     {0x1.0b69324493de8p-5, -0x1.6d97932e24ec3p-3, 0x1.f77fb3459a933p-1},
     {-0x1.8478bc6a7ef9dp-8, -0x1.b244af72015d8p-6, -0x1.26877fa89e60fp-4},
     -1},
    {"TalusFullTinyCapTriangle",
     "jma_norm01_talus_right.stl",
     Kind::kFull,
     {-0x1.d088cd4bdb368p-5, -0x1.2200f689b40aep-3, -0x1.aaa82b7eafbc8p-4},
     {0x1.3c4daece003e7p-1, -0x1.ac95342450a82p-4, 0x1.8f080b7132a47p-1},
     {0, 0, 0},
     -1},
};

constexpr double kKerfM = 0.001;

class NewPlaneFamily : public ::testing::TestWithParam<NewPlaneCase> {};

TEST_P(NewPlaneFamily, CutsClosedWithTheRightVolumeAndRoundTripsThroughEveryFormat) {
    const NewPlaneCase& c = GetParam();
    auto loaded = testing::load_shared_mesh(c.mesh);
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    const TriMesh shape = std::move(*loaded);
    TriMesh m = shape;
    const double v0 = testing::signed_volume(m);
    CutContext ctx(m);
    const Plane plane = *Plane::make(c.point, c.normal);
    const Seed seed{c.seed, c.face >= 0 ? FaceHandle(c.face) : FaceHandle(), -1.0};
    CrossSection cs;
    SlabCut slab;
    const CutResult r = c.kind == Kind::kFull ? slice_by_plane(ctx, plane, cs)
                        : c.kind == Kind::kLocalised
                            ? slice_by_plane(ctx, plane, seed, cs)
                            : subtract_slab(ctx, plane, kKerfM, seed, slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    double expected = v0;
    if (c.kind == Kind::kSlab) {
        const double removed = testing::slab_reference_removed_volume(shape, plane, kKerfM, c.seed);
        ASSERT_GT(removed, 0.0);
        expected = v0 - removed;
    } else {
        testing::expect_cross_section_consistent(m, cs, ctx.tolerance_m(),
                                                 r.stats.vertices_snapped);
    }
    // The seed's hole is cut with the outer loop around it (and whatever else that loop holds).
    if (c.kind == Kind::kLocalised) {
        EXPECT_GE(r.stats.loops, 2u);
    }
    const auto rep = testing::expect_closed_2_manifold(m);
    EXPECT_NEAR(rep.total_volume_m3, expected, 1e-9 * v0);
    testing::expect_face_normals_agree(m);
    for (auto format :
         {mesh::Format::kStl, mesh::Format::kObj, mesh::Format::kPly, mesh::Format::kOff})
        testing::expect_pieces_round_trip(m, format, c.name);
}

INSTANTIATE_TEST_SUITE_P(CleanSharedMeshes, NewPlaneFamily, ::testing::ValuesIn(kCases),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
}  // namespace kerf::cut
