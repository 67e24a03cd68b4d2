// The hand's grab (rt_core/loop/body_grab.hpp): button 3 near a body takes it, the body follows
// the tool's translation in the loop's collision world, BodyMoved poses come every 0.1 mm and on
// release; nothing is taken out of reach or while the saw runs; no allocation per tick.
#include "rt_core/loop/body_grab.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "tests/allocation_counter.hpp"
#include "tests/physics/physics_test_shapes.hpp"

namespace kerf::rt {
namespace {

using physics::Vec3;

constexpr std::uint32_t kGrab = 1u << 3;

/// Two 10 mm cubes side by side (slots 0 and 1), 20 mm apart along x.
struct TwoCubes {
    TwoCubes() {
        for (int i = 0; i < 2; ++i) {
            const double x = 0.02 * i;
            meshes.push_back(physics::test::make_box({x, 0, 0}, {x + 0.01, 0.01, 0.01}));
        }
        for (std::uint32_t i = 0; i < 2; ++i) {
            auto built = physics::CollisionBody::build(meshes[i].view());
            EXPECT_TRUE(built);
            bodies.push_back(std::move(*built));
            world.set_body(i, bodies.back().get());
        }
    }
    std::vector<physics::test::TestMesh> meshes;
    std::vector<std::unique_ptr<const physics::CollisionBody>> bodies;
    physics::CollisionWorld world;
};

TEST(BodyGrab, TheNearestBodyFollowsTheToolAndEachTenthOfAMillimetreIsPublished) {
    TwoCubes s;
    BodyGrab grab;
    BodyMove move;
    const Vec3 start{0.025, 0.012, 0.005};  // 2 mm above the second cube
    EXPECT_FALSE(grab.update(0, start, false, s.world, move));
    EXPECT_FALSE(grab.update(kGrab, start, false, s.world, move));  // taken, not moved yet
    ASSERT_TRUE(grab.holding());
    EXPECT_EQ(grab.body(), 1u);
    std::vector<BodyMove> published;
    published.reserve(100);
    kerf::test::arm_allocation_counter();
    for (int t = 1; t <= 400; ++t) {  // 4 mm along -x, 10 um a tick
        const Vec3 tool = start + Vec3{-1e-5 * t, 0, 0};
        if (grab.update(kGrab, tool, false, s.world, move)) published.push_back(move);
    }
    const Vec3 end = start + Vec3{-0.004, 0, 0};
    EXPECT_EQ(kerf::test::disarm_allocation_counter(), 0u) << "the grab allocated in a tick";
    // Let go: the pose reached since the last BodyMoved (if any) is published.
    if (grab.update(0, end, false, s.world, move)) published.push_back(move);
    EXPECT_FALSE(grab.holding());
    ASSERT_GE(published.size(), 36u);  // one per 0.1 mm (steps of 10 um round either way)
    EXPECT_LE(published.size(), 41u);
    EXPECT_EQ(published.back().body, 1u);
    EXPECT_NEAR(published.back().world_from_body.translation.x, -0.004, 1e-9);
    EXPECT_NEAR(published.back().world_from_body.translation.y, 0.0, 1e-12);
    // The loop's own world moved the body: its face at x = 20 mm is now at 16 mm.
    EXPECT_NEAR(s.world.pose(1).translation.x, -0.004, 1e-9);
    EXPECT_NEAR(s.world.pose(0).translation.x, 0.0, 1e-12) << "the other body stays";
    const physics::SurfaceHit hit = s.world.closest_point({0.0145, 0.005, 0.005}, 0.01);
    ASSERT_TRUE(hit.found);
    EXPECT_EQ(hit.body, 1u);
    EXPECT_NEAR(hit.distance, 0.0015, 1e-6);
}

TEST(BodyGrab, ReleasingBetweenStepsPublishesTheFinalPose) {
    TwoCubes s;
    BodyGrab grab;
    BodyMove move;
    const Vec3 start{0.005, 0.012, 0.005};
    grab.update(kGrab, start, false, s.world, move);
    ASSERT_TRUE(grab.holding());
    EXPECT_EQ(grab.body(), 0u);
    EXPECT_FALSE(grab.update(kGrab, start + Vec3{0, 0, 5e-5}, false, s.world, move));
    ASSERT_TRUE(grab.update(0, start + Vec3{0, 0, 5e-5}, false, s.world, move));
    EXPECT_NEAR(move.world_from_body.translation.z, 5e-5, 1e-12);
}

TEST(BodyGrab, NothingIsTakenOutOfReachWhileTheSawRunsOrWithTheButtonAlreadyDown) {
    TwoCubes s;
    BodyMove move;
    BodyGrab far;
    far.update(kGrab, {0.005, 0.02, 0.005}, false, s.world, move);  // 10 mm above: out of reach
    EXPECT_FALSE(far.holding());
    BodyGrab sawing;
    sawing.update(kGrab, {0.005, 0.012, 0.005}, true, s.world, move);
    EXPECT_FALSE(sawing.holding());
    // The button stays down while the tool comes near: only a new press takes hold.
    sawing.update(kGrab, {0.005, 0.012, 0.005}, false, s.world, move);
    EXPECT_FALSE(sawing.holding());
    sawing.update(0, {0.005, 0.012, 0.005}, false, s.world, move);
    sawing.update(kGrab, {0.005, 0.012, 0.005}, false, s.world, move);
    EXPECT_TRUE(sawing.holding());
    EXPECT_EQ(sawing.grabs(), 1u);
}

}  // namespace
}  // namespace kerf::rt
