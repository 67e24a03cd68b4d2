#include <gtest/gtest.h>

#include <random>

#include "display/mesh/indexed_mesh.hpp"

namespace kerf::mesh {
namespace {

TEST(VertexWelder, GivesIndicesInFirstSeenOrderAndWeldsBitIdenticalPoints) {
    IndexedMesh out;
    VertexWelder w;
    EXPECT_EQ(w.weld(Point(1, 2, 3), out), 0u);
    EXPECT_EQ(w.weld(Point(4, 5, 6), out), 1u);
    EXPECT_EQ(w.weld(Point(1, 2, 3), out), 0u);
    EXPECT_EQ(w.weld(Point(1, 2, std::nextafter(3.0, 4.0)), out), 2u);  // no tolerance
    EXPECT_EQ(w.weld(Point(0.0, 0.0, 0.0), out), 3u);
    EXPECT_EQ(w.weld(Point(-0.0, 0.0, -0.0), out), 3u);  // -0 welds with +0
    ASSERT_EQ(out.positions_m.size(), 4u);
    EXPECT_EQ(out.positions_m[1], Point(4, 5, 6));
}

TEST(VertexWelder, KeepsEveryIndexThroughManyRegrowths) {
    // 100,000 distinct points, each welded twice: the second pass (after the table has regrown
    // many times) finds every one at the index the first pass gave, with or without reserve().
    for (const bool reserve : {false, true}) {
        IndexedMesh out;
        VertexWelder w;
        if (reserve) w.reserve(1000);
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        std::vector<Point> points(100000);
        for (Point& p : points) {
            const double x = u(rng), y = u(rng), z = u(rng);
            p = Point(x, y, z);
        }
        for (std::size_t i = 0; i < points.size(); ++i)
            ASSERT_EQ(w.weld(points[i], out), static_cast<std::uint32_t>(i));
        for (std::size_t i = 0; i < points.size(); ++i)
            ASSERT_EQ(w.weld(points[i], out), static_cast<std::uint32_t>(i));
        EXPECT_EQ(out.positions_m.size(), points.size());
    }
}

}  // namespace
}  // namespace kerf::mesh
