// A sequential cut across an earlier cap that the library refused before the chords (issue 10,
// item 5): the 60-cut sequence on the 100k x 128 tube (sequential_cut_test.cpp) refused its 17th
// cut, a localised slice (cap_triangulation_failed): the plane crosses an earlier cap, and the
// cut points on that cap's inner edges lie on the line where the two planes meet, a collinear
// run whose fans no flip makes acceptable. With the chord put into the earlier cap
// (cap_chords.hpp) the new rim meets that cap in two points and the cut succeeds, keeping every
// invariant. The earlier cuts are replayed as they were recorded, without chords (their face
// hints index the mesh those cuts made).
#include <gtest/gtest.h>

#include <span>

#include "display/cut/context_state.hpp"
#include "display/cut/mesh_hash.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/chevron_checks.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/mesh_invariants.hpp"
#include "tests/cut/tube_sequence_cuts.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;
using testing::kTube100k128Cuts;
using testing::SeededCut;

TEST(CapChordRegression, ALocalisedSliceAcrossAnEarlierCapRefusedBeforeTheChordsIsCut) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, 128, (100000 - 4 * 128) / (4 * 128));
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    // Entry 20 of the recorded sequence (the 17th cut, a chevron's two limbs counting as one).
    const std::size_t last = 20;
    ASSERT_EQ(testing::replay_cuts(ctx, std::span(kTube100k128Cuts).first(last), kerf_m), last)
        << "an earlier cut ended in internal_error";
    const SeededCut& c = kTube100k128Cuts[last];
    ASSERT_EQ(c.kind, 0);
    ctx.grow_capacity();
    const Plane plane = *Plane::make(c.point, c.normal);
    CrossSection cs;
    // Without the chords it is refused, the mesh unchanged.
    const std::uint64_t hash = mesh_hash(m);
    ctx.state().cap_chords = false;
    EXPECT_EQ(slice_by_plane(ctx, plane, testing::seed_of(c), cs).status,
              CutStatus::kCapTriangulationFailed);
    ctx.state().cap_chords = true;
    ASSERT_EQ(mesh_hash(m), hash) << "a refusal changed the mesh";
    // With them it is cut across the earlier cap's chords.
    const double v0 = testing::expect_closed_2_manifold(m).total_volume_m3;
    const auto first_new = static_cast<int>(m.n_vertices());
    const CutResult r = slice_by_plane(ctx, plane, testing::seed_of(c), cs);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    EXPECT_GT(r.stats.cap_chords, 0u);
    const testing::MeshReport rep = testing::expect_closed_2_manifold(m);
    EXPECT_TRUE(rep.ok) << rep.failures_log;
    EXPECT_NEAR(rep.total_volume_m3, v0,
                testing::volume_change_bound(v0, r.stats.vertices_merged, ctx.tolerance_m(),
                                             testing::surface_area(m)));
    testing::expect_face_normals_agree(m);
    testing::expect_cross_section_consistent(m, cs, ctx.tolerance_m(), r.stats.vertices_snapped);
    double nearest = 1e300;
    EXPECT_EQ(testing::close_new_vertices(m, first_new, ctx.tolerance_m(), nearest), 0)
        << "new vertices " << nearest / ctx.tolerance_m() << " tol apart";
    // Every cap face of the new cut is tagged as a cap of its side.
    for (const FaceHandle f : cs.positive.cap_faces)
        EXPECT_EQ(m.property(ctx.state().cap, f), kCapPositive);
    for (const FaceHandle f : cs.negative.cap_faces)
        EXPECT_EQ(m.property(ctx.state().cap, f), kCapNegative);
    testing::expect_pieces_round_trip(m, mesh::Format::kStl, "tube 100000 x 128 cut 16");
}

}  // namespace
}  // namespace kerf::cut
