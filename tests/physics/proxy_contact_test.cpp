// God-object contact: the spring-damper law, stick/slip friction, and property tests — random
// approach paths into spheres, thin plates, box edges and vertices, and a real bone never leave the
// proxy inside.
#include "rt_core/physics/proxy_contact.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>

#include "rt_core/physics/force_model.hpp"
#include "tests/allocation_counter.hpp"
#include "tests/physics/physics_test_shapes.hpp"

// The stress build (kerf_physics_stress_tests, label stress) runs 20x the paths of each property.
#ifndef KERF_PROXY_PATH_SCALE
#define KERF_PROXY_PATH_SCALE 1
#endif

namespace kerf::physics {
namespace {

using test::TestMesh;
constexpr int kScale = KERF_PROXY_PATH_SCALE;

struct Scene {
    explicit Scene(const TestMesh& m) : mesh(m) {
        auto built = CollisionBody::build(mesh.view());
        EXPECT_TRUE(built);
        body = std::move(*built);
        world.set_body(0, body.get());
    }
    TestMesh mesh;
    std::unique_ptr<const CollisionBody> body;
    CollisionWorld world;
};

/// Drives the device along `path` (1 kHz) and checks after every tick that the proxy is outside
/// (generalized winding number < 0.5), every `check_every` ticks. Returns the ticks in contact.
int drive(const Scene& scene, ProxyContact& contact, const std::vector<Vec3>& path,
          int check_every = 1) {
    int in_contact = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
        const Vec3 v = i > 0 ? (path[i] - path[i - 1]) * 1000.0 : Vec3{};
        const ContactOutput out = contact.step(scene.world, path[i], v, 1e-3);
        in_contact += out.in_contact ? 1 : 0;
        if (int(i) % check_every == 0 || i + 1 == path.size()) {
            const double w = test::winding_number(scene.mesh, contact.proxy());
            if (w > 0.5) {
                ADD_FAILURE() << "proxy inside at tick " << i << ": (" << contact.proxy().x << ", "
                              << contact.proxy().y << ", " << contact.proxy().z << ") w=" << w;
                return in_contact;
            }
        }
    }
    return in_contact;
}

/// A straight approach from `from` to `to` in `steps` ticks, then a random walk of `wander` ticks
/// with steps up to `jitter` m, then straight back out.
std::vector<Vec3> approach(const Vec3& from, const Vec3& to, int steps, int wander, double jitter,
                           std::mt19937& rng) {
    std::vector<Vec3> path;
    for (int i = 0; i <= steps; ++i) path.push_back(from + (to - from) * (double(i) / steps));
    std::uniform_real_distribution<double> d(-jitter, jitter);
    Vec3 p = to;
    for (int i = 0; i < wander; ++i) path.push_back(p += Vec3{d(rng), d(rng), d(rng)});
    for (int i = 0; i <= steps; ++i) path.push_back(p + (from - p) * (double(i) / steps));
    return path;
}

Vec3 random_direction(std::mt19937& rng) {
    std::normal_distribution<double> g;
    return normalized(Vec3{g(rng), g(rng), g(rng)});
}

TEST(ProxyContact, FreeSpaceProxyFollowsTheDeviceWithZeroForce) {
    const Scene scene(test::make_sphere({}, 0.01, 2));
    ProxyContact contact;
    contact.reset({0.05, 0, 0});
    const ContactOutput out = contact.step(scene.world, {0.04, 0.01, 0}, {}, 1e-3);
    EXPECT_FALSE(out.in_contact);
    EXPECT_EQ(out.force_n, Vec3{});
    EXPECT_EQ(out.proxy_m, (Vec3{0.04, 0.01, 0}));
}

TEST(ProxyContact, PressingIntoAFlatWallGivesTheSpringForceAlongTheNormal) {
    const Scene scene(test::make_box({-0.05, -0.05, -0.02}, {0.05, 0.05, 0}));
    ProxyContact contact({.stiffness_n_per_m = 1000, .damping_n_s_per_m = 0});
    contact.reset({0, 0, 0.01});
    ContactOutput out;
    for (int i = 0; i <= 100; ++i)
        out = contact.step(scene.world, {0, 0, 0.01 - 0.012 * i / 100}, {}, 1e-3);
    ASSERT_TRUE(out.in_contact);
    EXPECT_NEAR(out.penetration_m, 0.002, 1e-5);
    EXPECT_NEAR(out.force_n.z, 2.0, 0.01);
    EXPECT_NEAR(out.force_n.x, 0, 1e-9);
    EXPECT_NEAR(out.normal.z, 1, 1e-9);
    EXPECT_GE(out.proxy_m.z, 0);
}

TEST(ProxyContact, DampingResistsApproachButNeverPulls) {
    const Scene scene(test::make_box({-0.05, -0.05, -0.02}, {0.05, 0.05, 0}));
    ProxyContact contact({.stiffness_n_per_m = 1000, .damping_n_s_per_m = 5});
    contact.reset({0, 0, 0.001});
    ContactOutput in = contact.step(scene.world, {0, 0, -0.001}, {0, 0, -0.1}, 1e-3);
    EXPECT_NEAR(in.force_n.z, 1.0 + 0.5, 0.01);
    ContactOutput out = contact.step(scene.world, {0, 0, -0.0001}, {0, 0, 1.0}, 1e-3);
    EXPECT_GE(out.force_n.z, 0);  // withdrawing fast: the damper may not pull the hand in
}

TEST(ProxyContact, FrictionSticksUnderTheStaticBoundAndSlipsAtTheDynamicBound) {
    const Scene scene(test::make_box({-0.05, -0.05, -0.02}, {0.05, 0.05, 0}));
    ContactParams params{.stiffness_n_per_m = 1000,
                         .damping_n_s_per_m = 0,
                         .static_friction_n = 0.4,
                         .dynamic_friction_n = 0.25};
    ProxyContact contact(params);
    contact.reset({0, 0, 0.001});
    contact.step(scene.world, {0, 0, -0.002}, {}, 1e-3);  // 2 N normal load
    // 0.3 mm sideways: 0.3 N < 0.4 N static: sticks.
    ContactOutput out = contact.step(scene.world, {0.0003, 0, -0.002}, {}, 1e-3);
    EXPECT_FALSE(out.slipping);
    EXPECT_NEAR(out.force_n.x, -0.3, 1e-3);
    // 0.6 mm: beyond static: slips, and the tangential force drops to the dynamic bound.
    out = contact.step(scene.world, {0.0006, 0, -0.002}, {}, 1e-3);
    EXPECT_TRUE(out.slipping);
    EXPECT_NEAR(out.force_n.x, -0.25, 1e-3);
    for (int i = 1; i <= 20; ++i)
        out = contact.step(scene.world, {0.0006 + 0.0001 * i, 0, -0.002}, {}, 1e-3);
    EXPECT_TRUE(out.slipping);
    EXPECT_NEAR(out.force_n.x, -0.25, 1e-3);
    // Coming back within the dynamic bound: sticks again.
    out = contact.step(scene.world, {out.proxy_m.x + 0.0001, 0, -0.002}, {}, 1e-3);
    EXPECT_FALSE(out.slipping);
    // No load, no friction: a grazing touch slides freely.
    contact.reset({0, 0, 0.001});
    out = contact.step(scene.world, {0.001, 0, -0.0000001}, {}, 1e-3);
    EXPECT_LE(std::abs(out.force_n.x), out.force_n.z + 1e-12);
    EXPECT_LT(out.force_n.z, 0.01);
}

TEST(ProxyContact, RandomApproachesIntoASphereNeverLeaveTheProxyInside) {
    const Scene scene(test::make_sphere({0.001, -0.002, 0.003}, 0.01, 2));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> depth(0.0, 0.009);
    ProxyContact contact({.stiffness_n_per_m = 1500, .damping_n_s_per_m = 2});
    int touching = 0;
    for (int path = 0; path < 60 * kScale; ++path) {
        const Vec3 from = Vec3{0.001, -0.002, 0.003} + random_direction(rng) * 0.02;
        const Vec3 to = Vec3{0.001, -0.002, 0.003} + random_direction(rng) * depth(rng);
        contact.reset(from);
        touching += drive(scene, contact, approach(from, to, 40, 60, 0.0015, rng));
    }
    EXPECT_GT(touching, 1000);
}

TEST(ProxyContact, AThinPlateStopsTheProxyEvenWhenTheDeviceJumpsThroughIt) {
    // 0.3 mm thick: the device crosses it within one tick (1 to 5 mm per tick); wide enough that
    // the device's wander never goes round its rim (which would rightly take the proxy along).
    const Scene scene(test::make_box({-0.08, -0.08, 0}, {0.08, 0.08, 0.0003}));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> xy(-0.015, 0.015), side(0, 1);
    ProxyContact contact;
    for (int path = 0; path < 100 * kScale; ++path) {
        const double sign = side(rng) < 0.5 ? 1 : -1;
        const Vec3 from{xy(rng), xy(rng), 0.00015 + sign * 0.01};
        const Vec3 to{xy(rng), xy(rng), 0.00015 - sign * 0.01};
        contact.reset(from);
        drive(scene, contact, approach(from, to, 4 + path % 16, 30, 0.004, rng));
        // The proxy stays on the side it came from.
        EXPECT_GT((contact.proxy().z - 0.00015) * sign, 0) << "path " << path;
    }
}

TEST(ProxyContact, PathsAimedAtEdgesAndVerticesNeverEnterABox) {
    const TestMesh box = test::make_box({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01});
    const Scene scene(box);
    std::mt19937 rng(9);
    ProxyContact contact;
    std::uniform_real_distribution<double> unit(-1, 1);
    for (int path = 0; path < 120 * kScale; ++path) {
        // A target on an edge or a vertex, approached from outside, pushed inwards past it.
        Vec3 target{unit(rng) > 0 ? 0.01 : -0.01, unit(rng) > 0 ? 0.01 : -0.01, unit(rng) * 0.01};
        if (path % 3 == 0) target.z = target.z > 0 ? 0.01 : -0.01;
        const Vec3 from = target * 2.0 + random_direction(rng) * 0.003;
        drive(scene, contact, approach(from, target * 0.3, 20, 40, 0.002, rng));
        contact.reset(from);
    }
}

TEST(ProxyContact, RandomApproachesIntoARealBoneNeverLeaveTheProxyInside) {
    const std::filesystem::path file =
        std::filesystem::path(KERF_SHARED_MESHES) / "bp3d_right_first_metatarsal.stl";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no shared meshes at " << file;
    const TestMesh bone = test::read_binary_stl(file.string(), 0.001);
    ASSERT_EQ(bone.triangles(), 4886u);
    const Scene scene(bone);
    Vec3 lo, hi;
    scene.body->bounds(lo, hi);
    const Vec3 centre = (lo + hi) * 0.5;
    const double reach = norm(hi - lo);
    std::mt19937 rng(21);
    ProxyContact contact;
    int touching = 0;
    for (int path = 0; path < 40 * kScale; ++path) {
        // Aim at a random surface vertex, then push 5 mm past it.
        const Vec3 target = bone.vertex(std::uint32_t(rng() % (bone.positions.size() / 3)));
        const Vec3 from = centre + random_direction(rng) * reach;
        const Vec3 beyond = target + normalized(target - from) * 0.005;
        contact.reset(from);
        touching += drive(scene, contact, approach(from, beyond, 60, 40, 0.001, rng), 4);
    }
    EXPECT_GT(touching, 400);
}

/// Two closed spheres that interpenetrate (bones at a joint), as one mesh.
TestMesh two_overlapping_spheres() {
    TestMesh a = test::make_sphere({0, 0, 0}, 0.01, 3);
    const TestMesh b = test::make_sphere({0.015, 0, 0}, 0.01, 3);
    const auto base = std::uint32_t(a.positions.size() / 3);
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (std::uint32_t i : b.indices) a.indices.push_back(base + i);
    a.materials.insert(a.materials.end(), b.materials.begin(), b.materials.end());
    return a;
}

// The way out of interpenetrating shells: a tool inside sphere A, whose nearest surface is B's
// (entered there, not left), is counted inside and its exit is in neither sphere; re-seating
// the proxy for such a tool (forces were off) puts it outside both.
TEST(ProxyContact, ReSeatingAToolInsideInterpenetratingShellsPutsTheProxyOutsideBoth) {
    const Scene scene(two_overlapping_spheres());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.011, 0.026), v(-0.011, 0.011);
    int inside = 0;
    for (int i = 0; i < 300 * kScale; ++i) {
        const Vec3 tool{u(rng), v(rng), v(rng)};
        const double w = test::winding_number(scene.mesh, tool);
        const CollisionWorld::WayOut out = scene.world.way_out(tool, tool + Vec3{0, 1, 0}, 1.0);
        ASSERT_TRUE(out.known);
        EXPECT_EQ(out.depth, int(std::lround(w))) << i;
        ForceModel model;
        model.reset_outside(scene.world, tool, 0.05);
        EXPECT_LT(test::winding_number(scene.mesh, model.contact().proxy()), 0.5) << i;
        if (w > 0.5) {
            ++inside;
            EXPECT_GT(norm(model.contact().proxy() - tool), 0.0) << i;
        } else {
            EXPECT_EQ(model.contact().proxy(), tool) << i;
        }
    }
    EXPECT_GT(inside, 60);
}

// The same on the scanned 24-shell forefoot (shells that touch and interpenetrate at the joints):
// tools within 3 mm of random surface vertices, the ray towards the nearest surface as the re-seat
// casts it. The depth way_out counts is the winding number, and the re-seated proxy is in no shell.
TEST(ProxyContact, ReSeatingAToolInTheMultiShellForefootPutsTheProxyOutsideEveryShell) {
    const std::filesystem::path file =
        std::filesystem::path(KERF_SHARED_MESHES) / "bp3d_right_forefoot_24shells.stl";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no shared meshes at " << file;
    const Scene scene(test::read_binary_stl(file.string(), 0.001));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> offset(-0.003, 0.003);
    int inside = 0;
    for (int i = 0; i < 40 * kScale; ++i) {
        const Vec3 v = scene.mesh.vertex(std::uint32_t(rng() % (scene.mesh.positions.size() / 3)));
        const Vec3 tool = v + Vec3{offset(rng), offset(rng), offset(rng)};
        const SurfaceHit near = scene.world.closest_point(tool, 0.05, kBoneSurfaces);
        ASSERT_TRUE(near.found);
        const CollisionWorld::WayOut out = scene.world.way_out(tool, near.point, 1.0);
        ASSERT_TRUE(out.known) << i;
        const double w = test::winding_number(scene.mesh, tool);
        EXPECT_EQ(out.depth, int(std::lround(w))) << i;
        ForceModel model;
        model.reset_outside(scene.world, tool, 0.05);
        EXPECT_LT(test::winding_number(scene.mesh, model.contact().proxy()), 0.5) << i;
        inside += w > 0.5 ? 1 : 0;
    }
    EXPECT_GT(inside, 8 * kScale);
}

TEST(ProxyContact, APieceDraggedIntoTheHeldProxyCarriesItAlong) {
    // The proxy rests on top of a block; the block is moved up by 3 mm in one tick (a severed
    // piece dragged): the proxy is carried to the new top instead of ending inside.
    const TestMesh block = test::make_box({-0.02, -0.02, -0.02}, {0.02, 0.02, 0});
    auto built = CollisionBody::build(block.view());
    ASSERT_TRUE(built);
    CollisionWorld world;
    world.set_body(0, built->get());
    ProxyContact contact;
    contact.reset({0, 0, 0.002});
    ContactOutput out = contact.step(world, {0, 0, -0.001}, {}, 1e-3);
    ASSERT_TRUE(out.in_contact);
    RigidTransform lifted;
    lifted.translation = {0, 0, 0.003};
    world.set_pose(0, lifted);
    out = contact.step(world, {0, 0, -0.001}, {}, 1e-3);
    EXPECT_TRUE(out.in_contact);
    EXPECT_GE(out.proxy_m.z, 0.003);
    EXPECT_NEAR(out.force_n.z, 1500 * 0.004, 0.05);
}

TEST(ProxyContact, StepAllocatesNothingAndIgnoresNonFiniteInput) {
    const Scene scene(test::make_sphere({}, 0.01, 3));
    ProxyContact contact;
    contact.reset({0.02, 0, 0});
    kerf::test::arm_allocation_counter();
    for (int i = 0; i < 10000; ++i) {
        const double r = 0.0105 - 0.002 * (i % 100) / 100.0;
        contact.step(scene.world, {r * std::cos(i * 1e-3), r * std::sin(i * 1e-3), 0}, {}, 1e-3);
    }
    EXPECT_EQ(kerf::test::disarm_allocation_counter(), 0u);
    const Vec3 before = contact.proxy();
    const ContactOutput out = contact.step(scene.world, {std::nan(""), 0, 0}, {}, 1e-3);
    EXPECT_EQ(out.force_n, Vec3{});
    EXPECT_EQ(contact.proxy(), before);
}

}  // namespace
}  // namespace kerf::physics
