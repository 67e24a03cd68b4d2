// A full-plane cut of a random sequence on the distal fibula (issue 10 item 3 in sequences) that
// left a triangle of zero area (twice-area 4e-21 m^2, the one threshold 2e-15 x 2) for the rest of
// the sequence. Two cut points of the plane within tol of each other were merged
// (merge_close_points: the second edge's split vertex collapsed into the first's, 0.9 tol away);
// the face on the other side of the dropped point's edge, a thin triangle of an earlier cap, was
// split there, and moving its corner onto the kept point put it on the line of the face's long
// edge. Only the link condition was checked for a merge, and the split parts only where the
// points were before it. Now the split parts round every merged point are checked where the
// merges leave them (check_merged_split_areas), and such a plan is snapped or refused like any
// other sliver: the cut leaves no triangle below the threshold, or is refused with the mesh
// unchanged. The same happened on the 100k-triangle tube of 128 segments (cut 56).
// The cuts are the hex floats the scratch sequence drew (SeededCut: kinds 0 and 2 localised from
// a seed at the plane point, 3 a chevron's second limb from its own seed and face hint, 4 full, 5
// slab 0.02 * scale_m wide), in order, from the shared mesh.
#include <gtest/gtest.h>

#include <span>

#include "display/cut/mesh_hash.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::TriMesh;
using testing::SeededCut;

const SeededCut kFibulaCuts[] = {
    {0,
     {0x1.45a910624dd3p-6, -0x1.f68cd65b7a328p-8, -0x1.3e64e353f7cedp-5},
     {0x1.3d47e5eb71e25p-2, 0x1.a6ecf5cfbfaf3p-1, 0x1.e220005fee26ap-2},
     {0x1.45a910624dd3p-6, -0x1.f68cd65b7a328p-8, -0x1.3e64e353f7cedp-5},
     28693},
    {4,
     {0x1.a7d6078263ab5p-6, -0x1.20936bdc80577p-7, -0x1.2c500e5604189p-5},
     {0x1.615b5b5ebdc7ep-2, -0x1.9154763ea843p-1, -0x1.0850ee4918651p-1},
     {0x1.a7d6078263ab5p-6, -0x1.20936bdc80577p-7, -0x1.2c500e5604189p-5},
     -1},
    {2,
     {0x1.dc5e16872b021p-6, -0x1.422035ee402bbp-6, -0x1.df802d0e56041p-6},
     {0x1.b7b02f7d7b475p-2, 0x1.5335d37204eb5p-1, 0x1.3a3e54fb8e124p-1},
     {0x1.dc5e16872b021p-6, -0x1.422035ee402bbp-6, -0x1.df802d0e56041p-6},
     34217},
    {3,
     {0x1.dc5e16872b021p-6, -0x1.422035ee402bbp-6, -0x1.df802d0e56041p-6},
     {0x1.9c649c8d327b5p-2, 0x1.8aeea772efc2ap-2, 0x1.a902c00a2a912p-1},
     {0x1.bfc256232fb7fp-6, -0x1.177bd188277bfp-6, -0x1.f98432b723885p-6},
     43967},
    {5,
     {0x1.a0f32a53490bbp-6, -0x1.640e9db22d0e5p-6, -0x1.3d6bbf258bf25p-5},
     {0x1.6301d58b8edddp-4, -0x1.9471c7a6ce50dp-4, -0x1.fb8fcde9dfb19p-1},
     {0x1.a0f32a53490bbp-6, -0x1.640e9db22d0e5p-6, -0x1.3d6bbf258bf25p-5},
     28492},
    {0,
     {0x1.0da504189374cp-6, -0x1.fbc44dd2f1aap-8, -0x1.a781dddddddddp-5},
     {-0x1.9ce2496292ccap-5, 0x1.adbe26a9d4c74p-1, -0x1.1520729051a02p-1},
     {0x1.0da504189374cp-6, -0x1.fbc44dd2f1aap-8, -0x1.a781dddddddddp-5},
     19878},
    {4,
     {0x1.8147ff513cc1fp-6, -0x1.889caaaaaaaabp-6, -0x1.834b8b439581p-5},
     {-0x1.35a302fa0e958p-1, 0x1.267c818b6d317p-1, 0x1.1a0a60733c9f7p-1},
     {0x1.8147ff513cc1fp-6, -0x1.889caaaaaaaabp-6, -0x1.834b8b439581p-5},
     -1},
    {2,
     {0x1.2471a743039c5p-6, -0x1.c430dba97da81p-7, -0x1.1a1e882c5bc28p-5},
     {-0x1.7ca4941c12db6p-2, -0x1.bc14cddc02cc8p-4, 0x1.d80f493a481cbp-1},
     {0x1.2471a743039c5p-6, -0x1.c430dba97da81p-7, -0x1.1a1e882c5bc28p-5},
     41586},
    {3,
     {0x1.2471a743039c5p-6, -0x1.c430dba97da81p-7, -0x1.1a1e882c5bc28p-5},
     {0x1.1969083c0cd3p-4, -0x1.8fded16a1ef8ap-4, 0x1.fc56b6026dd7dp-1},
     {0x1.24f6cf1befc97p-6, -0x1.c0d8c8ed810b8p-7, -0x1.19ea85db34d4ep-5},
     50839},
    {5,
     {0x1.5b8a8dfea2798p-6, -0x1.241a916872b02p-6, -0x1.a67dd194237fbp-6},
     {0x1.3419da31a424fp-2, 0x1.ba9b70825c7ffp-1, -0x1.9c5d90f70df27p-2},
     {0x1.5b8a8dfea2798p-6, -0x1.241a916872b02p-6, -0x1.a67dd194237fbp-6},
     36255},
    {0,
     {0x1.1b4fc3ece2a54p-6, -0x1.54cd28f5c28f7p-6, -0x1.e4ca2bb0cf87dp-5},
     {-0x1.444c46de041fdp-3, -0x1.77d5029949afp-1, 0x1.521d39404e97ap-1},
     {0x1.1b4fc3ece2a54p-6, -0x1.54cd28f5c28f7p-6, -0x1.e4ca2bb0cf87dp-5},
     12920},
    {4,
     {0x1.9d0ee7c73c5ffp-6, -0x1.e7df3fec98b0dp-7, -0x1.03ce49a19aedfp-5},
     {-0x1.9e27ce894c4d8p-3, -0x1.49c1c0c04be2ep-2, -0x1.d989e1c7e41c6p-1},
     {0x1.9d0ee7c73c5ffp-6, -0x1.e7df3fec98b0dp-7, -0x1.03ce49a19aedfp-5},
     -1},
    {2,
     {0x1.0a427983c131dp-5, -0x1.537078d4fdf3bp-7, -0x1.073616872b021p-4},
     {-0x1.ba990baaa31e6p-1, -0x1.a9ed2428b562cp-2, 0x1.211f2b1d8851ap-2},
     {0x1.0a427983c131dp-5, -0x1.537078d4fdf3bp-7, -0x1.073616872b021p-4},
     8061},
    {3,
     {0x1.0a427983c131dp-5, -0x1.537078d4fdf3bp-7, -0x1.073616872b021p-4},
     {-0x1.67f9bf32a96e1p-2, -0x1.d325223951d16p-1, 0x1.ad65cb779af0fp-3},
     {0x1.e8bfb686d390fp-6, -0x1.823b492bac783p-7, -0x1.3154a1f5dcc17p-4},
     56065},
    {5,
     {0x1.b7c448587292cp-6, -0x1.620b2d81c71fdp-6, -0x1.376a9f42def1dp-5},
     {-0x1.871469ff5d82ap-1, 0x1.b3c7d50d4a1d8p-2, 0x1.f0e35c7bc4013p-2},
     {0x1.b7c448587292cp-6, -0x1.620b2d81c71fdp-6, -0x1.376a9f42def1dp-5},
     28977},
    {0,
     {0x1.dc71b75bc39afp-6, -0x1.36c3c32de464fp-6, -0x1.37f619619ca4p-5},
     {-0x1.1878d456d1aep-1, -0x1.a362f596f143ep-1, -0x1.5c95371e9c217p-3},
     {0x1.dc71b75bc39afp-6, -0x1.36c3c32de464fp-6, -0x1.37f619619ca4p-5},
     57605},
    {4,
     {0x1.5514a0e4e16c9p-6, -0x1.fbbe2f8dbeb2fp-7, -0x1.e98dc21d7ba0cp-6},
     {0x1.78be76e01149ep-1, -0x1.0e159446012a3p-2, -0x1.3f547365dd541p-1},
     {0x1.5514a0e4e16c9p-6, -0x1.fbbe2f8dbeb2fp-7, -0x1.e98dc21d7ba0cp-6},
     -1},
    {2,
     {0x1.cde447ae147adp-6, -0x1.9bd9e56041893p-6, -0x1.0105333333334p-4},
     {-0x1.ba2e6886ddde6p-4, -0x1.12f73ca8a1288p-1, 0x1.ac594fdf5be37p-1},
     {0x1.cde447ae147adp-6, -0x1.9bd9e56041893p-6, -0x1.0105333333334p-4},
     9487},
    {3,
     {0x1.cde447ae147adp-6, -0x1.9bd9e56041893p-6, -0x1.0105333333334p-4},
     {-0x1.336fa3f657d81p-4, -0x1.f4dc390b903e3p-1, 0x1.8c1ad2aab8c07p-3},
     {0x1.3c768fb0eddd8p-6, -0x1.9a5e6cfca3354p-6, -0x1.05794d1b403ccp-4},
     64043},
    {0,
     {0x1.fb7dba5e353f8p-7, -0x1.1d2ac1e098eadp-7, -0x1.a97b242e6bdc8p-5},
     {-0x1.a4e99e3d100c1p-3, -0x1.c8b05fe50727cp-2, 0x1.be03f880c2513p-1},
     {0x1.fb7dba5e353f8p-7, -0x1.1d2ac1e098eadp-7, -0x1.a97b242e6bdc8p-5},
     19505},
    {4,
     {0x1.4ef7fc962fc97p-6, -0x1.b96653490b9bp-6, -0x1.d598dbd194238p-5},
     {0x1.8ec516a1a0e38p-4, 0x1.9d976b14c909ap-1, 0x1.29a8f21d758edp-1},
     {0x1.4ef7fc962fc97p-6, -0x1.b96653490b9bp-6, -0x1.d598dbd194238p-5},
     -1},
    {2,
     {0x1.dbc93f16732b3p-6, -0x1.58b4f53448b18p-7, -0x1.c49a9d6c6eae3p-5},
     {0x1.326c64809d92dp-1, 0x1.fe8996a73bf3fp-3, -0x1.85d17013c48c6p-1},
     {0x1.dbc93f16732b3p-6, -0x1.58b4f53448b18p-7, -0x1.c49a9d6c6eae3p-5},
     50116},
    {3,
     {0x1.dbc93f16732b3p-6, -0x1.58b4f53448b18p-7, -0x1.c49a9d6c6eae3p-5},
     {-0x1.dc40eae903694p-3, 0x1.4208804673767p-3, -0x1.eb699ea90323p-1},
     {0x1.e8f98e8ab7f49p-6, -0x1.62b6b91cef7dp-7, -0x1.c03d4de390d6p-5},
     68809},
    {5,
     {0x1.2bcc024be0cbdp-6, -0x1.ebd09dd548c2cp-7, -0x1.093e9088ae5p-5},
     {-0x1.a4d6becc0fdccp-3, -0x1.1eaceff45660fp-1, -0x1.9af6fc0d33e75p-1},
     {0x1.2bcc024be0cbdp-6, -0x1.ebd09dd548c2cp-7, -0x1.093e9088ae5p-5},
     32420},
    {0,
     {0x1.34c8731e48af3p-6, -0x1.020d8c548ee4fp-6, -0x1.f8cb28a820dadp-6},
     {-0x1.b86573d6dfe5bp-1, -0x1.001836aa8a432p-1, -0x1.98c1db772f9e8p-4},
     {0x1.34c8731e48af3p-6, -0x1.020d8c548ee4fp-6, -0x1.f8cb28a820dadp-6},
     33359},
    {4,
     {0x1.03143fd44f308p-5, -0x1.c95472015d868p-7, -0x1.022296872b021p-5},
     {0x1.04060563db509p-1, -0x1.e8c0df3c8299ep-2, 0x1.6f2ad17d88766p-1},
     {0x1.03143fd44f308p-5, -0x1.c95472015d868p-7, -0x1.022296872b021p-5},
     -1},
    {2,
     {0x1.e93da925dbe24p-7, -0x1.d2c443be81d6dp-7, -0x1.f8df4631d9715p-5},
     {-0x1.abffaaf621e02p-1, -0x1.9f9c45fd0d753p-2, -0x1.7a4d4fd2d454p-2},
     {0x1.e93da925dbe24p-7, -0x1.d2c443be81d6dp-7, -0x1.f8df4631d9715p-5},
     10781},
    {3,
     {0x1.e93da925dbe24p-7, -0x1.d2c443be81d6dp-7, -0x1.f8df4631d9715p-5},
     {-0x1.127a5317c93dep-3, -0x1.ef322bf68c3f4p-1, -0x1.ba1c111a8a2c1p-3},
     {0x1.e945c312fefap-7, -0x1.d291c36ec1fcbp-7, -0x1.f8f1ba359cd8p-5},
     75319},
    {5,
     {0x1.a5153ece2a534p-6, -0x1.b0da6ff513cc3p-6, -0x1.0e2b7ae147ae1p-4},
     {0x1.e766ec09dae8fp-1, -0x1.aa78fe4ad8ac7p-6, 0x1.387231687e202p-2},
     {0x1.a5153ece2a534p-6, -0x1.b0da6ff513cc3p-6, -0x1.0e2b7ae147ae1p-4},
     6285},
    {0,
     {0x1.7a9755ce9d37cp-6, -0x1.334fdd39906b9p-6, -0x1.7f567a5f18c74p-6},
     {0x1.c83151ec989c8p-2, 0x1.ef489a280289fp-6, -0x1.ca1f70719f4fp-1},
     {0x1.7a9755ce9d37cp-6, -0x1.334fdd39906b9p-6, -0x1.7f567a5f18c74p-6},
     42969},
    {4,
     {0x1.a7a8978d4fdf4p-6, -0x1.54b6ca11bfd45p-6, -0x1.08c932846ff51p-5},
     {0x1.fa2cea9904599p-3, -0x1.96d55f7d11ef7p-1, -0x1.1bee7e7ac573cp-1},
     {0x1.a7a8978d4fdf4p-6, -0x1.54b6ca11bfd45p-6, -0x1.08c932846ff51p-5},
     -1},
    {2,
     {0x1.00c01d0d145bfp-5, -0x1.91fe3abc06eb3p-7, -0x1.4607a09ecfd54p-5},
     {0x1.19bf65f961e5ep-1, 0x1.5b5f6bd16cdc9p-1, -0x1.f2600867858d7p-2},
     {0x1.00c01d0d145bfp-5, -0x1.91fe3abc06eb3p-7, -0x1.4607a09ecfd54p-5},
     27920},
    {3,
     {0x1.00c01d0d145bfp-5, -0x1.91fe3abc06eb3p-7, -0x1.4607a09ecfd54p-5},
     {-0x1.248e9a23c5fa4p-3, 0x1.d9ee3c2f3d063p-1, -0x1.66cce63156ab6p-2},
     {0x1.caa502e9e1f71p-6, -0x1.54b206866e866p-7, -0x1.4fade5b3ac165p-5},
     81375},
    {5,
     {0x1.f4554aedd11edp-7, -0x1.9105ef4255ed5p-7, -0x1.940afc7bb2a7fp-5},
     {-0x1.6848a35cbd8d8p-1, 0x1.1e2105b5b2b07p-1, 0x1.c14f4efe3c57fp-2},
     {0x1.f4554aedd11edp-7, -0x1.9105ef4255ed5p-7, -0x1.940afc7bb2a7fp-5},
     78733},
    {0,
     {0x1.05aa4083126eap-5, -0x1.14d6983c131d6p-6, -0x1.0469b33333334p-4},
     {-0x1.0eadf774060b1p-3, -0x1.33bcfaf9a85f3p-1, 0x1.938fc685c5987p-1},
     {0x1.05aa4083126eap-5, -0x1.14d6983c131d6p-6, -0x1.0469b33333334p-4},
     8759},
    {4,
     {0x1.e910888888889p-6, -0x1.52a8d2f1a9fbfp-7, -0x1.78147983c131dp-5},
     {-0x1.72d343b8b6d72p-1, 0x1.56ae9fd0f984ap-1, 0x1.5372e459b7ef6p-3},
     {0x1.e910888888889p-6, -0x1.52a8d2f1a9fbfp-7, -0x1.78147983c131dp-5},
     -1},
    {2,
     {0x1.2d671d5acb6f5p-6, -0x1.2f5fb020c49bbp-6, -0x1.864924dd2f1abp-5},
     {-0x1.797fcc0e6518fp-1, 0x1.562c786c31029p-1, -0x1.946a60cab7e9dp-4},
     {0x1.2d671d5acb6f5p-6, -0x1.2f5fb020c49bbp-6, -0x1.864924dd2f1abp-5},
     22916},
    {3,
     {0x1.2d671d5acb6f5p-6, -0x1.2f5fb020c49bbp-6, -0x1.864924dd2f1abp-5},
     {-0x1.f783606ae5413p-1, 0x1.4a1d6fc7cf191p-3, -0x1.541d795bdf04dp-4},
     {0x1.2db9fedc7b3f7p-6, -0x1.361998837eadbp-6, -0x1.9e42303ff5024p-5},
     105321},
    {5,
     {0x1.38c8e640a942ap-6, -0x1.0d548a927f163p-6, -0x1.54a279a3fffp-5},
     {0x1.36f95fdef7475p-1, -0x1.4f0f2b6120f3ap-2, -0x1.72a376cce61ddp-1},
     {0x1.38c8e640a942ap-6, -0x1.0d548a927f163p-6, -0x1.54a279a3fffp-5},
     86715},
    {0,
     {0x1.fe23aaaaaaaabp-6, -0x1.e95c078263ab5p-7, -0x1.7cabc962fc963p-5},
     {0x1.2004af4065376p-1, -0x1.a2e6f0155eac9p-1, 0x1.e74f6eafce546p-4},
     {0x1.fe23aaaaaaaabp-6, -0x1.e95c078263ab5p-7, -0x1.7cabc962fc963p-5},
     23865},
    {4,
     {0x1.6494b17e4b17fp-6, -0x1.bfb8a06d3a06dp-7, -0x1.698a078263ab5p-6},
     {0x1.ea8fda5baf0f6p-2, -0x1.9d9b3be0f7587p-1, 0x1.5fa16b446288ep-2},
     {0x1.6494b17e4b17fp-6, -0x1.bfb8a06d3a06dp-7, -0x1.698a078263ab5p-6},
     -1},
};

TEST(MergedSplitRegression, AMergeThatWouldFlattenAThinCapTriangleLeavesNoDegenerateTriangle) {
    auto loaded = testing::load_shared_mesh("tcsm_ksbl_L01_fibula_distal_left.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    const std::size_t last = std::size(kFibulaCuts) - 1;
    ASSERT_EQ(testing::replay_cuts(ctx, std::span(kFibulaCuts).first(last), kerf_m), last)
        << "an earlier cut ended in internal_error";
    // The last, a full plane: cut without a triangle below the one threshold, or refused with
    // the mesh unchanged.
    const SeededCut& c = kFibulaCuts[last];
    ASSERT_EQ(c.kind, 4);
    ctx.grow_capacity();
    const std::uint64_t hash = mesh_hash(m);
    CrossSection cs;
    const CutResult r = slice_by_plane(ctx, *Plane::make(c.point, c.normal), cs);
    ASSERT_NE(r.status, CutStatus::kInternalError);
    if (!r.ok()) {
        EXPECT_EQ(mesh_hash(m), hash) << to_string(r.status);
    }
    testing::expect_closed_2_manifold(m);
    testing::expect_face_normals_agree(m);
}

}  // namespace
}  // namespace kerf::cut
