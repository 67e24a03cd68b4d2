// CollisionBody / CollisionWorld: queries agree with brute force, bad meshes are refused, an
// update after a cut rebuilds only touched chunks, and queries allocate nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "rt_core/physics/collision_world.hpp"
#include "tests/allocation_counter.hpp"
#include "tests/physics/physics_test_shapes.hpp"

namespace kerf::physics {
namespace {

using test::TestMesh;

std::unique_ptr<const CollisionBody> build(const TestMesh& m, BuildOptions options = {}) {
    auto body = CollisionBody::build(m.view(), options);
    EXPECT_TRUE(body) << (body ? "" : to_string(body.error().error));
    return body ? std::move(*body) : nullptr;
}

TEST(CollisionBody, ClosestPointMatchesBruteForceOnASphere) {
    const TestMesh sphere = test::make_sphere({0.01, 0, 0}, 0.02, 3);
    const auto body = build(sphere, {.chunk_triangles = 64, .leaf_triangles = 4});
    ASSERT_TRUE(body);
    EXPECT_GT(body->chunk_count(), 1u);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-0.04, 0.04);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        const SurfaceHit hit = body->closest_point(p, 1.0);
        ASSERT_TRUE(hit.found);
        EXPECT_NEAR(hit.distance, test::brute_distance(sphere, p), 1e-9);
        EXPECT_NEAR(norm(hit.point - p), hit.distance, 1e-12);
    }
}

TEST(CollisionBody, ClosestPointHonoursTheSearchDistance) {
    const auto body = build(test::make_sphere({}, 0.01, 2));
    ASSERT_TRUE(body);
    EXPECT_FALSE(body->closest_point({0.05, 0, 0}, 0.01).found);
    EXPECT_TRUE(body->closest_point({0.05, 0, 0}, 0.05).found);
}

TEST(CollisionBody, FirstHitFindsTheNearestCrossingAndRespectsSides) {
    const TestMesh plate = test::make_box({-0.01, -0.01, 0}, {0.01, 0.01, 0.0005});
    const auto body = build(plate);
    ASSERT_TRUE(body);
    const SegmentHit down =
        body->first_hit({0.001, 0.002, 0.01}, {0.001, 0.002, -0.01}, HitSides::kFront);
    ASSERT_TRUE(down.found);
    EXPECT_NEAR(down.point.z, 0.0005, 1e-9);
    EXPECT_NEAR(down.normal.z, 1.0, 1e-12);
    // From inside the plate outwards only back faces are crossed.
    EXPECT_FALSE(body->first_hit({0, 0, 0.0002}, {0, 0, 0.01}, HitSides::kFront).found);
    EXPECT_TRUE(body->first_hit({0, 0, 0.0002}, {0, 0, 0.01}, HitSides::kBoth).found);
}

TEST(CollisionBody, SegmentsThroughSharedEdgesAndVerticesAreStopped) {
    const TestMesh sphere = test::make_sphere({}, 0.01, 2);
    const auto body = build(sphere);
    ASSERT_TRUE(body);
    // Aim exactly at every vertex and every edge midpoint from outside.
    for (std::size_t i = 0; i < sphere.indices.size(); i += 3) {
        for (int k = 0; k < 3; ++k) {
            const Vec3 a = sphere.vertex(sphere.indices[i + k]);
            const Vec3 b = sphere.vertex(sphere.indices[i + (k + 1) % 3]);
            for (const Vec3& target : {a, (a + b) * 0.5}) {
                const SegmentHit hit =
                    body->first_hit(target * 2.0, target * 0.0, HitSides::kFront);
                ASSERT_TRUE(hit.found) << "triangle " << i / 3;
            }
        }
    }
}

// Crossings are counted watertight: along any segment their signs sum to the winding number at
// its start minus that at its end, also where it passes exactly through shared edges and
// vertices; each crossing agrees with a brute-force pass over every triangle.
TEST(CollisionBody, CrossingsCountEverySurfaceOnceAlongASegment) {
    const TestMesh outer = test::make_sphere({0.01, 0, 0}, 0.02, 3);
    const TestMesh inner = test::make_sphere({0.01, 0, 0}, 0.01, 2);
    TestMesh both = outer;  // two nested shells: a segment crosses up to four surfaces
    const auto base = std::uint32_t(both.positions.size() / 3);
    both.positions.insert(both.positions.end(), inner.positions.begin(), inner.positions.end());
    for (std::uint32_t i : inner.indices) both.indices.push_back(base + i);
    both.materials.insert(both.materials.end(), inner.materials.begin(), inner.materials.end());
    // Pieces of at most 1 mm: every triangle is indexed as several (seen once all the same).
    const auto body =
        build(both, {.chunk_triangles = 64, .leaf_triangles = 4, .max_piece_edge_m = 0.001});
    ASSERT_TRUE(body);
    const auto check = [&](const Vec3& from, const Vec3& to, int i) {
        std::vector<std::pair<double, int>> expected;
        for (std::size_t k = 0; k < both.indices.size(); k += 3) {
            const TriangleCrossing x = segment_crossing(
                from, to - from, both.vertex(both.indices[k]), both.vertex(both.indices[k + 1]),
                both.vertex(both.indices[k + 2]));
            if (x.sign != 0) expected.push_back({x.t, x.sign});
        }
        SegmentCrossing out[16];
        const std::size_t n = body->crossings(from, to, out);
        ASSERT_EQ(n, expected.size()) << i;
        ASSERT_LE(n, std::size(out));
        std::vector<std::pair<double, int>> got;
        int sum = 0;
        for (std::size_t k = 0; k < n; ++k) {
            got.push_back({out[k].t, out[k].sign});
            sum += out[k].sign;
        }
        std::sort(expected.begin(), expected.end());
        std::sort(got.begin(), got.end());
        EXPECT_EQ(got, expected) << i;
        const double w = test::winding_number(both, from) - test::winding_number(both, to);
        EXPECT_EQ(sum, int(std::lround(w))) << i;
        // A short buffer: the count is still every crossing (past the buffer a triangle indexed
        // in pieces may count once per piece).
        EXPECT_GE(body->crossings(from, to, std::span<SegmentCrossing>(out, 1)), n) << i;
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(-0.04, 0.05);
    for (int i = 0; i < 300; ++i) {
        check({coord(rng), coord(rng), coord(rng)}, {coord(rng), coord(rng), coord(rng)}, i);
    }
    // Exactly through the vertices and edge midpoints of every 7th triangle of both shells, from
    // the centre outwards (corners and midpoints of the float mesh, as the structure stores them).
    for (std::size_t k = 0; k < both.indices.size(); k += 3 * 7) {
        for (int e = 0; e < 3; ++e) {
            const Vec3 a = both.vertex(both.indices[k + e]);
            const Vec3 b = both.vertex(both.indices[k + (e + 1) % 3]);
            for (const Vec3& target : {a, (a + b) * 0.5}) {
                const Vec3 centre{0.01, 0, 0};
                check(centre, centre + (target - centre) * 3.0, int(k));
            }
        }
    }
}

TEST(CollisionBody, NearTrianglesListsTheNeighbourhood) {
    const TestMesh sphere = test::make_sphere({}, 0.01, 3);
    const auto body = build(sphere);
    ASSERT_TRUE(body);
    std::uint32_t out[256];
    const std::size_t n = body->triangles_near({0.0101, 0, 0}, 0.001, out);
    ASSERT_GT(n, 0u);
    ASSERT_LE(n, 256u);
    for (std::size_t i = 0; i < n; ++i) {
        const TriangleCorners c = body->corners(out[i]);
        const Vec3 q = closest_point_on_triangle({0.0101, 0, 0}, c.a, c.b, c.c);
        EXPECT_LE(norm(q - Vec3{0.0101, 0, 0}), 0.001 + 1e-12);
    }
    EXPECT_EQ(body->triangles_near({0.1, 0, 0}, 0.001, out), 0u);
}

TEST(CollisionBody, BadMeshesAreRefusedNamingTheProblem) {
    TestMesh m = test::make_box({0, 0, 0}, {0.01, 0.01, 0.01});
    TestMesh bad = m;
    bad.indices[7] = 99;
    auto r = CollisionBody::build(bad.view());
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().error, MeshError::kIndexOutOfRange);
    EXPECT_EQ(r.error().index, 7u);
    bad = m;
    bad.positions[4] = std::nanf("");
    EXPECT_EQ(validate_mesh(bad.view()).error, MeshError::kNonFinitePosition);
    bad = m;
    bad.positions[4] = 11.0f;
    EXPECT_EQ(validate_mesh(bad.view()).error, MeshError::kCoordinateTooLarge);
    bad = m;
    bad.materials.pop_back();
    EXPECT_EQ(validate_mesh(bad.view()).error, MeshError::kMaterialCount);
    bad = m;
    bad.indices.pop_back();
    EXPECT_EQ(validate_mesh(bad.view()).error, MeshError::kIndicesNotTriples);
    bad = m;
    bad.pose.rotation.m[0][0] = 2;
    EXPECT_EQ(validate_mesh(bad.view()).error, MeshError::kBadTransform);
    EXPECT_EQ(validate_mesh(TestMesh{}.view()).error, MeshError::kEmpty);
    EXPECT_EQ(to_string(MeshError::kEmpty), "mesh has no triangle");
}

// update() checks only the blocks that differ from the previous mesh; what it refuses, and how it
// names the problem, must be validate_mesh's answer on the whole mesh.
TEST(CollisionBody, UpdateRefusesWhatValidateMeshRefusesWithTheSameAnswer) {
    const TestMesh before = test::make_sphere({}, 0.02, 4);  // 5120 triangles, 2562 vertices
    const auto body = build(before, {.chunk_triangles = 512, .leaf_triangles = 4});
    ASSERT_TRUE(body);
    const auto vertices = static_cast<std::uint32_t>(before.positions.size() / 3);
    std::vector<std::pair<const char*, TestMesh>> cases;
    TestMesh m = before;  // an appended vertex that is not finite, used by a new triangle
    m.add_triangle(m.add_vertex({0, 0, 0.03}), 1, 2, Material::kCutSurface);
    m.positions[m.positions.size() - 2] = std::nanf("");
    cases.emplace_back("appended NaN", m);
    m = before;  // an existing vertex moved beyond 10 m
    m.positions[3 * 1500 + 2] = 11.0f;
    cases.emplace_back("moved too far", m);
    m = before;  // a triangle rewritten in place with an index out of range
    m.indices[3 * 4000 + 1] = vertices + 5;
    cases.emplace_back("changed index", m);
    m = before;  // the last vertex removed, the triangles that use it left unchanged
    m.positions.resize(m.positions.size() - 3);
    cases.emplace_back("removed vertex", m);
    m = before;  // an appended triangle with a material outside the enum
    m.add_triangle(0, 1, 2, static_cast<Material>(7));
    cases.emplace_back("bad material", m);
    for (const auto& [what, bad] : cases) {
        const MeshProblem expected = validate_mesh(bad.view());
        ASSERT_NE(expected.error, MeshError::kNone) << what;
        const auto updated = CollisionBody::update(*body, bad.view());
        ASSERT_FALSE(updated) << what;
        EXPECT_EQ(updated.error().error, expected.error) << what;
        EXPECT_EQ(updated.error().index, expected.index) << what;
    }
    EXPECT_TRUE(CollisionBody::update(*body, before.view()));
}

TEST(CollisionBody, UpdateAfterACutRebuildsOnlyTouchedChunks) {
    const TestMesh before = test::make_sphere({}, 0.02, 5);  // 20480 triangles
    const auto body = build(before, {.chunk_triangles = 1024, .leaf_triangles = 4});
    ASSERT_TRUE(body);
    // A "cut": split the triangles crossing a small region in two (changed + appended ones).
    TestMesh after = before;
    std::size_t changed = 0;
    for (std::size_t t = 0; t < before.triangles() && changed < 40; ++t) {
        const Vec3 a = before.vertex(before.indices[3 * t]);
        if (a.x < 0.019) continue;
        const std::uint32_t b = before.indices[3 * t + 1], c = before.indices[3 * t + 2];
        const std::uint32_t m = after.add_vertex((before.vertex(b) + before.vertex(c)) * 0.5);
        after.indices[3 * t + 2] = m;
        after.add_triangle(before.indices[3 * t], m, c, Material::kCutSurface);
        ++changed;
    }
    ASSERT_GT(changed, 0u);
    UpdateStats stats;
    auto updated = CollisionBody::update(*body, after.view(), &stats);
    ASSERT_TRUE(updated);
    EXPECT_LT(stats.chunks_refitted + stats.chunks_rebuilt, body->chunk_count() / 2);
    EXPECT_GT(stats.chunks_refitted, 0u);
    EXPECT_GT(stats.chunks_rebuilt, 0u);  // the appended triangles' chunk
    EXPECT_LT(stats.triangles_touched, after.triangles() / 2);
    const auto fresh = build(after);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coord(-0.03, 0.03);
    for (int i = 0; i < 300; ++i) {
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        EXPECT_NEAR((*updated)->closest_point(p, 1).distance, fresh->closest_point(p, 1).distance,
                    1e-12);
    }
    EXPECT_EQ((*updated)->triangle_count(), after.triangles());
    // And back: triangles removed (their chunks rebuilt from the survivors).
    auto back = CollisionBody::update(**updated, before.view(), &stats);
    ASSERT_TRUE(back);
    EXPECT_EQ((*back)->triangle_count(), before.triangles());
    EXPECT_GT(stats.chunks_rebuilt, 0u);
    for (int i = 0; i < 300; ++i) {
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        EXPECT_NEAR((*back)->closest_point(p, 1).distance, body->closest_point(p, 1).distance,
                    1e-12);
    }
    // Moving vertices only: the chunks holding them are refitted, none rebuilt.
    TestMesh moved = before;
    for (std::size_t v = 0; v < 30; ++v) moved.positions[3 * v] *= 1.01f;
    auto refitted = CollisionBody::update(*body, moved.view(), &stats);
    ASSERT_TRUE(refitted);
    EXPECT_EQ(stats.chunks_rebuilt, 0u);
    EXPECT_GT(stats.chunks_refitted, 0u);
    const auto moved_fresh = build(moved);
    for (int i = 0; i < 300; ++i) {
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        EXPECT_NEAR((*refitted)->closest_point(p, 1).distance,
                    moved_fresh->closest_point(p, 1).distance, 1e-12);
    }
}

// Faces removed from the front of the arrays (a body severed) shift every index after them: a
// chunk's slots then hold other triangles, anywhere on the body. Those chunks are regrouped, so
// the update answers like a fresh build and no chunk spans the body; a local cut regroups none.
TEST(CollisionBody, UpdateAfterShiftedIndicesRegroupsTheChunksThatSpreadOut) {
    const TestMesh before = test::make_sphere({}, 0.02, 5);  // 20480 triangles
    const auto body = build(before, {.chunk_triangles = 1024, .leaf_triangles = 4});
    ASSERT_TRUE(body);
    TestMesh after = before;  // the first 100 triangles gone, the rest moved up by 100
    after.indices.erase(after.indices.begin(), after.indices.begin() + 300);
    after.materials.erase(after.materials.begin(), after.materials.begin() + 100);
    UpdateStats stats;
    auto updated = CollisionBody::update(*body, after.view(), &stats);
    ASSERT_TRUE(updated);
    EXPECT_GT(stats.chunks_regrouped, body->chunk_count() / 2);
    EXPECT_LE((*updated)->chunk_count(), body->chunk_count() + 2);
    const auto fresh = build(after);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-0.03, 0.03);
    for (int i = 0; i < 300; ++i) {
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        EXPECT_NEAR((*updated)->closest_point(p, 1).distance, fresh->closest_point(p, 1).distance,
                    1e-12);
    }
    // A local change (one triangle's material) regroups nothing.
    TestMesh local = after;
    local.materials[5000] = Material::kCutSurface;
    auto again = CollisionBody::update(**updated, local.view(), &stats);
    ASSERT_TRUE(again);
    EXPECT_EQ(stats.chunks_regrouped, 0u);
    EXPECT_EQ(stats.chunks_refitted, 1u);
}

TEST(CollisionBody, RefitFollowsMovedVertices) {
    const TestMesh a = test::make_sphere({}, 0.01, 3);
    const auto body = build(a);
    TestMesh b = a;
    for (float& c : b.positions) c *= 1.5f;
    auto refitted = CollisionBody::refit(*body, b.view());
    ASSERT_TRUE(refitted);
    EXPECT_NEAR((*refitted)->closest_point({0.03, 0, 0}, 1).distance, 0.015, 1e-4);
    TestMesh other = test::make_box({0, 0, 0}, {1e-3, 1e-3, 1e-3});
    EXPECT_FALSE(CollisionBody::refit(*body, other.view()));
}

TEST(CollisionWorld, QueriesTransformEveryBodyIntoTheWorld) {
    TestMesh sphere = test::make_sphere({}, 0.01, 2);
    sphere.pose.translation = {0.1, 0, 0};
    const auto body = build(sphere);
    CollisionWorld world;
    world.set_body(3, body.get());
    EXPECT_EQ(world.slot_end(), 4u);
    const SurfaceHit hit = world.closest_point({0.1, 0, 0.05}, 1);
    ASSERT_TRUE(hit.found);
    EXPECT_EQ(hit.body, 3u);
    EXPECT_NEAR(hit.distance, 0.04, 2e-4);
    EXPECT_TRUE(world.inside({0.1, 0, 0}, 0.1));
    EXPECT_FALSE(world.inside({0.2, 0, 0}, 0.2));
    RigidTransform moved;
    moved.translation = {0, 0.1, 0};
    world.set_pose(3, moved);
    EXPECT_TRUE(world.first_hit({0, 0.2, 0}, {0, 0.1, 0}, HitSides::kFront).found);
    world.clear();
    EXPECT_FALSE(world.closest_point({0, 0.1, 0}, 1).found);
}

// Box A holds the tool; the ray leaves A through the middle of a face (the diagonal edge its two
// triangles share: one crossing) and then grazes an edge of box B (entering one face and leaving
// the other at the same point: no crossing). The start is in one shell, and leaves it on A's face.
// (The cast-by-cast walk this replaced counted the graze as one crossing: depth 0 or 2.)
TEST(CollisionWorld, WayOutCountsASharedEdgeOnceAndAGrazedEdgeNotAtAll) {
    constexpr double h = 1.0 / 128;  // exact in float, as the structure stores corners
    TestMesh mesh = test::make_box({-h, -h, -h}, {h, h, h});
    const TestMesh b = test::make_box({2 * h, -h, -h}, {4 * h, h, h});
    const auto base = std::uint32_t(mesh.positions.size() / 3);
    mesh.positions.insert(mesh.positions.end(), b.positions.begin(), b.positions.end());
    for (std::uint32_t i : b.indices) mesh.indices.push_back(base + i);
    mesh.materials.insert(mesh.materials.end(), b.materials.begin(), b.materials.end());
    const auto body = build(mesh);
    CollisionWorld world;
    world.set_body(0, body.get());
    const Vec3 tool{0.5 * h, -0.5 * h, 0};  // on the line through B's edge at (2h, h, 0)
    const CollisionWorld::WayOut out = world.way_out(tool, {2 * h, h, 0}, 1.0);
    ASSERT_TRUE(out.known);
    EXPECT_EQ(out.depth, 1);
    EXPECT_NEAR(out.exit.x, h, 1e-12);
    EXPECT_NEAR(out.exit.y, 0, 1e-12);
    EXPECT_NEAR(out.normal.x, 1, 1e-12);
    // Outside both, the same ray through the graze: depth 0, the exit is the start.
    const CollisionWorld::WayOut outside = world.way_out({1.5 * h, 0.5 * h, 0}, {2 * h, h, 0}, 1.0);
    ASSERT_TRUE(outside.known);
    EXPECT_EQ(outside.depth, 0);
    EXPECT_EQ(outside.exit, (Vec3{1.5 * h, 0.5 * h, 0}));
}

// Two boxes sharing a face (a withdrawn cut closed in the collision mesh: its caps coincide): a
// ray from inside A leaves A and enters B at the same point. That is no way out for a proxy;
// with a minimum gap the exit is B's far face.
TEST(CollisionWorld, WayOutThroughCoincidentOppositeFacesIsNoExitGivenAMinimumGap) {
    constexpr double h = 1.0 / 128;
    TestMesh mesh = test::make_box({-h, -h, -h}, {h, h, h});
    const TestMesh b = test::make_box({h, -h, -h}, {3 * h, h, h});
    const auto base = std::uint32_t(mesh.positions.size() / 3);
    mesh.positions.insert(mesh.positions.end(), b.positions.begin(), b.positions.end());
    for (std::uint32_t i : b.indices) mesh.indices.push_back(base + i);
    mesh.materials.insert(mesh.materials.end(), b.materials.begin(), b.materials.end());
    const auto body = build(mesh);
    CollisionWorld world;
    world.set_body(0, body.get());
    const Vec3 tool{0.25 * h, 0.125 * h, 0.0625 * h};
    const CollisionWorld::WayOut out = world.way_out(tool, tool + Vec3{1, 0, 0}, 1.0, 1e-6);
    ASSERT_TRUE(out.known);
    EXPECT_EQ(out.depth, 1);
    EXPECT_NEAR(out.exit.x, 3 * h, 1e-12);
    EXPECT_NEAR(out.normal.x, 1, 1e-12);
    // From inside B, leaving through its far face: an exit at once, whatever the gap asked.
    const Vec3 in_b{2 * h, 0.125 * h, 0.0625 * h};
    EXPECT_NEAR(world.way_out(in_b, in_b + Vec3{1, 0, 0}, 1.0, 1e-6).exit.x, 3 * h, 1e-12);
}

TEST(CollisionWorld, PerTickQueriesAllocateNothing) {
    const auto body = build(test::make_sphere({}, 0.01, 4));
    CollisionWorld world;
    world.set_body(0, body.get());
    std::uint32_t out[64];
    kerf::test::arm_allocation_counter();
    double sum = 0;
    for (int i = 0; i < 10000; ++i) {
        const Vec3 p{0.012 * std::cos(i * 0.01), 0.012 * std::sin(i * 0.01), 0.001};
        sum += world.closest_point(p, 0.01).distance;
        sum += world.first_hit(p, p * 0.5, HitSides::kFront).t;
        sum += double(body->triangles_near(p, 0.003, out));
        sum += world.way_out(p * 0.5, p, 1.0).exit.x;
    }
    EXPECT_EQ(kerf::test::disarm_allocation_counter(), 0u);
    EXPECT_GT(sum, 0);
}

}  // namespace
}  // namespace kerf::physics
