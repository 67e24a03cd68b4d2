// Cap triangulation: loops with any nesting and orientation, degenerate input, determinism.
#include "display/cut/triangulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "tests/cut/triangulation_checks.hpp"

namespace kerf::cut {
namespace {

using testing::check_triangulation;
using testing::Loops;
using testing::spans_of;

std::vector<Point2> circle(Point2 c, double r, int n, bool ccw = true) {
    std::vector<Point2> loop;
    for (int k = 0; k < n; ++k) {
        const double a = 2.0 * M_PI * k / n * (ccw ? 1.0 : -1.0);
        loop.emplace_back(c[0] + r * std::cos(a), c[1] + r * std::sin(a));
    }
    return loop;
}

std::vector<Point2> square(Point2 lo, double side, bool ccw = true) {
    std::vector<Point2> s{lo, lo + Point2(side, 0), lo + Point2(side, side), lo + Point2(0, side)};
    if (!ccw) std::reverse(s.begin(), s.end());
    return s;
}

/// Triangulates, expects success and every invariant of check_triangulation.
std::vector<Triangle> expect_valid(const Loops& loops, bool exact = false,
                                   TriangulateStats* stats = nullptr) {
    Triangulator t;
    std::vector<Triangle> tris;
    const auto spans = spans_of(loops);
    const auto s = t.triangulate(spans, tris);
    EXPECT_TRUE(s.has_value()) << to_string(s.error().code) << " loop " << s.error().loop;
    EXPECT_EQ(check_triangulation(loops, tris, exact), "");
    EXPECT_EQ(t.stats().degenerate_ears, 0u);
    if (stats != nullptr) *stats = t.stats();
    return tris;
}

TriangulateError expect_refused(const Loops& loops, TriangulateErrc why) {
    std::vector<Triangle> tris{{0, 1, 2}};
    Triangulator t;
    const auto spans = spans_of(loops);
    const auto s = t.triangulate(spans, tris);
    EXPECT_FALSE(s.has_value());
    EXPECT_TRUE(tris.empty());
    if (s.has_value()) return {};
    EXPECT_EQ(s.error().code, why) << to_string(s.error().code);
    return s.error();
}

TEST(Triangulate, SquareGivesTwoCounterClockwiseTrianglesInEitherOrientation) {
    TriangulateStats st;
    EXPECT_EQ(expect_valid({square({0, 0}, 1.0)}, true, &st).size(), 2u);
    EXPECT_EQ(st.fans, 1u);
    EXPECT_EQ(expect_valid({square({0, 0}, 1.0, false)}, true).size(), 2u);
}

TEST(Triangulate, ConvexLoopIsFannedAndConcaveLoopIsEarClipped) {
    TriangulateStats st;
    expect_valid({circle({0, 0}, 1.0, 50)}, false, &st);
    EXPECT_EQ(st.fans, 1u);
    // An L-shape: one reflex vertex, so no fan.
    expect_valid({{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}}, true, &st);
    EXPECT_EQ(st.fans, 0u);
}

TEST(Triangulate, AnnulusLikeABoneCrossSectionHasTheRingArea) {
    TriangulateStats st;
    const Loops bone{circle({0, 0}, 0.010, 400), circle({0.001, 0}, 0.004, 200, true)};
    const auto tris = expect_valid(bone, false, &st);
    EXPECT_EQ(st.outer_loops, 1u);
    EXPECT_EQ(st.holes, 1u);
    EXPECT_EQ(st.strips, 1u);  // stitched between the two loops, no ear clipping
    EXPECT_EQ(tris.size(), 600u);
}

TEST(Triangulate, AHoleTheStripCannotReachIsEarClippedInstead) {
    // A C-shaped region with a hole in its lower arm: a strip round the hole would have to cross
    // the gap of the C, so some strip triangle turns clockwise and the region is ear-clipped.
    TriangulateStats st;
    const Loops c_shape{{{0, 0}, {10, 0}, {10, 3}, {3, 3}, {3, 7}, {10, 7}, {10, 10}, {0, 10}},
                        square({5, 1}, 1, false)};
    const auto tris = expect_valid(c_shape, true, &st);
    EXPECT_EQ(st.strips, 0u);
    EXPECT_EQ(tris.size(), 12u);  // 8 + 4 points, one hole: n + 2h - 2 triangles
}

TEST(Triangulate, IslandsInsideHolesAndLoopsSideBySideAreAllCapped) {
    TriangulateStats st;
    const Loops loops{
        square({0, 0}, 16), square({2, 2}, 12, false),  // outer + hole
        square({4, 4}, 8),  square({6, 6}, 4),          // island in the hole, hole in the island
        square({20, 0}, 4), square({21, 1}, 2),         // a second annulus beside the first
        square({30, 0}, 3),                             // and a plain square
    };
    expect_valid(loops, true, &st);
    EXPECT_EQ(st.outer_loops, 4u);
    EXPECT_EQ(st.holes, 3u);
}

TEST(Triangulate, CollinearPointsOnEdgesNeverGiveZeroAreaTriangles) {
    // A square with 10 points on every side, and a comb with collinear teeth bases.
    std::vector<Point2> dense;
    for (int side = 0; side < 4; ++side) {
        for (int k = 0; k < 10; ++k) {
            const double t = k;
            const Point2 p = side == 0   ? Point2(t, 0)
                             : side == 1 ? Point2(10, t)
                             : side == 2 ? Point2(10 - t, 10)
                                         : Point2(0, 10 - t);
            dense.push_back(p);
        }
    }
    expect_valid({dense}, true);
    // A comb whose tooth bases are collinear runs along y = 2.
    std::vector<Point2> comb{{0, 0}, {20, 0}};
    for (int k = 9; k >= 0; --k) {
        const double x = 2.0 * k;
        comb.insert(comb.end(), {Point2(x + 2, 2), Point2(x + 1.5, 2), Point2(x + 1.25, 6),
                                 Point2(x + 0.75, 6), Point2(x + 0.5, 2)});
    }
    comb.emplace_back(0, 2);
    expect_valid({comb, square({4, 0.5}, 1, false)}, true);
}

TEST(Triangulate, HolesTouchingTheBridgeRayAtVerticesAreBridgedCleanly) {
    // Holes whose leftmost vertices share one y with outer vertices and with each other.
    const Loops loops{{{0, 0}, {10, 0}, {10, 4}, {5, 4}, {5, 6}, {10, 6}, {10, 10}, {0, 10}},
                      {{2, 5}, {3, 4}, {4, 5}, {3, 6}},
                      {{6, 2}, {7, 1}, {8, 2}, {7, 3}},
                      {{6, 8}, {7, 7}, {8, 8}, {7, 9}}};
    expect_valid(loops, true);
}

TEST(Triangulate, RandomRegionsWithHolesAndIslandsKeepEveryInvariant) {
    std::mt19937_64 rng(12345);
    for (int trial = 0; trial < 300; ++trial) {
        const Loops loops = testing::random_region(rng, trial % 2 == 0 ? 12 : 80);
        SCOPED_TRACE(trial);
        expect_valid(loops, true);
    }
}

TEST(Triangulate, LargeCrossSectionOfThousandsOfPointsIsValid) {
    std::mt19937_64 rng(7);
    Loops loops{testing::star_loop(rng, {0, 0}, 0.009, 0.010, 3000, false, false),
                testing::star_loop(rng, {0, 0}, 0.003, 0.004, 1500, true, false)};
    TriangulateStats st;
    const auto tris = expect_valid(loops, false, &st);
    EXPECT_EQ(tris.size(), 4500u);
}

TEST(Triangulate, SameInputGivesTheSameTrianglesAndTheTriangulatorIsReusable) {
    std::mt19937_64 rng(99);
    const Loops a = testing::random_region(rng, 40);
    const Loops b = testing::random_region(rng, 40);
    Triangulator t;
    std::vector<Triangle> first, other, again;
    ASSERT_TRUE(t.triangulate(spans_of(a), first).has_value());
    ASSERT_TRUE(t.triangulate(spans_of(b), other).has_value());
    ASSERT_TRUE(t.triangulate(spans_of(a), again).has_value());
    EXPECT_EQ(first, again);
    const auto oneshot = triangulate_loops(spans_of(a));
    ASSERT_TRUE(oneshot.has_value());
    EXPECT_EQ(*oneshot, first);
}

TEST(Triangulate, EmptyAndTooShortLoopsAreRefused) {
    expect_refused({}, TriangulateErrc::kNoLoops);
    const auto e =
        expect_refused({square({0, 0}, 1), {{0, 0}, {1, 1}}}, TriangulateErrc::kTooFewPoints);
    EXPECT_EQ(e.loop, 1);
}

TEST(Triangulate, NonFiniteCoordinatesAreRefused) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    expect_refused({{{0, 0}, {1, 0}, {nan, 1}}}, TriangulateErrc::kNonFinite);
    expect_refused({{{0, 0}, {inf, 0}, {0, 1}}}, TriangulateErrc::kNonFinite);
}

TEST(Triangulate, ZeroAreaLoopIsRefused) {
    const auto e = expect_refused({square({5, 5}, 1), {{0, 0}, {1, 1}, {2, 2}, {3, 3}}},
                                  TriangulateErrc::kZeroArea);
    EXPECT_EQ(e.loop, 1);
}

TEST(Triangulate, CrossingTouchingOrRepeatingLoopsAreRefusedWithTheLoopsNamed) {
    // A bow-tie crosses itself.
    auto e = expect_refused({{{0, 0}, {4, 4}, {4, 0}, {0, 2}}}, TriangulateErrc::kSelfIntersecting);
    EXPECT_EQ(e.loop, 0);
    EXPECT_EQ(e.other_loop, 0);
    // Two overlapping squares.
    e = expect_refused({square({0, 0}, 2), square({1, 1}, 2)}, TriangulateErrc::kSelfIntersecting);
    EXPECT_NE(e.loop, e.other_loop);
    // A hole touching its outer loop at a vertex.
    expect_refused({square({0, 0}, 4), {{0, 2}, {1, 1}, {2, 2}, {1, 3}}},
                   TriangulateErrc::kSelfIntersecting);
    // A repeated point, and a spike folding back along an edge.
    expect_refused({{{0, 0}, {1, 0}, {1, 0}, {1, 1}}}, TriangulateErrc::kSelfIntersecting);
    expect_refused({{{0, 0}, {2, 0}, {1, 0}, {1, 1}}}, TriangulateErrc::kSelfIntersecting);
}

TEST(Triangulate, FailureNamesReadAsText) {
    EXPECT_EQ(to_string(TriangulateErrc::kSelfIntersecting), "self_intersecting");
    EXPECT_EQ(to_string(TriangulateErrc::kZeroArea), "zero_area");
    EXPECT_EQ(triangulate_error(TriangulateErrc::kSelfIntersecting, 0, 3).message(),
              "loops 0 and 3: an edge of one crosses or touches an edge of the other "
              "(self_intersecting)");
    EXPECT_EQ(triangulate_error(TriangulateErrc::kZeroArea, 2).message(),
              "loop 2: encloses (relatively) zero area (zero_area)");
}

TEST(Triangulate, SignedAreaIsPositiveCounterClockwise) {
    EXPECT_DOUBLE_EQ(signed_area(square({1, 1}, 2)), 4.0);
    EXPECT_DOUBLE_EQ(signed_area(square({1, 1}, 2, false)), -4.0);
}

// ---- triangulate_strip: an annulus with every point kept ------------------------------------

/// triangulate_strip on `loops`: whether it stitched them, and every invariant when it did.
bool strip_valid(const Loops& loops, bool exact, std::size_t* triangles = nullptr) {
    Triangulator t;
    std::vector<Triangle> tris{{0, 1, 2}};
    const bool ok = t.triangulate_strip(spans_of(loops), tris);
    if (!ok) {
        EXPECT_TRUE(tris.empty());
        return false;
    }
    EXPECT_EQ(check_triangulation(loops, tris, exact), "");
    EXPECT_EQ(t.stats().strips, 1u);
    if (triangles != nullptr) *triangles = tris.size();
    return true;
}

/// A square of side `side` at `lo` with `per_side` points on each side (collinear runs).
std::vector<Point2> dense_square(Point2 lo, double side, int per_side, bool ccw = true) {
    std::vector<Point2> out;
    for (int e = 0; e < 4; ++e)
        for (int k = 0; k < per_side; ++k) {
            const double t = side * k / per_side;
            out.push_back(e == 0   ? lo + Point2(t, 0)
                          : e == 1 ? lo + Point2(side, t)
                          : e == 2 ? lo + Point2(side - t, side)
                                   : lo + Point2(0, side - t));
        }
    if (!ccw) std::reverse(out.begin(), out.end());
    return out;
}

TEST(TriangulateStrip, StitchesAnAnnulusWithCollinearRunsKeepingEveryPoint) {
    // Straight runs on both loops (a plane across flat quads): no ear, so no zero-area triangle.
    std::size_t n = 0;
    EXPECT_TRUE(strip_valid({dense_square({0, 0}, 40, 10), dense_square({10, 10}, 20, 5, false)},
                            true, &n));
    EXPECT_EQ(n, 60u);  // 40 + 20 points, one hole: every point kept, n + 2h - 2 triangles
    // Either loop first, either orientation, the hole off centre.
    EXPECT_TRUE(
        strip_valid({dense_square({3, 2}, 8, 2, true), dense_square({0, 0}, 40, 7, false)}, false));
    // A bone-like ring, in metres.
    EXPECT_TRUE(strip_valid({circle({0, 0}, 0.010, 400), circle({0.001, 0}, 0.004, 200)}, false));
}

TEST(TriangulateStrip, AnAnnulusNotStarShapedAboutItsHoleIsCheckedInFullAndStillStitched) {
    // A ring whose outer loop has a radial spike: that edge does not turn about the hole's
    // centre, so the loop is not star-shaped about it and gets the full crossing check; simple,
    // so it is stitched all the same.
    std::vector<Point2> spiked = circle({0, 0}, 10, 24);
    spiked.insert(spiked.begin() + 1, Point2(12, 0));
    std::size_t n = 0;
    EXPECT_TRUE(strip_valid({spiked, circle({0, 0}, 3, 12, false)}, false, &n));
    EXPECT_EQ(n, 37u);
    // The spike folded back across itself: a crossing (triangulate() refuses it), declined.
    spiked[1] = Point2(12, 1);
    spiked.insert(spiked.begin() + 2, {Point2(12, -1), Point2(9.5, 0.5)});
    const Loops crossed{spiked, circle({0, 0}, 3, 12, false)};
    expect_refused(crossed, TriangulateErrc::kSelfIntersecting);
    EXPECT_FALSE(strip_valid(crossed, false));
    // A loop whose outer edge folds round out of the hole's sight: simple, but no strip
    // triangle reaches round the fold (triangulate() ear-clips it).
    const Loops notched{{{0, 0},
                         {20, 0},
                         {20, 20},
                         {12, 20},
                         {12, 18},
                         {18, 18},
                         {18, 2},
                         {2, 2},
                         {2, 18},
                         {8, 18},
                         {8, 20},
                         {0, 20}},
                        square({9, 9}, 2, false)};
    std::vector<Triangle> tris;
    ASSERT_TRUE(Triangulator().triangulate(spans_of(notched), tris).has_value());
    EXPECT_FALSE(strip_valid(notched, true));
}

TEST(TriangulateStrip, DeclinesWhatIsNotOneCleanAnnulus) {
    // Not two loops; two loops side by side; a hole crossing its outer loop; a hole touching it
    // at a vertex and along an edge; an outer loop winding twice round the hole.
    EXPECT_FALSE(strip_valid({square({0, 0}, 4)}, true));
    EXPECT_FALSE(
        strip_valid({square({0, 0}, 4), square({1, 1}, 1, false), square({2, 2}, 1)}, true));
    EXPECT_FALSE(strip_valid({square({0, 0}, 4), square({10, 0}, 4, false)}, true));
    EXPECT_FALSE(strip_valid({square({0, 0}, 4), square({3, 1}, 2, false)}, true));
    EXPECT_FALSE(strip_valid({square({0, 0}, 4), {{0, 2}, {1, 3}, {2, 2}, {1, 1}}}, true));
    EXPECT_FALSE(strip_valid({square({0, 0}, 4), {{0, 1}, {0, 3}, {2, 3}, {2, 1}}}, true));
    std::vector<Point2> twice;
    for (int k = 0; k < 24; ++k) {
        const double a = 2.0 * M_PI * k / 12.0, r = 10.0 + 0.25 * k;
        twice.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    EXPECT_FALSE(strip_valid({twice, circle({0, 0}, 2, 12, false)}, false));
}

TEST(TriangulateStrip, AcceptsOnlyWhatTriangulateAcceptsOnSmallIntegerAnnuli) {
    // Differential: random pairs of small integer loops (exact predicates). Whatever the strip
    // stitches, triangulate must accept too (no crossing or touching slips through the star
    // test), and the strip's triangles keep every invariant exactly.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> coord(-6, 6), count(3, 9);
    int stitched = 0;
    for (int round = 0; round < 20000; ++round) {
        Loops loops(2);
        for (int l = 0; l < 2; ++l) {
            const double scale = l == 0 ? 2.0 : 1.0;  // the outer one larger, mostly
            const int n = count(rng);
            for (int k = 0; k < n; ++k) {
                // A star-ish loop round the origin with integer jitter, so many are annuli.
                const double a = 2.0 * M_PI * k / n;
                loops[l].emplace_back(std::round(scale * 5 * std::cos(a)) + coord(rng) / 3,
                                      std::round(scale * 5 * std::sin(a)) + coord(rng) / 3);
            }
        }
        Triangulator t;
        std::vector<Triangle> tris;
        const bool strip = t.triangulate_strip(spans_of(loops), tris);
        if (!strip) continue;
        ++stitched;
        std::vector<Triangle> general;
        ASSERT_TRUE(Triangulator().triangulate(spans_of(loops), general).has_value())
            << "round " << round;
        ASSERT_EQ(check_triangulation(loops, tris, true), "") << "round " << round;
    }
    EXPECT_GT(stitched, 1000);  // the test reaches the strip
}

}  // namespace
}  // namespace kerf::cut
