// A slab cut that ended in internal_error on a clean shared bone with the lower wall already cut
// (issue 10 item 5), cut 47 of a random sequence on the right calcaneus. The dry run planned both
// walls on the unedited mesh; the lower wall then split a cap triangle of an earlier cut (a
// needle: 105 tolerances wide at its rim edge, its apex 29,000 tolerances away below the lower
// plane) and took the quad part's diagonal from the rim vertex 75 tolerances above the upper
// plane, leaving a needle 2.3 tolerances wide at the lower wall. The upper wall, re-planned on the
// edited mesh, cut a corner off that needle too small to keep and too far from the plane to snap
// (sliver_split). Such diagonals are now flipped (the quad's other diagonal: same plane, same
// area) and the upper wall planned again. The planes are the hex floats the scratch sequence
// drew (kind 0-3 localised with the plane point as seed, 4 full, 5 slab 0.02 * scale_m wide), in
// order, from the shared mesh, less the 5 that were refused (sliver_split) when it was recorded:
// they left the mesh unchanged, and now that a plan refused for a split part is tried once more
// with the merges of close points first (plan_snapped) they cut, and the sequence went elsewhere.
//
// The first of them (kNeedleSlab, after the first 17) is a test of its own: a slab whose wall
// crosses needles of earlier caps thinner than tol, each with two cut points within tol of each
// other; the part between them was below the one threshold and the slab was refused.
#include <gtest/gtest.h>

#include <span>

#include "display/cut/components.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/slice_sweep.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

using testing::SeededCut;

const SeededCut kNeedleSlab = {
    5,
    {-0x1.74ff7d15d4179p-5, -0x1.a71f713a27badp-4, -0x1.c8bce018c0648p-4},
    {0x1.c460ac85d490ep-1, 0x1.358c9f0136b8cp-1, -0x1.9ffaaf014f04p-4},
    {-0x1.74ff7d15d4179p-5, -0x1.a71f713a27badp-4, -0x1.c8bce018c0648p-4},
    92474};

const SeededCut kCalcaneusCuts[] = {
    {0,
     {-0x1.ca841d5acb6f5p-6, -0x1.0eef7983c131dp-3, -0x1.cd721f671529bp-4},
     {0x1.3a93a266f770ap-1, 0x1.36181ac3d0f12p-1, 0x1.ec524c8ce378p-4},
     {-0x1.ca841d5acb6f5p-6, -0x1.0eef7983c131dp-3, -0x1.cd721f671529bp-4},
     45271},
    {1,
     {-0x1.e25c5d867c3edp-6, -0x1.4b6bd9c54a692p-4, -0x1.b10a13cc1e099p-4},
     {0x1.53dbdbab664cp-4, 0x1.d26528b89f26p-5, -0x1.cde3d099ceb4ep-2},
     {-0x1.e25c5d867c3edp-6, -0x1.4b6bd9c54a692p-4, -0x1.b10a13cc1e099p-4},
     20445},
    {2,
     {-0x1.9325ac083126fp-5, -0x1.b22c5b7a32847p-4, -0x1.0b28ac083126fp-3},
     {0x1.7d0635dbcfc0cp-1, -0x1.ec32a9e7bed71p-1, 0x1.352e440981688p-2},
     {-0x1.9325ac083126fp-5, -0x1.b22c5b7a32847p-4, -0x1.0b28ac083126fp-3},
     4176},
    {2,
     {-0x1.600d74bc6a7fp-5, -0x1.9254cc1e098ebp-4, -0x1.53e1dbd194238p-4},
     {0x1.ab0abb7359a2p-2, 0x1.265e991510a84p-2, -0x1.0aac5b593f366p-1},
     {-0x1.600d74bc6a7fp-5, -0x1.9254cc1e098ebp-4, -0x1.53e1dbd194238p-4},
     30219},
    {4,
     {-0x1.38fe189374bc7p-5, -0x1.74c553f7ced93p-4, -0x1.064872015d868p-3},
     {-0x1.2f0567788b1bp-2, 0x1.2205d4004a5c2p-1, 0x1.1f7837d28ed8p-4},
     {-0x1.38fe189374bc7p-5, -0x1.74c553f7ced93p-4, -0x1.064872015d868p-3},
     -1},
    {5,
     {-0x1.bff84fdf3b645p-5, -0x1.1a61d3a06d3a1p-3, -0x1.1e62ee402bb0dp-3},
     {0x1.3970314eb52ep-5, 0x1.1eded40ab82ecp-2, -0x1.6a1b4fbd5344ap-1},
     {-0x1.bff84fdf3b645p-5, -0x1.1a61d3a06d3a1p-3, -0x1.1e62ee402bb0dp-3},
     826},
    {0,
     {-0x1.fbb4888888888p-5, -0x1.808b0aec33e2p-4, -0x1.efbdd9c54a693p-4},
     {0x1.21900e1a077b8p-2, 0x1.6b37d5db5fbd4p-1, -0x1.b9c99109a075p-4},
     {-0x1.fbb4888888888p-5, -0x1.808b0aec33e2p-4, -0x1.efbdd9c54a693p-4},
     40783},
    {1,
     {-0x1.04a9d6b2dbd19p-5, -0x1.97b4e978d4fep-4, -0x1.d2d3147ae147bp-4},
     {-0x1.eae87ccfaab08p-2, 0x1.8755591d1a7d8p-1, -0x1.0ed49981d2fcp-3},
     {-0x1.04a9d6b2dbd19p-5, -0x1.97b4e978d4fep-4, -0x1.d2d3147ae147bp-4},
     15654},
    {2,
     {-0x1.c9edbfd44f308p-5, -0x1.31db63ab596dfp-3, -0x1.fdfeb900aec34p-4},
     {0x1.247c61329b57ap-1, -0x1.a8bb29a92f254p-3, -0x1.dc2eba9683f4p-1},
     {-0x1.c9edbfd44f308p-5, -0x1.31db63ab596dfp-3, -0x1.fdfeb900aec34p-4},
     38267},
    {2,
     {-0x1.d308cd7b900afp-5, -0x1.60cc70a3d70a4p-4, -0x1.96a7020c49ba5p-4},
     {-0x1.77394c3aeec6bp-1, 0x1.e5b9dc546b67p-2, 0x1.74186054d1eep-3},
     {-0x1.d308cd7b900afp-5, -0x1.60cc70a3d70a4p-4, -0x1.96a7020c49ba5p-4},
     51816},
    {4,
     {-0x1.02cfc39109c2cp-5, -0x1.946fda4212053p-4, -0x1.c38d1fd230b6bp-4},
     {0x1.e6f8e9e74486p-2, 0x1.ec19260fefc4cp-1, 0x1.713e48192a064p-1},
     {-0x1.02cfc39109c2cp-5, -0x1.946fda4212053p-4, -0x1.c38d1fd230b6bp-4},
     -1},
    {5,
     {-0x1.b043cac083127p-5, -0x1.4471bd194238p-4, -0x1.e1e5c54a69218p-4},
     {0x1.ab888f6a3d5p-7, -0x1.d32e442120f5dp-1, 0x1.bd82c2e22347p-1},
     {-0x1.b043cac083127p-5, -0x1.4471bd194238p-4, -0x1.e1e5c54a69218p-4},
     42746},
    {0,
     {-0x1.0b89596de8ca1p-5, -0x1.93586c8b43958p-4, -0x1.9cfdfea27983cp-4},
     {-0x1.6c30838f4e75dp-1, -0x1.8bbc2b6d3a93ep-1, 0x1.4c4e06c2d422p-1},
     {-0x1.0b89596de8ca1p-5, -0x1.93586c8b43958p-4, -0x1.9cfdfea27983cp-4},
     23425},
    {1,
     {-0x1.0141a22222222p-5, -0x1.8b8696de8ca13p-4, -0x1.9ed22f1a9fbe8p-4},
     {0x1.191059ba6457p-3, -0x1.3a5440adc12cdp-1, -0x1.3b9e7a2e2ce9cp-3},
     {-0x1.0141a22222222p-5, -0x1.8b8696de8ca13p-4, -0x1.9ed22f1a9fbe8p-4},
     23100},
    {2,
     {-0x1.1ac86ab076a51p-5, -0x1.9e8c7ffc79bd8p-4, -0x1.d246d23a2d463p-4},
     {0x1.14b91c522f56p-2, -0x1.2a3b94d5141cp-1, 0x1.86e2f6632305p-3},
     {-0x1.1ac86ab076a51p-5, -0x1.9e8c7ffc79bd8p-4, -0x1.d246d23a2d463p-4},
     83580},
    {2,
     {-0x1.b5f9c962fc963p-5, -0x1.420b3d70a3d71p-4, -0x1.cfd1402bb0cf8p-4},
     {0x1.7dd0f4c52d30cp-2, 0x1.614776020248p-1, 0x1.345b1f92a288p-2},
     {-0x1.b5f9c962fc963p-5, -0x1.420b3d70a3d71p-4, -0x1.cfd1402bb0cf8p-4},
     15991},
    {4,
     {-0x1.0659378560803p-5, -0x1.94ccbd87b7e0dp-4, -0x1.bef8087fe77fbp-4},
     {-0x1.5049dee6c8ac4p-1, 0x1.6f2d869be9a78p-3, -0x1.9289d7ffd51cp-4},
     {-0x1.0659378560803p-5, -0x1.94ccbd87b7e0dp-4, -0x1.bef8087fe77fbp-4},
     -1},
    {0,
     {-0x1.5545888888888p-5, -0x1.0a04777777778p-3, -0x1.98d0c33e1f671p-4},
     {-0x1.abef5dc294954p-1, 0x1.a4af28f413254p-1, 0x1.fdd7f11468624p-1},
     {-0x1.5545888888888p-5, -0x1.0a04777777778p-3, -0x1.98d0c33e1f671p-4},
     23835},
    {1,
     {-0x1.afe07b04c601dp-5, -0x1.3afdb10617ca9p-4, -0x1.b1dec9890a4e1p-4},
     {-0x1.3455153b76ccep-1, 0x1.e35a804d3f37p-2, -0x1.95ff154edb87p-1},
     {-0x1.afe07b04c601dp-5, -0x1.3afdb10617ca9p-4, -0x1.b1dec9890a4e1p-4},
     48597},
    {2,
     {-0x1.09eb55fdaac95p-5, -0x1.995b92dd98544p-4, -0x1.baa65653082ffp-4},
     {-0x1.2f69ecfc0c49p-3, -0x1.7c07e1f659e8ap-1, 0x1.1d3b09cba1becp-2},
     {-0x1.09eb55fdaac95p-5, -0x1.995b92dd98544p-4, -0x1.baa65653082ffp-4},
     84270},
    {2,
     {-0x1.189a73fbc3e59p-5, -0x1.7401960042dbdp-4, -0x1.e6fc61772d669p-4},
     {-0x1.5d35dad471aa8p-1, -0x1.72c8e2d16b55bp-1, 0x1.5c5f354ec46cp-2},
     {-0x1.189a73fbc3e59p-5, -0x1.7401960042dbdp-4, -0x1.e6fc61772d669p-4},
     72097},
    {5,
     {-0x1.19b0d7b900aecp-4, -0x1.0d86b645a1cacp-3, -0x1.f84517e4b17e5p-4},
     {-0x1.54e7a0939a7e1p-1, -0x1.c2f30bf1238bcp-2, -0x1.d248136bdac23p-1},
     {-0x1.19b0d7b900aecp-4, -0x1.0d86b645a1cacp-3, -0x1.f84517e4b17e5p-4},
     39005},
    {0,
     {-0x1.0a2cbda9b7904p-5, -0x1.99b6a875ffa13p-4, -0x1.bb259cde75a9bp-4},
     {0x1.d7222eda2fd3ap-1, 0x1.82d1ef246b66p-2, -0x1.f3316eac3f5e8p-3},
     {-0x1.0a2cbda9b7904p-5, -0x1.99b6a875ffa13p-4, -0x1.bb259cde75a9bp-4},
     59000},
    {1,
     {-0x1.f8ac10aac666dp-6, -0x1.859f2f1ee2d09p-4, -0x1.b4263fc4c0477p-4},
     {0x1.f1f01360e404p-3, 0x1.f948984af1124p-1, 0x1.a72c784de7058p-1},
     {-0x1.f8ac10aac666dp-6, -0x1.859f2f1ee2d09p-4, -0x1.b4263fc4c0477p-4},
     91948},
    {2,
     {-0x1.6ac23a06d3a07p-5, -0x1.e83c83126e979p-4, -0x1.1437126e978d5p-3},
     {-0x1.eb54aa22edfb8p-2, -0x1.e58128f143501p-1, 0x1.760bebf8d7a48p-3},
     {-0x1.6ac23a06d3a07p-5, -0x1.e83c83126e979p-4, -0x1.1437126e978d5p-3},
     2412},
    {2,
     {-0x1.26e7a77704984p-5, -0x1.65f94a8079e75p-4, -0x1.f592c60f83fcbp-4},
     {-0x1.cfe2879ddf414p-3, -0x1.4d6626f9d1b46p-1, -0x1.4fd589e44a28cp-1},
     {-0x1.26e7a77704984p-5, -0x1.65f94a8079e75p-4, -0x1.f592c60f83fcbp-4},
     87100},
    {4,
     {-0x1.e31eb2dbd1943p-5, -0x1.08a82a53490bap-3, -0x1.90604fdf3b645p-4},
     {0x1.6fb9bb048abcp-6, -0x1.d864cfc8789ep-6, 0x1.9c5bc6cdfb274p-2},
     {-0x1.e31eb2dbd1943p-5, -0x1.08a82a53490bap-3, -0x1.90604fdf3b645p-4},
     -1},
    {5,
     {-0x1.06564d8063ef8p-5, -0x1.967119947185dp-4, -0x1.c200a3652b1e5p-4},
     {-0x1.50e5aa55e9f2p-1, 0x1.95655f97d4058p-1, -0x1.8de0cb34b82d8p-1},
     {-0x1.06564d8063ef8p-5, -0x1.967119947185dp-4, -0x1.c200a3652b1e5p-4},
     106677},
    {0,
     {-0x1.f79375d45d5dfp-5, -0x1.db7949d2a7bdp-4, -0x1.efe7460b93608p-4},
     {-0x1.eab31d14d73cfp-1, -0x1.6b2cb1d90b332p-2, 0x1.f1010b0606f26p-1},
     {-0x1.f79375d45d5dfp-5, -0x1.db7949d2a7bdp-4, -0x1.efe7460b93608p-4},
     94129},
    {1,
     {-0x1.114b8b4395811p-4, -0x1.effa51eb851ebp-4, -0x1.0219be76c8b43p-3},
     {0x1.a6595b2fa4a84p-1, 0x1.76b6fbea3d71p-2, 0x1.1ef014c0749f4p-1},
     {-0x1.114b8b4395811p-4, -0x1.effa51eb851ebp-4, -0x1.0219be76c8b43p-3},
     6928},
    {2,
     {-0x1.ca79b2dbd1943p-5, -0x1.0aeb111111111p-3, -0x1.9b913b645a1cbp-4},
     {0x1.cc984ae747694p-2, -0x1.9f1a21be8258p-7, 0x1.dccd3f56e7b1cp-1},
     {-0x1.ca79b2dbd1943p-5, -0x1.0aeb111111111p-3, -0x1.9b913b645a1cbp-4},
     23598},
    {2,
     {-0x1.02964d57b4cffp-5, -0x1.8b96e8e132684p-4, -0x1.9f28dadc6be95p-4},
     {0x1.c3cf62f12ee8p-7, -0x1.54844be596fa6p-2, 0x1.4704f603840bcp-2},
     {-0x1.02964d57b4cffp-5, -0x1.8b96e8e132684p-4, -0x1.9f28dadc6be95p-4},
     91842},
    {0,
     {-0x1.46ade5bb1668dp-5, -0x1.b483c8a0c4b8bp-4, -0x1.c62afeced0fbcp-4},
     {0x1.fd1979763102cp-2, -0x1.da05853492fa8p-3, -0x1.0472f1abe9edcp-2},
     {-0x1.46ade5bb1668dp-5, -0x1.b483c8a0c4b8bp-4, -0x1.c62afeced0fbcp-4},
     76512},
    {1,
     {-0x1.46a4cac083127p-5, -0x1.2f4cb645a1cacp-4, -0x1.b9f9a6921736p-4},
     {0x1.dc2b0235b5e84p-2, -0x1.28b8a143b3504p-3, -0x1.8a4caa986a399p-1},
     {-0x1.46a4cac083127p-5, -0x1.2f4cb645a1cacp-4, -0x1.b9f9a6921736p-4},
     47958},
    {2,
     {-0x1.aba6fb913f998p-5, -0x1.68b37085b757fp-4, -0x1.5ba6c2e27bbb8p-4},
     {-0x1.a2081c889da7cp-2, 0x1.3ff62bcfd42bep-1, 0x1.4e57b7e93085p-1},
     {-0x1.aba6fb913f998p-5, -0x1.68b37085b757fp-4, -0x1.5ba6c2e27bbb8p-4},
     64179},
    {2,
     {-0x1.2e895cd7b900bp-5, -0x1.3868acb6f4651p-4, -0x1.a217555555555p-4},
     {-0x1.50956581322cp-2, 0x1.67826412d4fe8p-3, -0x1.aa167bf524b74p-1},
     {-0x1.2e895cd7b900bp-5, -0x1.3868acb6f4651p-4, -0x1.a217555555555p-4},
     50757},
    {4,
     {-0x1.5261714ec961bp-5, -0x1.ab6184af46d8bp-4, -0x1.fe7bbf8c4931dp-4},
     {0x1.785ce751ae4f8p-3, -0x1.90912b4c4bc43p-1, -0x1.126e450b859p-1},
     {-0x1.5261714ec961bp-5, -0x1.ab6184af46d8bp-4, -0x1.fe7bbf8c4931dp-4},
     -1},
    {5,
     {-0x1.9e39a6921735fp-5, -0x1.ed3fb900aec34p-4, -0x1.1d84d3a06d3a1p-3},
     {-0x1.a1aa4728f57a6p-2, -0x1.790cd27ddd544p-3, 0x1.8591765e6ef48p-1},
     {-0x1.9e39a6921735fp-5, -0x1.ed3fb900aec34p-4, -0x1.1d84d3a06d3a1p-3},
     31443},
    {0,
     {-0x1.48ae242e6bdc8p-5, -0x1.412406d3a06d4p-4, -0x1.8a421f671529bp-4},
     {0x1.0f68c835359d8p-2, 0x1.9282ac178afd6p-1, 0x1.a08636d452d1ep-1},
     {-0x1.48ae242e6bdc8p-5, -0x1.412406d3a06d4p-4, -0x1.8a421f671529bp-4},
     25640},
    {1,
     {-0x1.5206fa2405353p-5, -0x1.aeaa017847bebp-4, -0x1.f9a170a34f1ffp-4},
     {0x1.dc5545c6abde8p-3, -0x1.c8192cf761506p-2, 0x1.748b285774762p-1},
     {-0x1.5206fa2405353p-5, -0x1.aeaa017847bebp-4, -0x1.f9a170a34f1ffp-4},
     145823},
    {2,
     {-0x1.e0d0d7b900aecp-5, -0x1.72ac485cd7b9p-4, -0x1.c3e8f87d9c54bp-4},
     {-0x1.e2f85324ec09ep-1, -0x1.a8862df588858p-3, 0x1.3ebaebbec43dcp-2},
     {-0x1.e0d0d7b900aecp-5, -0x1.72ac485cd7b9p-4, -0x1.c3e8f87d9c54bp-4},
     17779},
    {2,
     {-0x1.dd88b54d2d82p-6, -0x1.6c1f989686d75p-4, -0x1.b5e0a4ab96bfbp-4},
     {0x1.236a94190ea82p-1, 0x1.f1805d42590ap-3, 0x1.fb05161f4fa44p-1},
     {-0x1.dd88b54d2d82p-6, -0x1.6c1f989686d75p-4, -0x1.b5e0a4ab96bfbp-4},
     98324},
    {5,
     {-0x1.42ef43ad3696bp-5, -0x1.b15b4048adf7cp-4, -0x1.f6336dbaf09f4p-4},
     {-0x1.6d05f848a1261p-1, -0x1.5152abb51b49cp-1, 0x1.40c8178a66b3p-1},
     {-0x1.42ef43ad3696bp-5, -0x1.b15b4048adf7cp-4, -0x1.f6336dbaf09f4p-4},
     130042},
};

TEST(SlabRimNeedleRegression, CalcaneusSlabWhoseUpperWallMeetsALowerWallNeedleIsCut) {
    auto loaded = testing::load_shared_mesh("jma_norm01_calcaneus_right.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    const std::size_t last = std::size(kCalcaneusCuts) - 1;
    ASSERT_EQ(testing::replay_cuts(ctx, std::span(kCalcaneusCuts).first(last), kerf_m), last)
        << "an earlier cut ended in internal_error";
    SlabCut slab;
    const SeededCut& c = kCalcaneusCuts[last];
    ASSERT_EQ(c.kind, 5);
    ctx.grow_capacity();
    const TriMesh before = m;
    const double v0 = testing::expect_closed_2_manifold(before).total_volume_m3;
    const Plane plane = *Plane::make(c.point, c.normal);
    const CutResult r = subtract_slab(ctx, plane, kerf_m, testing::seed_of(c), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    // Both walls cut, and what is gone is the material of the seed's body between the planes:
    // its volume found independently of any cut, as the flux of clamp(s, 0, kerf) n through the
    // body's surface before the cut (s the signed distance to the lower plane: the divergence is
    // 1 inside the slab, 0 outside). Two slices of a copy cannot serve as the reference here:
    // full slices on these planes refuse elsewhere on this mesh, and two localised slices meet
    // the same needle. The body is the one nearest a point of the remaining lower cap.
    ASSERT_FALSE(slab.lower.negative.cap_faces.empty());
    EXPECT_FALSE(slab.upper.positive.cap_faces.empty());
    const double removed = testing::seed_body_band_volume(before, m, slab, plane, kerf_m);
    ASSERT_GT(removed, 0.0);
    const auto rep = testing::expect_closed_2_manifold(m);
    EXPECT_NEAR(rep.total_volume_m3, v0 - removed, 1e-9 * v0);
    testing::expect_face_normals_agree(m);
}

TEST(SlabRimNeedleRegression, ASlabCrossingNeedlesOfEarlierCapsMergesTheirCutPoints) {
    auto loaded = testing::load_shared_mesh("jma_norm01_calcaneus_right.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    ASSERT_EQ(testing::replay_cuts(ctx, std::span(kCalcaneusCuts).first(17), kerf_m), 17u)
        << "an earlier cut ended in internal_error";
    ctx.grow_capacity();
    const TriMesh before = m;
    const double v0 = testing::expect_closed_2_manifold(before).total_volume_m3;
    const Plane plane = *Plane::make(kNeedleSlab.point, kNeedleSlab.normal);
    SlabCut slab;
    const CutResult r = subtract_slab(ctx, plane, kerf_m, testing::seed_of(kNeedleSlab), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    EXPECT_GT(r.stats.vertices_merged, 0u);
    const double removed =
        testing::seed_body_slab_reference(before, plane, kerf_m, kNeedleSlab.point);
    const auto rep = testing::expect_closed_2_manifold(m);
    ASSERT_GT(removed, 0.0);
    // Each merge moves a vertex by up to tol (volume_change_bound).
    EXPECT_NEAR(rep.total_volume_m3, v0 - removed,
                testing::volume_change_bound(v0, r.stats.vertices_merged, ctx.tolerance_m(),
                                             testing::surface_area(m)));
    testing::expect_face_normals_agree(m);
}

}  // namespace
}  // namespace kerf::cut
