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

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;
using testing::SeededCut;

// The tube sequence up to its 17th cut (kind: 0-2 localised, 3 a chevron's second limb, 4 full,
// 5 slab; hex floats; the hint is the face the seed search found when recorded). Drawn by
// sequential_cut_test's random_face_cut with the tube's seed (100000 + 128); the 10th cut, a full
// plane, was refused too (sliver_split, with or without chords) and leaves the mesh as it was.
const SeededCut kTubeCuts[] = {
    {0,
     {0x1.447aec74808fp-9, -0x1.6611f28e048cp-8, 0x1.2411983143bd2p-5},
     {0x1.3ade6b359f696p-1, 0x1.8a9c29492d47fp-2, -0x1.603d3378514a8p-1},
     {0x1.447aec74808fp-9, -0x1.6611f28e048cp-8, 0x1.2411983143bd2p-5},
     70864},
    {4,
     {-0x1.3f89d5e7424e8p-9, -0x1.c9f5182c95cc4p-10, 0x1.b457f8f652b1cp-6},
     {-0x1.418d04988393cp-1, -0x1.82cc98ca5b9aep-1, -0x1.7e515142163aap-3},
     {-0x1.3f89d5e7424e8p-9, -0x1.c9f5182c95cc4p-10, 0x1.b457f8f652b1cp-6},
     -1},
    {2,
     {-0x1.80403bd501b31p-8, -0x1.4bf568415acdbp-10, 0x1.54a12a671a915p-6},
     {-0x1.6a0b2e9768917p-1, -0x1.8b3c399b91803p-4, 0x1.66a59962a653bp-1},
     {-0x1.80403bd501b31p-8, -0x1.4bf568415acdbp-10, 0x1.54a12a671a915p-6},
     41097},
    {3,
     {-0x1.80403bd501b31p-8, -0x1.4bf568415acdbp-10, 0x1.54a12a671a915p-6},
     {0x1.07f0beb0cde9cp-2, -0x1.89eec9075b13cp-5, 0x1.ee1632eabb2cfp-1},
     {-0x1.877756014becdp-8, 0x1.7a47ffc1046p-12, 0x1.567b19fccfb43p-6},
     109258},
    {5,
     {-0x1.01020e17f9282p-11, -0x1.87cbbb0ec78c8p-8, 0x1.f9506828d1bap-6},
     {-0x1.fd6e1aa059a46p-2, 0x1.c8f1b963c51fcp-2, -0x1.7cdfa7739b04fp-1},
     {-0x1.01020e17f9282p-11, -0x1.87cbbb0ec78c8p-8, 0x1.f9506828d1bap-6},
     61117},
    {0,
     {-0x1.96f9d86204091p-11, 0x1.7bb748ed3997bp-9, 0x1.6855dc7588018p-11},
     {0x1.fbad1431d24e2p-4, 0x1.9253b487b9f7cp-1, 0x1.363dde6974ad5p-1},
     {-0x1.96f9d86204091p-11, 0x1.7bb748ed3997bp-9, 0x1.6855dc7588018p-11},
     1355},
    {4,
     {-0x1.6d997b721b28cp-8, -0x1.20f332397aaa8p-9, 0x1.0abb8eb1002d1p-5},
     {0x1.b57ef42baa24fp-4, 0x1.58d7b366afd3dp-1, -0x1.767b7245c92f5p-1},
     {-0x1.6d997b721b28cp-8, -0x1.20f332397aaa8p-9, 0x1.0abb8eb1002d1p-5},
     -1},
    {2,
     {-0x1.2bc20c2b5785ep-8, 0x1.fca6624288753p-9, 0x1.85e4e78b2c299p-6},
     {-0x1.7cd0729df4e42p-1, -0x1.d20539d3396b5p-3, 0x1.41cb240b54345p-1},
     {-0x1.2bc20c2b5785ep-8, 0x1.fca6624288753p-9, 0x1.85e4e78b2c299p-6},
     47202},
    {3,
     {-0x1.2bc20c2b5785ep-8, 0x1.fca6624288753p-9, 0x1.85e4e78b2c299p-6},
     {0x1.50dd9988aca8ep-2, -0x1.549ee7e6a31d8p-4, 0x1.e19fb4e2fed3p-1},
     {-0x1.f62c15311dc9fp-9, 0x1.2322887f8ad8p-10, 0x1.83dcb6d86d7e3p-6},
     118786},
    {5,
     {-0x1.0690da214ea43p-8, -0x1.d1f94a1ff6c39p-10, 0x1.066a1d7f723c7p-5},
     {0x1.de7905e3d2cd3p-2, -0x1.5bdc72417379fp-1, 0x1.21a8d211d5425p-1},
     {-0x1.0690da214ea43p-8, -0x1.d1f94a1ff6c39p-10, 0x1.066a1d7f723c7p-5},
     106877},
    {0,
     {0x1.447aec74808fp-9, 0x1.6611f28e048cp-8, 0x1.00e135a9c975p-5},
     {0x1.79e84b0ed10c6p-1, 0x1.28bd0332cce69p-1, -0x1.61b3d6d47d011p-2},
     {0x1.447aec74808fp-9, 0x1.6611f28e048cp-8, 0x1.00e135a9c975p-5},
     61999},
    {4,
     {-0x1.5bbc5f6baccb9p-10, 0x1.60920fc69095fp-9, 0x1.de9208cc18a1dp-7},
     {0x1.e07053d1b615ep-4, 0x1.e569a8a6afcbcp-1, -0x1.2ebbc877a73d7p-2},
     {-0x1.5bbc5f6baccb9p-10, 0x1.60920fc69095fp-9, 0x1.de9208cc18a1dp-7},
     -1},
    {2,
     {0x1.7bb748ed3997bp-9, 0x1.96f9d86204093p-11, 0x1.dbc15d132d91dp-6},
     {-0x1.b46dc8ca657b9p-2, -0x1.c0d226b0f7349p-1, 0x1.c994b0a088b34p-3},
     {0x1.7bb748ed3997bp-9, 0x1.96f9d86204093p-11, 0x1.dbc15d132d91dp-6},
     57611},
    {3,
     {0x1.7bb748ed3997bp-9, 0x1.96f9d86204093p-11, 0x1.dbc15d132d91dp-6},
     {0x1.5526216c5c3d4p-3, -0x1.f01267526e00ep-1, 0x1.76dd9e37d25fdp-3},
     {0x1.05ee016e47b4cp-8, 0x1.174e44ccb2754p-10, 0x1.085bc6372701fp-5},
     125075},
    {5,
     {0x1.433e27543c95ap-9, 0x1.bf7013f9ccdb5p-10, 0x1.7939e2cb0a618p-5},
     {-0x1.baede9fe25c0cp-1, -0x1.e1a4687b2381ap-2, -0x1.64f00d0c04791p-3},
     {0x1.433e27543c95ap-9, 0x1.bf7013f9ccdb5p-10, 0x1.7939e2cb0a618p-5},
     91417},
    {0,
     {-0x1.579d549c141f3p-8, -0x1.7deaa66fef4dp-9, 0x1.eca56368aff2p-6},
     {0x1.66358aa69e735p-1, 0x1.dcb79eb38c579p-2, -0x1.158434cd898b4p-1},
     {-0x1.579d549c141f3p-8, -0x1.7deaa66fef4dp-9, 0x1.eca56368aff2p-6},
     59541},
    {4,
     {-0x1.127f2e1f9f309p-13, -0x1.87f6894032661p-8, 0x1.e9b8ff823642cp-6},
     {0x1.76cc9e2b9e34ap-2, 0x1.38953e0374536p-1, 0x1.679b69ea94bc1p-1},
     {-0x1.127f2e1f9f309p-13, -0x1.87f6894032661p-8, 0x1.e9b8ff823642cp-6},
     -1},
    {2,
     {0x1.6d997b721b28bp-9, -0x1.20f332397aaafp-10, 0x1.6c8ede0ae8997p-5},
     {-0x1.8b37076e4dddp-5, -0x1.afed0bd09396cp-1, 0x1.11d040e9ba59bp-1},
     {0x1.6d997b721b28bp-9, -0x1.20f332397aaafp-10, 0x1.6c8ede0ae8997p-5},
     88561},
    {3,
     {0x1.6d997b721b28bp-9, -0x1.20f332397aaafp-10, 0x1.6c8ede0ae8997p-5},
     {-0x1.34740297b63c4p-6, -0x1.a4f3608195619p-1, -0x1.234b00f2028cfp-1},
     {0x1.ee5ea6c96013dp-9, -0x1.3ec81d9b4dfep-10, 0x1.6bd04474b88d4p-5},
     138347},
    {5,
     {0x1.f972880167624p-10, 0x1.743f8ac36135dp-8, 0x1.1c53bff4bd512p-5},
     {0x1.1527ddfcea079p-1, -0x1.69f27e959b2f3p-1, -0x1.d2253bb2380eep-2},
     {0x1.f972880167624p-10, 0x1.743f8ac36135dp-8, 0x1.1c53bff4bd512p-5},
     68659},
    {0,
     {0x1.dd19122186e7cp-9, -0x1.a68e2a3d5cd18p-10, 0x1.6699c26d2afa3p-5},
     {0x1.5a28657efcb83p-7, -0x1.089640c97e618p-1, -0x1.b64d457daa46bp-1},
     {0x1.dd19122186e7cp-9, -0x1.a68e2a3d5cd18p-10, 0x1.6699c26d2afa3p-5},
     139779}};

TEST(CapChordRegression, ALocalisedSliceAcrossAnEarlierCapRefusedBeforeTheChordsIsCut) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, 128, (100000 - 4 * 128) / (4 * 128));
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    const std::size_t last = std::size(kTubeCuts) - 1;
    ASSERT_EQ(testing::replay_cuts(ctx, std::span(kTubeCuts).first(last), kerf_m), last)
        << "an earlier cut ended in internal_error";
    const SeededCut& c = kTubeCuts[last];
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
