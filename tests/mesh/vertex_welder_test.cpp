#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/mesh_io.hpp"
#include "tests/mesh/mesh_test_support.hpp"

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

TEST(VertexWelder, BinaryStlWeldsOnFloatBitsExactlyAsOnThePointsInMetres) {
    // Binary STL welds on the file's float bits; that must give the indices and points
    // VertexWelder gives on the points in metres, in every unit: corners drawn from a small pool
    // (so most repeat) that holds -0 next to +0, adjacent floats and subnormals.
    std::vector<float> values = {0.0f,
                                 -0.0f,
                                 1.0f,
                                 std::nextafter(1.0f, 2.0f),
                                 -1.0f,
                                 1e-40f,
                                 std::nextafter(1e-40f, 1.0f),
                                 3e38f,
                                 12.5f,
                                 12.500001f};
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::size_t> pick(0, values.size() - 1);
    const std::size_t triangles = 3000;
    std::string stl(84 + 50 * triangles, '\0');
    const auto count = static_cast<std::uint32_t>(triangles);
    std::memcpy(stl.data() + 80, &count, 4);  // little-endian host (x86-64, as everywhere here)
    std::vector<float> corners;
    for (std::size_t f = 0; f < triangles; ++f) {
        for (std::size_t c = 0; c < 9; ++c) {
            const float v = values[pick(rng)];
            corners.push_back(v);
            std::memcpy(stl.data() + 84 + 50 * f + 12 + 4 * c, &v, 4);
        }
    }
    for (const LengthUnit unit : kLengthUnits) {
        auto parsed = parse_indexed(as_bytes(stl), Format::kStl, unit);
        ASSERT_TRUE(parsed.has_value()) << to_string(unit);
        IndexedMesh expected;
        VertexWelder w;
        std::vector<std::uint32_t> indices;
        const double s = metres_per_unit(unit);
        for (std::size_t c = 0; c < corners.size(); c += 3) {
            const Point p(double{corners[c]} * s, double{corners[c + 1]} * s,
                          double{corners[c + 2]} * s);
            indices.push_back(w.weld(p, expected));
        }
        ASSERT_EQ(parsed->triangles.size(), triangles);
        for (std::size_t i = 0; i < indices.size(); ++i)
            ASSERT_EQ(parsed->triangles[i / 3][i % 3], indices[i]) << to_string(unit) << " " << i;
        ASSERT_EQ(parsed->positions_m.size(), expected.positions_m.size());
        for (std::size_t i = 0; i < expected.positions_m.size(); ++i) {
            for (int k = 0; k < 3; ++k) {  // bit for bit, -0 kept where it came first
                EXPECT_EQ(std::bit_cast<std::uint64_t>(parsed->positions_m[i][k]),
                          std::bit_cast<std::uint64_t>(expected.positions_m[i][k]));
            }
        }
    }
}

}  // namespace
}  // namespace kerf::mesh
