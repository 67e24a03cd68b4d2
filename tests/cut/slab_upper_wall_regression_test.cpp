// Two slab cuts of a random sequence on generated tubes (issue 10 item 5) whose upper wall,
// planned again after the lower wall was cut, refused: the cut ended in internal_error with the
// lower wall already cut and nothing removed. The dry run plans both walls on the unedited mesh;
// the lower wall's split changes faces the upper plane also crosses, and the re-plan on them
// failed:
//  - 200k-triangle tube of 512 segments, the 48th cut of its sequence: a fan of needles on a flat
//    end disc around a vertex just beyond the upper plane (no other diagonal to flip to), so the
//    upper plane cut corners off them too small to keep (sliver_split);
//  - 200k-triangle tube of 32 segments, the 6th cut: cap_triangulation_failed on the upper
//    re-plan.
// Now every edit of a slab cut can be undone (EditUndo), and on such a refusal the walls are cut
// the other way round: the upper wall first, the lower one planned again after it. Both cuts
// succeed, removing what an independent reference says (the seed's body sliced on both planes by
// full slices). The planes are the hex floats the scratch sequence drew (kind 0-3 localised with
// the plane point as seed, 4 full, 5 slab 0.02 * scale_m wide), in order, on
// make_hollow_tube(0.05, 0.006, 0.003, segments, (200000 - 4 segments) / (4 segments)).
#include <gtest/gtest.h>

#include <span>

#include "display/cut/subtract_slab.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;
using testing::SeededCut;

const SeededCut kTube32Cuts[] = {
    {0,
     {-0x1.95340f7583919p-11, -0x1.7a33a391f0bfp-9, 0x1.0f24764bfc487p-7},
     {0x1.96ca527c8b4fp-2, -0x1.f39bd9414e0d8p-3, 0x1.17fcf2983d42p-1},
     {-0x1.95340f7583919p-11, -0x1.7a33a391f0bfp-9, 0x1.0f24764bfc487p-7},
     33132},
    {1,
     {-0x1.5a46968a25725p-9, -0x1.5f2bff186138p-8, 0x1.903dc020e30f5p-9},
     {0x1.5cf4c618524fp-2, 0x1.93933ad8dd4a2p-1, -0x1.ba661b9c7a58ap-2},
     {-0x1.5a46968a25725p-9, -0x1.5f2bff186138p-8, 0x1.903dc020e30f5p-9},
     12202},
    {2,
     {0x1.86b28e9769ee5p-8, 0x1.992251b0bed9cp-12, 0x1.cf375ac72e2bcp-6},
     {-0x1.9b073c3c0cc5bp-1, -0x1.d3a9eccbb2b92p-2, 0x1.7cda7886bd1b2p-1},
     {0x1.86b28e9769ee5p-8, 0x1.992251b0bed9cp-12, 0x1.cf375ac72e2bcp-6},
     112897},
    {2,
     {0x1.7a33a391f0bfp-9, -0x1.95340f758391bp-11, 0x1.96cd1592358dp-5},
     {-0x1.78f71486754ap-2, -0x1.f0c37827a8bd6p-2, -0x1.b0bfad506bf9cp-3},
     {0x1.7a33a391f0bfp-9, -0x1.95340f758391bp-11, 0x1.96cd1592358dp-5},
     198524},
    {4,
     {0x1.5632f6f460f83p-9, -0x1.6042e91eb2c0bp-8, 0x1.68575f8165b7p-6},
     {0x1.c4fade7356a0cp-1, 0x1.62d03f92381fap-1, -0x1.fc8f3340de135p-1},
     {0x1.5632f6f460f83p-9, -0x1.6042e91eb2c0bp-8, 0x1.68575f8165b7p-6},
     -1},
    {5,
     {-0x1.5f2bff1861381p-9, 0x1.5a46968a25721p-10, 0x1.2dee229d48d37p-6},
     {0x1.721ba2b69b122p-1, 0x1.0af77ce6e52fcp-1, 0x1.bd0ae5eb59dbcp-1},
     {-0x1.5f2bff1861381p-9, 0x1.5a46968a25721p-10, 0x1.2dee229d48d37p-6},
     73690},
};

const SeededCut kTube512Cuts[] = {
    {0,
     {-0x1.560acfc6339fcp-9, 0x1.6211dea8cfep-8, 0x1.38e38e38e38e4p-7},
     {0x1.5f5404f9bf49cp-2, -0x1.4076b8390c002p-1, 0x1.e65b1eb90bc2p-4},
     {-0x1.560acfc6339fcp-9, 0x1.6211dea8cfep-8, 0x1.38e38e38e38e4p-7},
     37192},
    {1,
     {0x1.7d080aac2c6p-9, 0x1.8467fc3402f81p-11, 0x1.4fa4fa4fa4fa5p-5},
     {-0x1.55b73b75c4866p-1, -0x1.b2b082884527ep-2, 0x1.a93f105d55838p-3},
     {0x1.7d080aac2c6p-9, 0x1.8467fc3402f81p-11, 0x1.4fa4fa4fa4fa5p-5},
     160809},
    {2,
     {0x1.4d0fe72769e7cp-8, 0x1.a202c85eda1b4p-9, 0x1.638e38e38e38fp-5},
     {0x1.54901cad3022p-1, 0x1.461038a1f682p-4, -0x1.445dad40f56d2p-1},
     {0x1.4d0fe72769e7cp-8, 0x1.a202c85eda1b4p-9, 0x1.638e38e38e38fp-5},
     170074},
    {2,
     {-0x1.8928230926b34p-9, 0x1.9bbfbe18a551dp-15, 0x1.24fa4fa4fa4fbp-6},
     {0x1.a41464c8e62ap-2, -0x1.c348eb4513348p-3, 0x1.03a42909bd0bp-2},
     {-0x1.8928230926b34p-9, 0x1.9bbfbe18a551dp-15, 0x1.24fa4fa4fa4fbp-6},
     71164},
    {4,
     {0x1.184e72f3044e8p-8, 0x1.13c1cd9b23865p-8, 0x1.60b60b60b60b7p-5},
     {0x1.665e0c231ca0ep-1, -0x1.1568f57190b0fp-1, -0x1.ba0fe1b7685b4p-3},
     {0x1.184e72f3044e8p-8, 0x1.13c1cd9b23865p-8, 0x1.60b60b60b60b7p-5},
     -1},
    {5,
     {0x1.1ab55b69f7bf5p-12, -0x1.879e440d806f8p-9, 0x1.b05b05b05b05cp-6},
     {0x1.22ad1b6fafe6p-3, -0x1.0000259b2eb1cp-3, 0x1.54854c710cb98p-1},
     {0x1.1ab55b69f7bf5p-12, -0x1.879e440d806f8p-9, 0x1.b05b05b05b05cp-6},
     104207},
    {0,
     {0x1.29f9936e83945p-10, -0x1.6be400028611p-9, 0x1.c71c71c71c71dp-8},
     {-0x1.5fecd99f910f8p-2, -0x1.c98fcfba0439dp-1, 0x1.65af9f89f9cp-7},
     {0x1.29f9936e83945p-10, -0x1.6be400028611p-9, 0x1.c71c71c71c71dp-8},
     28478},
    {1,
     {-0x1.afe223e1a7543p-10, -0x1.7a185c0ce6ea9p-8, 0x1.7a4fa4fa4fa5p-5},
     {0x1.896ffb1bc0fb8p-3, 0x1.1572afb816926p-1, -0x1.1b2fdaa1e470ep-1},
     {-0x1.afe223e1a7543p-10, -0x1.7a185c0ce6ea9p-8, 0x1.7a4fa4fa4fa5p-5},
     180947},
    {2,
     {0x1.1c4595287ea43p-9, 0x1.16fbf090684abp-9, 0x1.537612931a84ap-5},
     {0x1.ceaa8acf2352ap-1, -0x1.99427da14ed29p-1, -0x1.b9af4cd320eap-6},
     {0x1.1c4595287ea43p-9, 0x1.16fbf090684abp-9, 0x1.537612931a84ap-5},
     162943},
    {2,
     {0x1.bf8d12689aedfp-10, -0x1.4352d86bb6bd9p-9, 0x1.0b60b60b60b6p-7},
     {0x1.e5eb0f2b37fcp-2, 0x1.384e6eabae75cp-2, 0x1.1d4939a4354fp-1},
     {0x1.bf8d12689aedfp-10, -0x1.4352d86bb6bd9p-9, 0x1.0b60b60b60b6p-7},
     214279},
    {4,
     {-0x1.f561a0f31cd4p-10, 0x1.2eee9b3af328p-9, 0x1.49f49f49f49f4p-8},
     {-0x1.ea3f874c88628p-3, 0x1.8604f09ff5d0cp-2, 0x1.74512d5b2f302p-1},
     {-0x1.f561a0f31cd4p-10, 0x1.2eee9b3af328p-9, 0x1.49f49f49f49f4p-8},
     -1},
    {5,
     {0x1.448f837f07e3ep-10, 0x1.662905054886fp-9, 0x1.8e38e38e38e39p-6},
     {0x1.1b84fff1950aep-1, -0x1.a5ee9008bb3fp-4, 0x1.aede2c3f02cf8p-1},
     {0x1.448f837f07e3ep-10, 0x1.662905054886fp-9, 0x1.8e38e38e38e39p-6},
     95419},
    {0,
     {0x1.b6e5d1e7d104dp-10, 0x1.4646e939947b9p-9, 0x1.9576d1217a3dfp-6},
     {0x1.9218c6bd48caep-1, -0x1.2a6603b75f146p-1, -0x1.72ee70ce69417p-1},
     {0x1.b6e5d1e7d104dp-10, 0x1.4646e939947b9p-9, 0x1.9576d1217a3dfp-6},
     261442},
    {1,
     {-0x1.64740a7670531p-10, 0x1.5e7f82ed524bdp-9, 0x1.13e93e93e93e9p-5},
     {0x1.229305b6c97a8p-3, -0x1.bdaeee8ca2cdp-1, 0x1.9233d3217a518p-2},
     {-0x1.64740a7670531p-10, 0x1.5e7f82ed524bdp-9, 0x1.13e93e93e93e9p-5},
     132429},
    {2,
     {-0x1.5dc41ee26231dp-9, 0x1.67515d71a81ebp-10, 0x1.71c71c71c71c8p-5},
     {0x1.65842513e54b4p-2, -0x1.4e288528cd29p-5, -0x1.c784bb022ee02p-1},
     {-0x1.5dc41ee26231dp-9, 0x1.67515d71a81ebp-10, 0x1.71c71c71c71c8p-5},
     177587},
    {2,
     {-0x1.4122199960f25p-11, -0x1.8727b347ef5f5p-8, 0x1.816c16c16c16cp-5},
     {0x1.04e08ec1ee1dp-4, 0x1.0d23417e5244p-5, 0x1.43761d4bd6ad4p-2},
     {-0x1.4122199960f25p-11, -0x1.8727b347ef5f5p-8, 0x1.816c16c16c16cp-5},
     185070},
    {4,
     {0x1.aa275d0d16951p-10, -0x1.4a78e3a74e87cp-9, 0x1.c16c16c16c16cp-7},
     {0x1.263202b67bf04p-2, -0x1.80e7b65ad5b27p-1, -0x1.8f1e193180369p-1},
     {0x1.aa275d0d16951p-10, -0x1.4a78e3a74e87cp-9, 0x1.c16c16c16c16cp-7},
     -1},
    {5,
     {-0x1.31c0e4ca9ac99p-9, 0x1.69f4a5c4a9e45p-8, 0x1.337590d74016cp-7},
     {-0x1.7b81c80b4bc18p-1, -0x1.310ce93855e32p-1, 0x1.803bffd3aa9c2p-1},
     {-0x1.31c0e4ca9ac99p-9, 0x1.69f4a5c4a9e45p-8, 0x1.337590d74016cp-7},
     199686},
    {0,
     {0x1.7dbb092dbaab8p-9, 0x1.6706d8a6fa8b4p-9, 0x1.a82914c2235dfp-6},
     {-0x1.2eb33d789028cp-3, 0x1.457110865a4f6p-1, -0x1.aa6434b59748ep-2},
     {0x1.7dbb092dbaab8p-9, 0x1.6706d8a6fa8b4p-9, 0x1.a82914c2235dfp-6},
     269266},
    {1,
     {0x1.88cfb932f9203p-9, 0x1.1afebdd1aa145p-13, 0x1.471c71c71c71dp-6},
     {-0x1.f9c987b81b956p-2, -0x1.43f10c9d238f8p-1, 0x1.08f3ab4e445ep-5},
     {0x1.88cfb932f9203p-9, 0x1.1afebdd1aa145p-13, 0x1.471c71c71c71dp-6},
     78854},
    {2,
     {0x1.184e72f3044e8p-9, 0x1.13c1cd9b23864p-9, 0x1.71c71c71c71c8p-5},
     {0x1.bea473f33d3ap-5, -0x1.bab3e26969a5ep-2, 0x1.194e46069b3cp-5},
     {0x1.184e72f3044e8p-9, 0x1.13c1cd9b23864p-9, 0x1.71c71c71c71c8p-5},
     177279},
    {2,
     {0x1.30f90c31906cdp-8, 0x1.f0686f87ec1cbp-9, 0x1.b50c439dca435p-6},
     {0x1.625e69068b51ep-1, 0x1.0ff5acdc80bep-1, -0x1.901929a9376p-9},
     {0x1.30f90c31906cdp-8, 0x1.f0686f87ec1cbp-9, 0x1.b50c439dca435p-6},
     266432},
    {4,
     {0x1.03d0c5f98d053p-10, 0x1.f1ccac12b5a6bp-9, 0x1.9d6e740513e85p-6},
     {0x1.30e82b3d9b69p-1, 0x1.6a1b7060b8652p-1, 0x1.3eca379b47978p-2},
     {0x1.03d0c5f98d053p-10, 0x1.f1ccac12b5a6bp-9, 0x1.9d6e740513e85p-6},
     -1},
    {5,
     {-0x1.3cd97e75bd8cfp-9, -0x1.d1b3f83aa24c7p-10, 0x1.330127d9c2ed9p-6},
     {0x1.b8a84fea61406p-1, 0x1.c50645859a96ep-1, 0x1.5272d6ea25968p-1},
     {-0x1.3cd97e75bd8cfp-9, -0x1.d1b3f83aa24c7p-10, 0x1.330127d9c2ed9p-6},
     73319},
    {0,
     {0x1.87e4ec22c1824p-9, -0x1.01116b22dec21p-12, 0x1.82d82d82d82d9p-9},
     {-0x1.f14c2c9b9e94p-7, 0x1.7c60deb20b30ep-1, 0x1.a012d4485832p-3},
     {0x1.87e4ec22c1824p-9, -0x1.01116b22dec21p-12, 0x1.82d82d82d82d9p-9},
     12275},
    {1,
     {-0x1.8001252e6a675p-9, 0x1.52548f4658a09p-11, 0x1.93e93e93e93e9p-5},
     {0x1.09d748482148p-1, 0x1.de8231d804498p-2, 0x1.de6bed47da7ep-1},
     {-0x1.8001252e6a675p-9, 0x1.52548f4658a09p-11, 0x1.93e93e93e93e9p-5},
     194013},
    {2,
     {-0x1.7d35f43672df5p-8, -0x1.819d72889b967p-10, 0x1.67f460444466p-5},
     {-0x1.a57e971be8868p-1, -0x1.6368c06c5c26p-5, 0x1.c42b6bf073e6p-5},
     {-0x1.7d35f43672df5p-8, -0x1.819d72889b967p-10, 0x1.67f460444466p-5},
     172585},
    {2,
     {0x1.0df77668f31fdp-8, -0x1.1de3326a0a025p-8, 0x1.582d82d82d82dp-6},
     {-0x1.69ff93707aebp-4, -0x1.032125e1ad58p-7, -0x1.7c92c06add06cp-3},
     {0x1.0df77668f31fdp-8, -0x1.1de3326a0a025p-8, 0x1.582d82d82d82dp-6},
     -1},
    {4,
     {-0x1.4e675570f5033p-13, -0x1.88a750958658cp-9, 0x1.c16c16c16c16cp-7},
     {-0x1.55e142edacd54p-2, 0x1.20966175e1fbcp-1, 0x1.86ed978d3de68p-2},
     {-0x1.4e675570f5033p-13, -0x1.88a750958658cp-9, 0x1.c16c16c16c16cp-7},
     -1},
    {5,
     {0x1.87ccc310c6ba3p-9, 0x1.0a83609e54bd9p-12, 0x1.903e5a4153615p-5},
     {-0x1.ab570e6733b9cp-2, 0x1.4ec00bff884cp-4, -0x1.7d1948f0a2bf5p-1},
     {0x1.87ccc310c6ba3p-9, 0x1.0a83609e54bd9p-12, 0x1.903e5a4153615p-5},
     191500},
    {0,
     {-0x1.ba3eecee47a9cp-10, 0x1.4524bdeff209dp-9, 0x1.8e38e38e38e39p-7},
     {0x1.3a4b7aeb4251ap-1, -0x1.2769156cd4ccap-2, 0x1.e6016b7c3c18cp-1},
     {-0x1.ba3eecee47a9cp-10, 0x1.4524bdeff209dp-9, 0x1.8e38e38e38e39p-7},
     48480},
    {1,
     {0x1.e741da774e405p-10, 0x1.75dd66763fcb9p-8, 0x1.db05b05b05b07p-6},
     {0x1.bcfc7e542f61cp-2, 0x1.ed9bc7c4a023ep-1, -0x1.0b9b1ad93b922p-1},
     {0x1.e741da774e405p-10, 0x1.75dd66763fcb9p-8, 0x1.db05b05b05b07p-6},
     112845},
    {2,
     {-0x1.e935de1402e98p-12, -0x1.016c7f8ab50ep-8, 0x1.e5b97852bbac9p-7},
     {0x1.5128d9dbdf4ap-4, 0x1.ceb351dbd8f4p-3, 0x1.e4dfd4af3b85p-1},
     {-0x1.e935de1402e98p-12, -0x1.016c7f8ab50ep-8, 0x1.e5b97852bbac9p-7},
     -1},
    {2,
     {0x1.62c434adedbf8p-8, -0x1.532482bf8cadfp-9, 0x1.38e38e38e38e4p-7},
     {-0x1.9e02059e677fdp-1, 0x1.197d62384aa6cp-1, -0x1.3e131a997bf76p-1},
     {0x1.62c434adedbf8p-8, -0x1.532482bf8cadfp-9, 0x1.38e38e38e38e4p-7},
     37814},
    {4,
     {0x1.83b1339c58974p-9, 0x1.068dcfc7ad05cp-11, 0x1.13e93e93e93e9p-6},
     {0x1.2529b4f42438ep-1, -0x1.fbc43d27172aep-1, 0x1.e57521f4d4d66p-1},
     {0x1.83b1339c58974p-9, 0x1.068dcfc7ad05cp-11, 0x1.13e93e93e93e9p-6},
     -1},
    {5,
     {0x1.8058e5ed7e03bp-8, 0x1.4c0b4eaf96e99p-10, 0x1.6c16c16c16c17p-6},
     {-0x1.bcec5b384f4b3p-1, -0x1.6de30a6beaf4p-1, 0x1.dd88042d0653ap-1},
     {0x1.8058e5ed7e03bp-8, 0x1.4c0b4eaf96e99p-10, 0x1.6c16c16c16c17p-6},
     86051},
    {0,
     {0x1.49cf097bd3001p-13, -0x1.88ab60fc5fe9dp-9, 0x1.73af0ae78a103p-6},
     {-0x1.6bbf9b6c12808p-4, 0x1.43761945b29c4p-2, -0x1.ce3b0057a284ap-1},
     {0x1.49cf097bd3001p-13, -0x1.88ab60fc5fe9dp-9, 0x1.73af0ae78a103p-6},
     89865},
    {1,
     {0x1.64244f4eb75f4p-8, -0x1.4d539683d6efp-9, 0x1.fa4fa4fa4fa5p-7},
     {0x1.f53aa4e441edep-1, 0x1.3ef3f0fc16b5p-1, -0x1.a12c7641544cap-2},
     {0x1.64244f4eb75f4p-8, -0x1.4d539683d6efp-9, 0x1.fa4fa4fa4fa5p-7},
     278533},
    {2,
     {-0x1.734b9c15ba86bp-8, -0x1.02deb42347673p-9, 0x1.fa4fa4fa4fa5p-7},
     {0x1.8af2db77cdf8p-4, 0x1.d33aa63c08f8p-3, 0x1.ef4f3dca4aec4p-2},
     {-0x1.734b9c15ba86bp-8, -0x1.02deb42347673p-9, 0x1.fa4fa4fa4fa5p-7},
     59959},
    {2,
     {-0x1.61df6cb688315p-8, -0x1.56d8f2260efe5p-9, 0x1.013d0273ae3d8p-6},
     {0x1.7af5596f3b774p-1, 0x1.7c26a5c013056p-1, -0x1.e82b5fed31c8ep-2},
     {-0x1.61df6cb688315p-8, -0x1.56d8f2260efe5p-9, 0x1.013d0273ae3d8p-6},
     354808},
    {4,
     {-0x1.e256a82231f7p-9, 0x1.6af0bf3947c1dp-11, 0x1.ab4112b900399p-6},
     {0x1.cdfc9984b1a6cp-2, -0x1.77272efb118ccp-1, 0x1.45265b7a17edp-3},
     {-0x1.e256a82231f7p-9, 0x1.6af0bf3947c1dp-11, 0x1.ab4112b900399p-6},
     -1},
    {5,
     {-0x1.7f4cb5820c62p-8, 0x1.5ee2a2b95fc68p-10, 0x1.1c71c71c71c71p-8},
     {-0x1.8a330ca9c0a9cp-1, -0x1.52b39eca0b4a4p-1, -0x1.54b6af123d88ap-1},
     {-0x1.7f4cb5820c62p-8, 0x1.5ee2a2b95fc68p-10, 0x1.1c71c71c71c71p-8},
     241594},
    {0,
     {-0x1.e122c156dc6fcp-11, 0x1.765c2a07b85efp-9, 0x1.693e93e93e93fp-5},
     {-0x1.9a3f6f02f43d4p-2, -0x1.5d0a488065eb8p-2, -0x1.7935c7bdb8658p-4},
     {-0x1.e122c156dc6fcp-11, 0x1.765c2a07b85efp-9, 0x1.693e93e93e93fp-5},
     173363},
    {1,
     {0x1.12aa40ff11847p-12, 0x1.87b605cb893b5p-9, 0x1.d357ac93cc83cp-6},
     {-0x1.0a66f5bc332b4p-3, 0x1.88530700750cp-3, -0x1.5b7fdb43406dbp-1},
     {0x1.12aa40ff11847p-12, 0x1.87b605cb893b5p-9, 0x1.d357ac93cc83cp-6},
     301346},
    {2,
     {0x1.6c7f3dc115bc5p-9, 0x1.26feccf150f28p-10, 0x1.ec16c16c16c18p-6},
     {-0x1.eedc302b1462ap-2, -0x1.57b2f9885bdbep-2, -0x1.cb29d1d248dep-1},
     {0x1.6c7f3dc115bc5p-9, 0x1.26feccf150f28p-10, 0x1.ec16c16c16c18p-6},
     117823},
    {2,
     {0x1.b3593afb3410dp-10, 0x1.d8e4dc9ff59ebp-9, 0x1.d1d07b19c9d67p-6},
     {-0x1.4ed0988319f5p-4, -0x1.89cfd3a8e0145p-1, 0x1.6f6ac7d19a9ep-3},
     {0x1.b3593afb3410dp-10, 0x1.d8e4dc9ff59ebp-9, 0x1.d1d07b19c9d67p-6},
     365230},
    {4,
     {-0x1.104be6a89f02p-9, -0x1.1bab571dddd25p-9, 0x1.2c16c16c16c17p-5},
     {-0x1.cd83a0cb7a6ep-4, -0x1.bdc3bb666c8dep-1, -0x1.553f8ae62c716p-2},
     {-0x1.104be6a89f02p-9, -0x1.1bab571dddd25p-9, 0x1.2c16c16c16c17p-5},
     -1},
    {5,
     {0x1.681febe0db063p-9, 0x1.3bbeed3b9f788p-10, 0x1.c71c71c71c71dp-10},
     {-0x1.29404a8c5e7bap-1, 0x1.ef97ae440c01cp-2, -0x1.1d4531bb8c36p-1},
     {0x1.681febe0db063p-9, 0x1.3bbeed3b9f788p-10, 0x1.c71c71c71c71dp-10},
     7234},
};

// Replays `cuts` on the 200k-triangle tube of `segments` segments; the last, a slab, must
// remove exactly the slab component that holds the seed: closed, oriented, and the volume of the
// independent reference (to 1e-9, plus what the cut's vertex merges may move: each at most the
// tolerance times the surface).
void replay_and_check_last_slab(int segments, std::span<const SeededCut> cuts) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, segments,
                                       (200000 - 4 * segments) / (4 * segments));
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    const std::size_t last = cuts.size() - 1;
    ASSERT_EQ(testing::replay_cuts(ctx, cuts.first(last), kerf_m), last)
        << "an earlier cut ended in internal_error";
    const SeededCut& c = cuts[last];
    ASSERT_EQ(c.kind, 5);
    ctx.grow_capacity();
    const TriMesh before = m;
    const double v0 = testing::expect_closed_2_manifold(before).total_volume_m3;
    const Plane plane = *Plane::make(c.point, c.normal);
    SlabCut slab;
    const CutResult r = subtract_slab(ctx, plane, kerf_m, testing::seed_of(c), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    EXPECT_FALSE(slab.lower.negative.cap_faces.empty());
    EXPECT_FALSE(slab.upper.positive.cap_faces.empty());
    const double removed = testing::seed_body_slab_reference(before, plane, kerf_m, c.point);
    ASSERT_GT(removed, 0.0) << "a reference slice failed";
    const auto rep = testing::expect_closed_2_manifold(m);
    EXPECT_NEAR(rep.total_volume_m3, v0 - removed,
                testing::volume_change_bound(v0, r.stats.vertices_merged, ctx.tolerance_m(),
                                             testing::surface_area(before)));
    testing::expect_face_normals_agree(m);
}

TEST(SlabUpperWallRegression, TubeSlabWhoseUpperWallMeetsANeedleFanIsCut) {
    replay_and_check_last_slab(512, kTube512Cuts);
}

TEST(SlabUpperWallRegression, TubeSlabWhoseUpperCapFailsOnTheReplanIsCut) {
    replay_and_check_last_slab(32, kTube32Cuts);
}

}  // namespace
}  // namespace kerf::cut
