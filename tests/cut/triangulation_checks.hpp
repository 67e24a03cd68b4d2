// Independent checks of a cap triangulation and a generator of valid multi-loop regions, shared by
// triangulate_test.cpp and the fuzz target (no gtest here: a violation is returned as text).
//
//   std::string why = check_triangulation(loops, triangles, /*exact=*/true);
//   EXPECT_EQ(why, "");
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "display/cut/triangulate.hpp"

namespace kerf::cut::testing {

using Loops = std::vector<std::vector<Point2>>;

/// Spans over each loop, as triangulate() takes them.
inline std::vector<std::span<const Point2>> spans_of(const Loops& loops) {
    std::vector<std::span<const Point2>> s;
    for (const auto& l : loops) s.emplace_back(l);
    return s;
}

/// Nesting depth of each loop by brute force (crossing number of each loop's first point).
inline std::vector<int> brute_depths(const Loops& loops) {
    std::vector<int> depth(loops.size(), 0);
    for (std::size_t i = 0; i < loops.size(); ++i) {
        const Point2 p = loops[i][0];
        for (std::size_t j = 0; j < loops.size(); ++j) {
            if (i == j) continue;
            bool in = false;
            const auto& l = loops[j];
            for (std::size_t k = 0; k < l.size(); ++k) {
                const Point2 a = l[k];
                const Point2 b = l[(k + 1) % l.size()];
                if ((a[1] > p[1]) != (b[1] > p[1]) &&
                    p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) {
                    in = !in;
                }
            }
            depth[i] += in ? 1 : 0;
        }
    }
    return depth;
}

/// Area of the region: outer loops (even depth) minus holes (odd depth).
inline double region_area(const Loops& loops) {
    const auto depth = brute_depths(loops);
    double a = 0.0;
    for (std::size_t i = 0; i < loops.size(); ++i) {
        const double s = std::abs(signed_area(loops[i]));
        a += depth[i] % 2 == 0 ? s : -s;
    }
    return a;
}

/// Empty when `tris` triangulates `loops`: indices in range; every triangle counter-clockwise
/// (zero area allowed only when `allow_degenerate`); each loop edge used once with the material on
/// its left and never reversed; every other directed edge matched by its reverse exactly once;
/// triangle count = points + 2 holes - 2 outer loops; area sum = region area (1e-12 relative, or
/// exactly when `exact`, for small integer coordinates).
inline std::string check_triangulation(const Loops& loops, const std::vector<Triangle>& tris,
                                       bool exact, bool allow_degenerate = false) {
    std::vector<Point2> pts;
    std::vector<std::uint32_t> begin;
    for (const auto& l : loops) {
        begin.push_back(static_cast<std::uint32_t>(pts.size()));
        pts.insert(pts.end(), l.begin(), l.end());
    }
    const auto depth = brute_depths(loops);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    double sum = 0.0;
    for (const Triangle& t : tris) {
        const std::uint32_t idx[3] = {t.a, t.b, t.c};
        for (auto i : idx) {
            if (i >= pts.size()) return "index out of range: " + std::to_string(i);
        }
        const Point2 ab = pts[t.b] - pts[t.a];
        const Point2 ac = pts[t.c] - pts[t.a];
        const double twice = ab[0] * ac[1] - ab[1] * ac[0];
        if (twice < 0 || (twice == 0 && !allow_degenerate)) {
            return "triangle not counter-clockwise: " + std::to_string(t.a) + "," +
                   std::to_string(t.b) + "," + std::to_string(t.c) + " area2 " +
                   std::to_string(twice);
        }
        sum += 0.5 * twice;
        for (int k = 0; k < 3; ++k) ++directed[{idx[k], idx[(k + 1) % 3]}];
    }
    int holes = 0;
    for (std::size_t l = 0; l < loops.size(); ++l) {
        const bool outer = depth[l] % 2 == 0;
        holes += outer ? 0 : 1;
        const bool forward = (signed_area(loops[l]) > 0) == outer;  // material on the left
        const auto n = static_cast<std::uint32_t>(loops[l].size());
        for (std::uint32_t k = 0; k < n; ++k) {
            std::uint32_t u = begin[l] + k;
            std::uint32_t v = begin[l] + (k + 1) % n;
            if (!forward) std::swap(u, v);
            if (directed[{u, v}] != 1 || directed.count({v, u}) != 0) {
                return "loop edge " + std::to_string(u) + "->" + std::to_string(v) + " of loop " +
                       std::to_string(l) + " not used exactly once";
            }
            directed.erase({u, v});
        }
    }
    for (const auto& [e, count] : directed) {
        const auto it = directed.find({e.second, e.first});
        if (count != 1 || it == directed.end() || it->second != 1) {
            return "interior edge " + std::to_string(e.first) + "->" + std::to_string(e.second) +
                   " not matched by its reverse";
        }
    }
    const auto outer_loops = static_cast<int>(loops.size()) - holes;
    const auto expected = static_cast<long>(pts.size()) + 2L * holes - 2L * outer_loops;
    if (static_cast<long>(tris.size()) != expected) {
        return "triangle count " + std::to_string(tris.size()) + " != " + std::to_string(expected);
    }
    const double want = region_area(loops);
    const double tol = exact ? 0.0 : 1e-12 * std::abs(want);
    if (std::abs(sum - want) > tol) {
        return "area " + std::to_string(sum) + " != " + std::to_string(want);
    }
    return "";
}

/// A star-shaped loop around `c`: `n` angles evenly spaced with jitter (< 0.4 spacing), radii in
/// [r_min, r_max], rounded to integers when `integer` (exact predicates), clockwise when `cw`.
template <class Rng>
std::vector<Point2> star_loop(Rng& rng, Point2 c, double r_min, double r_max, int n, bool cw,
                              bool integer) {
    std::uniform_real_distribution<double> jitter(-0.4, 0.4);
    std::uniform_real_distribution<double> radius(r_min, r_max);
    std::vector<Point2> loop;
    const double step = 2.0 * M_PI / n;
    for (int k = 0; k < n; ++k) {
        const double ang = (k + jitter(rng)) * step * (cw ? -1.0 : 1.0);
        const double r = radius(rng);
        Point2 p(c[0] + r * std::cos(ang), c[1] + r * std::sin(ang));
        if (integer) p = Point2(std::round(p[0]), std::round(p[1]));
        loop.push_back(p);
    }
    return loop;
}

/// A valid region: a star outer loop (radius ~2^20) holding up to 3x3 star holes, some with an
/// island inside; orientations random. Integer coordinates keep every predicate exact.
template <class Rng>
Loops random_region(Rng& rng, int max_points_per_loop, bool integer = true) {
    const double r = 1 << 20;
    std::uniform_int_distribution<int> count(6, std::max(6, max_points_per_loop));
    std::bernoulli_distribution coin(0.5);
    // Every draw is its own statement: the order of a call's arguments is unspecified, and the
    // same seed must give the same region in every build (gcc -O2 and the sanitizer builds).
    const auto loop = [&](Point2 c, double r0, double r1) {
        const bool clockwise = coin(rng);  // before the count: the order gcc gave the old call
        const int n = count(rng);
        return star_loop(rng, c, r0, r1, n, clockwise, integer);
    };
    Loops loops;
    loops.push_back(loop(Point2(0, 0), r / 2, r));
    const double cell = r / 4 * std::sqrt(2.0) / 3;  // 3x3 cells inside the disc of radius r/4
    for (int gx = 0; gx < 3; ++gx) {
        for (int gy = 0; gy < 3; ++gy) {
            if (!coin(rng)) continue;
            const Point2 c(-1.5 * cell + (gx + 0.5) * cell, -1.5 * cell + (gy + 0.5) * cell);
            const double hr = cell * 0.45;
            loops.push_back(loop(c, hr / 2, hr));
            if (coin(rng)) loops.push_back(loop(c, hr / 8, hr / 4));
        }
    }
    std::shuffle(loops.begin(), loops.end(), rng);
    return loops;
}

}  // namespace kerf::cut::testing
