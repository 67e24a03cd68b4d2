// A slab cut that ended in internal_error on a clean shared bone (issue 10 item 5), cut 47 of a
// random sequence on the distal fibula (lower wall localised, upper wall through the slab).
// Earlier cuts had left a piece whose tip, above the slab's lower wall, is bounded only by their
// caps. The search for the upper wall started from the lower wall's faces but skipped every cap
// face there, so it found no upper wall; the slab then ran past the upper plane into those caps
// and the final check refused it after the lower wall was already cut. Caps of earlier cuts now
// start the search too (after the uncapped faces, so cuts that never needed them are unchanged).
// The 48 planes are the hex floats the scratch sequence drew (kind 0-3 localised with the plane
// point as seed, 4 full, 5 slab 0.02 * scale_m wide), in order, from the shared mesh.
#include <gtest/gtest.h>

#include <span>

#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "tests/cut/chevron_checks.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

using testing::SeededCut;

const SeededCut kFibulaCuts[] = {
    {0,
     {0x1.165e3490b9af7p-6, -0x1.46e66de8ca11cp-6, -0x1.aa42b7a32847p-5},
     {0x1.70aedaa3344fcp-1, 0x1.7303cda37563ep-1, 0x1.aba1000ee3bbcp-1},
     {0x1.165e3490b9af7p-6, -0x1.46e66de8ca11cp-6, -0x1.aa42b7a32847p-5},
     19365},
    {1,
     {0x1.15b431d5acb6fp-6, -0x1.dde20fb38a94dp-7, -0x1.05c571a9fbe77p-4},
     {-0x1.2e7d4755618c8p-4, -0x1.88e43ca15ce0ap-2, 0x1.2004c6e3e69dp-2},
     {0x1.15b431d5acb6fp-6, -0x1.dde20fb38a94dp-7, -0x1.05c571a9fbe77p-4},
     8376},
    {2,
     {0x1.4e3ad2f1a9fbfp-6, -0x1.983d78d4fdf3cp-7, -0x1.c30053f7ced91p-6},
     {0x1.c66a4286239ecp-1, 0x1.21ba76322677p-3, 0x1.37064eba503a8p-3},
     {0x1.4e3ad2f1a9fbfp-6, -0x1.983d78d4fdf3cp-7, -0x1.c30053f7ced91p-6},
     35194},
    {2,
     {0x1.91ebbb0cf87dbp-6, -0x1.1560888888889p-7, -0x1.5b4beb851eb85p-6},
     {-0x1.d47760f58190ep-1, -0x1.1dcb2b94fdb78p-3, -0x1.22d38ffa65244p-3},
     {0x1.91ebbb0cf87dbp-6, -0x1.1560888888889p-7, -0x1.5b4beb851eb85p-6},
     39904},
    {4,
     {0x1.04f0a6e978d5p-5, -0x1.5ee2555555555p-7, -0x1.d117916872b03p-5},
     {0x1.b21b5f1dfe2acp-1, -0x1.0e34f1884139p-5, -0x1.b05c1af71e34p-5},
     {0x1.04f0a6e978d5p-5, -0x1.5ee2555555555p-7, -0x1.d117916872b03p-5},
     -1},
    {5,
     {0x1.4d478dfea2799p-6, -0x1.b47cdf3b645a3p-6, -0x1.ce3b851eb851fp-5},
     {0x1.f273dd6d06ep-6, 0x1.747c127c8168ap-1, -0x1.6aa320acabe48p-2},
     {0x1.4d478dfea2799p-6, -0x1.b47cdf3b645a3p-6, -0x1.ce3b851eb851fp-5},
     15421},
    {0,
     {0x1.c793c5ab75ea1p-6, -0x1.7bb12d9f23dc9p-7, -0x1.190d9d283b621p-4},
     {-0x1.bf50608281914p-1, -0x1.3138dd8bc1b72p-1, -0x1.b717b40da7999p-1},
     {0x1.c793c5ab75ea1p-6, -0x1.7bb12d9f23dc9p-7, -0x1.190d9d283b621p-4},
     47721},
    {1,
     {0x1.0674a06d3a06dp-5, -0x1.fd05c131d5accp-7, -0x1.d44ce1f67152bp-5},
     {0x1.612dcc092caep-3, 0x1.6f2cf09992a9p-2, -0x1.0507c3f25dcc2p-1},
     {0x1.0674a06d3a06dp-5, -0x1.fd05c131d5accp-7, -0x1.d44ce1f67152bp-5},
     14837},
    {2,
     {0x1.28418bf258bf3p-6, -0x1.1bcaa89e60f05p-6, -0x1.7cb462fc962fdp-5},
     {-0x1.3245b84ae0112p-1, -0x1.bd33a3d3903a4p-2, -0x1.12e7b88991f02p-1},
     {0x1.28418bf258bf3p-6, -0x1.1bcaa89e60f05p-6, -0x1.7cb462fc962fdp-5},
     23834},
    {2,
     {0x1.0157a740da741p-5, -0x1.b29c111111111p-7, -0x1.4b8c369d0369dp-5},
     {-0x1.98e9af2294c5p-1, -0x1.72b27ebd35a1cp-1, 0x1.a9154a45aafdcp-2},
     {0x1.0157a740da741p-5, -0x1.b29c111111111p-7, -0x1.4b8c369d0369dp-5},
     27680},
    {4,
     {0x1.56e62bb0cf87dp-6, -0x1.d2951bfd44f31p-8, -0x1.4eb2921735ee4p-5},
     {-0x1.256c7b403de0ap-1, 0x1.14328d5cd8258p-2, -0x1.e5f8a70ab1732p-2},
     {0x1.56e62bb0cf87dp-6, -0x1.d2951bfd44f31p-8, -0x1.4eb2921735ee4p-5},
     -1},
    {5,
     {0x1.b60c4f3078264p-6, -0x1.0fe5ca11bfd44p-7, -0x1.c5ca9db22d0e5p-6},
     {0x1.56b590581394cp-1, 0x1.612ecef42d066p-1, 0x1.80ca1686ce17p-2},
     {0x1.b60c4f3078264p-6, -0x1.0fe5ca11bfd44p-7, -0x1.c5ca9db22d0e5p-6},
     35249},
    {0,
     {0x1.1906124b9d989p-6, -0x1.e780f4ebf2df3p-7, -0x1.4d75301b98d5dp-5},
     {-0x1.e817bc4a1eed1p-1, 0x1.0db85cc0c433p-3, -0x1.0ddd70fdbf34p-6},
     {0x1.1906124b9d989p-6, -0x1.e780f4ebf2df3p-7, -0x1.4d75301b98d5dp-5},
     55545},
    {1,
     {0x1.014d407901005p-5, -0x1.a1b35a165c4c5p-8, -0x1.10dd94dedcd87p-4},
     {0x1.7bbae2176dd4p-2, -0x1.1c9326514d6c8p-1, -0x1.cc3180b79d79p-4},
     {0x1.014d407901005p-5, -0x1.a1b35a165c4c5p-8, -0x1.10dd94dedcd87p-4},
     47811},
    {2,
     {0x1.4e3872015d868p-6, -0x1.36e662fc962fdp-7, -0x1.01c401b4e81b5p-5},
     {0x1.ffb568d69273cp-1, 0x1.42f04a4401bap-5, -0x1.7ee0a1eff759dp-1},
     {0x1.4e3872015d868p-6, -0x1.36e662fc962fdp-7, -0x1.01c401b4e81b5p-5},
     32965},
    {2,
     {0x1.655c0fb38a94dp-6, -0x1.c4559a485cd7cp-6, -0x1.c88d5b7a32847p-5},
     {-0x1.cdcf91a334ebcp-1, -0x1.bf6f433ab3aefp-1, -0x1.d3d382207c95cp-1},
     {0x1.655c0fb38a94dp-6, -0x1.c4559a485cd7cp-6, -0x1.c88d5b7a32847p-5},
     16073},
    {4,
     {0x1.fd1cbce2f848p-6, -0x1.5310aaa6c92a4p-7, -0x1.28fecbbdf91a7p-4},
     {0x1.ef76152d9f3f8p-3, 0x1.487303d550b24p-2, 0x1.4ba5f9dd97f9ep-1},
     {0x1.fd1cbce2f848p-6, -0x1.5310aaa6c92a4p-7, -0x1.28fecbbdf91a7p-4},
     -1},
    {5,
     {0x1.baf88f5c28f5dp-6, -0x1.6c54513cc1e09p-6, -0x1.51d55c28f5c29p-5},
     {-0x1.06bbbeb0748bp-1, 0x1.7c70fa22652ap-4, -0x1.f31df583ff82p-2},
     {0x1.baf88f5c28f5dp-6, -0x1.6c54513cc1e09p-6, -0x1.51d55c28f5c29p-5},
     27094},
    {0,
     {0x1.c24bf87d9c54bp-6, -0x1.fb506de8ca11cp-7, -0x1.2ec937fa89e61p-4},
     {0x1.f5e07037652p-8, 0x1.4f47ae1189d08p-3, 0x1.b34c7a0b9156p-3},
     {0x1.c24bf87d9c54bp-6, -0x1.fb506de8ca11cp-7, -0x1.2ec937fa89e61p-4},
     351},
    {1,
     {0x1.9b06f15d11108p-6, -0x1.21ef03c2104bep-6, -0x1.10ee9956c2363p-4},
     {0x1.cfa413d2b0cd4p-2, 0x1.f5d7ae9a0af5p-4, 0x1.b92ef2c7cf156p-1},
     {0x1.9b06f15d11108p-6, -0x1.21ef03c2104bep-6, -0x1.10ee9956c2363p-4},
     64811},
    {2,
     {0x1.8d38630e41d85p-6, -0x1.9e3b10c5bb4efp-8, -0x1.c53ee98ddf018p-5},
     {0x1.b4791ea95d1fap-1, -0x1.0df3314633fp-7, 0x1.536eea837e908p-1},
     {0x1.8d38630e41d85p-6, -0x1.9e3b10c5bb4efp-8, -0x1.c53ee98ddf018p-5},
     16742},
    {2,
     {0x1.fdb3d194237fbp-6, -0x1.f3580a3d70a3dp-7, -0x1.01a2dee402bb1p-5},
     {-0x1.d947d102987fep-2, 0x1.13f04163d873cp-2, 0x1.cc6ce507ff358p-3},
     {0x1.fdb3d194237fbp-6, -0x1.f3580a3d70a3dp-7, -0x1.01a2dee402bb1p-5},
     32896},
    {4,
     {0x1.9f56b9af72017p-6, -0x1.4e6be56041894p-6, -0x1.df4f3ece2a535p-6},
     {0x1.e3d5118d5a6p-9, -0x1.1c25f6b09cac6p-1, 0x1.831d817f95464p-1},
     {0x1.9f56b9af72017p-6, -0x1.4e6be56041894p-6, -0x1.df4f3ece2a535p-6},
     -1},
    {5,
     {0x1.01b43922f6349p-5, -0x1.b17a709811211p-8, -0x1.15143e16f0dc8p-4},
     {-0x1.e733b3a925f2p-1, 0x1.e2854df2bdb24p-2, 0x1.a162bd47a0ebp-2},
     {0x1.01b43922f6349p-5, -0x1.b17a709811211p-8, -0x1.15143e16f0dc8p-4},
     5174},
    {0,
     {0x1.1c0033729a029p-6, -0x1.c2c11145ae877p-7, -0x1.5a2660e9848b9p-5},
     {-0x1.3355fa4dbd9c4p-3, 0x1.915ba950a52d6p-1, 0x1.633a0acdce4cp-1},
     {0x1.1c0033729a029p-6, -0x1.c2c11145ae877p-7, -0x1.5a2660e9848b9p-5},
     60326},
    {1,
     {0x1.665e4511c46fdp-6, -0x1.be716db387bf4p-6, -0x1.f147ce9faa665p-5},
     {0x1.4b235f48769dp-1, 0x1.cb4b7d9e96658p-3, -0x1.8027605977edcp-2},
     {0x1.665e4511c46fdp-6, -0x1.be716db387bf4p-6, -0x1.f147ce9faa665p-5},
     65372},
    {2,
     {0x1.8b304a6921735p-6, -0x1.cddf8dfea2798p-8, -0x1.9d7d53f7ced93p-5},
     {0x1.d4664a26729cap-1, -0x1.768e0fcbdab4bp-1, -0x1.7164eb458a33cp-1},
     {0x1.8b304a6921735p-6, -0x1.cddf8dfea2798p-8, -0x1.9d7d53f7ced93p-5},
     20898},
    {2,
     {0x1.86b6827c4edbcp-6, -0x1.d28fd1c1ddb31p-6, -0x1.d235f50771b77p-5},
     {-0x1.29c457284b033p-1, -0x1.54ec58de94a14p-3, 0x1.3da3b6cfdb56p-4},
     {0x1.86b6827c4edbcp-6, -0x1.d28fd1c1ddb31p-6, -0x1.d235f50771b77p-5},
     61525},
    {4,
     {0x1.13b6b6f3a6925p-6, -0x1.2c96ce062b2edp-6, -0x1.067757447864fp-4},
     {0x1.663c32983628p-2, 0x1.1cfa1e6be417cp-1, 0x1.e26655619e018p-1},
     {0x1.13b6b6f3a6925p-6, -0x1.2c96ce062b2edp-6, -0x1.067757447864fp-4},
     -1},
    {5,
     {0x1.9fea7c7062538p-6, -0x1.69f787795ed6bp-6, -0x1.4b2abfa5bf91dp-5},
     {-0x1.6b6d18870ee5fp-1, -0x1.7e96279e34cb4p-1, -0x1.17cbe24fd0d2ap-1},
     {0x1.9fea7c7062538p-6, -0x1.69f787795ed6bp-6, -0x1.4b2abfa5bf91dp-5},
     66280},
    {0,
     {0x1.f8982c2067847p-6, -0x1.8bca9c1323275p-7, -0x1.2a75c01dcb65dp-4},
     {0x1.66b7a8a8402c8p-3, 0x1.8c36586d54d6cp-2, -0x1.15d6baf62e1bbp-1},
     {0x1.f8982c2067847p-6, -0x1.8bca9c1323275p-7, -0x1.2a75c01dcb65dp-4},
     47415},
    {1,
     {0x1.302cb558ba019p-6, -0x1.9e3320556bbd8p-8, -0x1.bae753ee820fbp-5},
     {-0x1.ea3a5a6590428p-3, 0x1.0e138279e8728p-1, 0x1.ec536f7df9816p-1},
     {0x1.302cb558ba019p-6, -0x1.9e3320556bbd8p-8, -0x1.bae753ee820fbp-5},
     73667},
    {2,
     {0x1.509bb22d0e56p-6, -0x1.4a1e0e5604189p-6, -0x1.3eea20c49ba5fp-5},
     {0x1.b3f9323fdf92cp-1, -0x1.f49e9a482ce7ap-2, -0x1.67a358409369cp-2},
     {0x1.509bb22d0e56p-6, -0x1.4a1e0e5604189p-6, -0x1.3eea20c49ba5fp-5},
     28525},
    {2,
     {0x1.f63bc6a7ef9dbp-6, -0x1.6a27bc6a7ef9dp-6, -0x1.deb5bbbbbbbbcp-5},
     {0x1.5dbfb16753a58p-1, -0x1.6a3ced2206fe6p-1, -0x1.dd674ea2bd9eep-1},
     {0x1.f63bc6a7ef9dbp-6, -0x1.6a27bc6a7ef9dp-6, -0x1.deb5bbbbbbbbcp-5},
     13662},
    {4,
     {0x1.3f794b17e4b18p-6, -0x1.edefdd2f1a9fcp-8, -0x1.5f55ad65b7a33p-5},
     {0x1.c303e9182e6ap-5, 0x1.4c5665f00e688p-1, -0x1.d265e91359cb1p-1},
     {0x1.3f794b17e4b18p-6, -0x1.edefdd2f1a9fcp-8, -0x1.5f55ad65b7a33p-5},
     -1},
    {5,
     {0x1.4eda91077fdc3p-6, -0x1.22fcd5694a679p-6, -0x1.c11057408719p-6},
     {-0x1.bf824ebc876dfp-1, 0x1.1743faddb172cp-1, -0x1.37026482d5bdcp-2},
     {0x1.4eda91077fdc3p-6, -0x1.22fcd5694a679p-6, -0x1.c11057408719p-6},
     35135},
    {0,
     {0x1.887a3cb55cd2bp-6, -0x1.19013cbbef531p-6, -0x1.95400923fae3bp-5},
     {0x1.e0f6bb3a694e8p-3, 0x1.bc282836b011ep-1, -0x1.bb892ae5874f6p-2},
     {0x1.887a3cb55cd2bp-6, -0x1.19013cbbef531p-6, -0x1.95400923fae3bp-5},
     97056},
    {1,
     {0x1.aefde686241edp-6, -0x1.d1a4b3ce9f97cp-7, -0x1.94cf6ba4a91b4p-6},
     {0x1.e21aaad04454p-5, 0x1.c1f6f8e5f6738p-1, 0x1.de786d1968878p-1},
     {0x1.aefde686241edp-6, -0x1.d1a4b3ce9f97cp-7, -0x1.94cf6ba4a91b4p-6},
     71890},
    {2,
     {0x1.3c2472b020c4bp-6, -0x1.3bd89e60f04c7p-7, -0x1.00316c8b43958p-4},
     {0x1.f4938a6d89868p-3, 0x1.157087792addp-2, 0x1.b2e289c85a368p-3},
     {0x1.3c2472b020c4bp-6, -0x1.3bd89e60f04c7p-7, -0x1.00316c8b43958p-4},
     10088},
    {2,
     {0x1.a35cfbe76c8b4p-6, -0x1.1ba64e81b4e82p-6, -0x1.299e28f5c28f6p-4},
     {-0x1.481824b6ece44p-2, -0x1.4bfdbc7fefab4p-2, 0x1.449a87beb51dp-3},
     {0x1.a35cfbe76c8b4p-6, -0x1.1ba64e81b4e82p-6, -0x1.299e28f5c28f6p-4},
     982},
    {4,
     {0x1.ba71f91a8c343p-6, -0x1.b54ac0b09ba5dp-6, -0x1.d5f203dc9b8f9p-5},
     {0x1.5637a0e884ed4p-1, -0x1.47a68dd96aac2p-1, 0x1.d7022ce3856e8p-3},
     {0x1.ba71f91a8c343p-6, -0x1.b54ac0b09ba5dp-6, -0x1.d5f203dc9b8f9p-5},
     -1},
    {5,
     {0x1.7f8e560418938p-6, -0x1.a66edbd194238p-8, -0x1.c3675d867c3edp-6},
     {0x1.f171d14c37f86p-1, 0x1.1c0d44563fba4p-1, 0x1.d3ec470eb098cp-1},
     {0x1.7f8e560418938p-6, -0x1.a66edbd194238p-8, -0x1.c3675d867c3edp-6},
     35283},
    {0,
     {0x1.2ec1ef0309b89p-6, -0x1.bc1ffe4f17268p-8, -0x1.afcdeed9b607dp-5},
     {0x1.e61cd8eeef71ep-1, -0x1.4dac45c0e14ep-6, -0x1.a58fff490b822p-1},
     {0x1.2ec1ef0309b89p-6, -0x1.bc1ffe4f17268p-8, -0x1.afcdeed9b607dp-5},
     85243},
    {1,
     {0x1.fe3a39bb3e347p-6, -0x1.8ef6de64daf9fp-8, -0x1.0eda9e5c1601cp-4},
     {-0x1.0b28df44ff826p-2, -0x1.ca5c1a8f8e162p-2, 0x1.c2b5179b552acp-1},
     {0x1.fe3a39bb3e347p-6, -0x1.8ef6de64daf9fp-8, -0x1.0eda9e5c1601cp-4},
     45234},
    {2,
     {0x1.0da504189374cp-6, -0x1.fbc44dd2f1aap-8, -0x1.a781dddddddddp-5},
     {0x1.ae7ac060e07e8p-2, 0x1.16283b53aaedap-1, -0x1.cf672435965e2p-2},
     {0x1.0da504189374cp-6, -0x1.fbc44dd2f1aap-8, -0x1.a781dddddddddp-5},
     19878},
    {2,
     {0x1.e0aa44dc33e87p-6, -0x1.4601eb5af6298p-6, -0x1.82fed0ec9bad9p-5},
     {-0x1.fbc101f76f431p-1, 0x1.b59ba39f845f2p-1, -0x1.9ea8040008ea2p-2},
     {0x1.e0aa44dc33e87p-6, -0x1.4601eb5af6298p-6, -0x1.82fed0ec9bad9p-5},
     23202},
    {4,
     {0x1.291f12805de82p-6, -0x1.6d70e0d2ccda3p-7, -0x1.751d695abfdcbp-5},
     {-0x1.c918785c76b5dp-1, 0x1.89f2f2a3da7dp-2, -0x1.3a2528653ccefp-1},
     {0x1.291f12805de82p-6, -0x1.6d70e0d2ccda3p-7, -0x1.751d695abfdcbp-5},
     -1},
    {5,
     {0x1.1c1f913bb77a5p-6, -0x1.d2e237a412a75p-7, -0x1.7deff0c60f83cp-5},
     {-0x1.462ed20d051b4p-1, 0x1.0ae5bdfd8094p-4, 0x1.2c9beca934092p-1},
     {0x1.1c1f913bb77a5p-6, -0x1.d2e237a412a75p-7, -0x1.7deff0c60f83cp-5},
     113369},
};

TEST(SlabCapWallRegression, FibulaSlabWhoseTipIsBoundedByEarlierCapsIsCut) {
    auto loaded = testing::load_shared_mesh("tcsm_ksbl_L01_fibula_distal_left.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    CutContext ctx(m);
    const double kerf_m = 0.02 * ctx.scale_m();
    const std::size_t last = std::size(kFibulaCuts) - 1;
    ASSERT_EQ(testing::replay_cuts(ctx, std::span(kFibulaCuts).first(last), kerf_m), last)
        << "an earlier cut ended in internal_error";
    SlabCut slab;
    const SeededCut& c = kFibulaCuts[last];
    ASSERT_EQ(c.kind, 5);
    ctx.grow_capacity();
    const TriMesh before = m;
    const double v0 = testing::expect_closed_2_manifold(before).total_volume_m3;
    const Plane plane = *Plane::make(c.point, c.normal);
    const CutResult r = subtract_slab(ctx, plane, kerf_m, testing::seed_of(c), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    // The slab's upper wall crosses the earlier caps: both walls cut, and the piece between them
    // that the lower wall's loop bounds is gone, as two full slices of the same mesh find it (the
    // seed lies on another piece's face, so the piece is named by the remaining lower cap).
    ASSERT_FALSE(slab.lower.negative.cap_faces.empty());
    EXPECT_FALSE(slab.upper.negative.cap_faces.empty());
    const Vec3 on_lower_cap = testing::face_centroid(m, slab.lower.negative.cap_faces.front());
    const double removed =
        testing::slab_reference_removed_volume(before, plane, kerf_m, on_lower_cap);
    ASSERT_GT(removed, 0.0);
    const auto rep = testing::expect_closed_2_manifold(m);
    EXPECT_NEAR(rep.total_volume_m3, v0 - removed, 1e-9 * v0);
    testing::expect_face_normals_agree(m);
}

}  // namespace
}  // namespace kerf::cut
