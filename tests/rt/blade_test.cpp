// The blade's orientation: from the device when it senses one (the Kerf HID orientation
// extension, emulated by kerf-hapsim --orientation and the script's `orient`), else the planned
// cut stepped by buttons 1 (+step) and 2 (-step) about the blade's edge.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/rt/rt_rig.hpp"

namespace kerf::rt {
namespace {

TEST(RtBlade, ASensedOrientationDrivesTheBlade) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    // 30 degrees about x: w = cos 15, x = sin 15.
    test::Rig rig({"hold,0.01\norient,0.96592583,0.25881905,0,0\nhold,10\n",
                   {"--orientation"},
                   100'000,
                   false});
    ASSERT_TRUE(rig.ok()) << rig.error();
    for (int i = 0; i < 100; ++i) rig.tick();
    ASSERT_TRUE(rig.loop().last_sample().has_orientation);
    EXPECT_TRUE(rig.loop().blade().sensed());
    const physics::Mat3& r = rig.loop().blade().orientation();
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    EXPECT_NEAR(r.m[0][0], 1.0, 1e-4);
    EXPECT_NEAR(r.m[1][1], c, 1e-4);
    EXPECT_NEAR(r.m[1][2], -s, 1e-4);
    EXPECT_NEAR(r.m[2][1], s, 1e-4);
}

TEST(RtBlade, WithoutOrientationThePlannedCutIsSteppedWithButtons) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    const char* script =
        "hold,0.01\nbutton,1,down\nhold,0.02\nbutton,1,up\nhold,0.02\nbutton,1,down\nhold,0.02\n"
        "button,1,up\nhold,0.02\nbutton,2,down\nhold,0.02\nbutton,2,up\nhold,10\n";
    test::Rig rig({script, {}, 100'000, false});
    ASSERT_TRUE(rig.ok()) << rig.error();
    for (int i = 0; i < 200; ++i) rig.tick();
    EXPECT_FALSE(rig.loop().last_sample().has_orientation);
    EXPECT_FALSE(rig.loop().blade().sensed());
    EXPECT_EQ(rig.loop().blade().steps(), 1);  // +1 +1 -1
    const physics::Mat3& r = rig.loop().blade().orientation();
    const double a = 5.0 * M_PI / 180;  // one 5-degree step about the edge (world x)
    EXPECT_NEAR(r.m[0][0], 1.0, 1e-9);
    EXPECT_NEAR(r.m[1][1], std::cos(a), 1e-9);
    EXPECT_NEAR(r.m[2][1], std::sin(a), 1e-9);
}

}  // namespace
}  // namespace kerf::rt
