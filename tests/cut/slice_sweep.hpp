// Random-plane sweeps shared by the property tests (unit) and the stress tests (real meshes).
#pragma once

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "display/cut/slice_by_plane.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut::testing {

struct SweepCounts {
    int cut = 0;           ///< cuts that succeeded (and passed the checks)
    int refused = 0;       ///< plane misses / seed far: mesh verified unchanged
    int failed = 0;        ///< anything else (or a check failed)
    int cap_refusals = 0;  ///< kCapTriangulationFailed: a cap would need a sliver; mesh unchanged
    int sliver_refusals = 0;  ///< kSliverSplit: a split would leave a sliver no snap removes
};

/// Refusals the library may give on valid input (mesh verified unchanged). A cap refusal is
/// counted separately: rare, and the sweeps assert it stays rare. A sliver split (a plane just
/// beyond tol from a vertex of a thin triangle an earlier cut left) is a refusal too: with the one
/// degenerate threshold (mesh::kDegenerateTwiceAreaRelative) it happens in a few per cent of
/// sequences of random cuts through earlier caps; the property test counts it.
inline bool is_refusal(CutStatus s) {
    return s == CutStatus::kPlaneMissesMesh || s == CutStatus::kSeedFarFromCut ||
           s == CutStatus::kSeedOnInnerBoundary || s == CutStatus::kCapTriangulationFailed ||
           s == CutStatus::kSliverSplit;
}

/// Which coordinate of a random direction is drawn first. kZyx is the order gcc gave the old
/// Vec3(g(rng), g(rng), g(rng)) (argument order is unspecified; clang drew x first), so the planes
/// the property tests have always cut stay the same in every build; kXyz is clang's old order, a
/// second family of planes (the stress sweep runs both).
enum class DrawOrder { kZyx, kXyz };

inline const char* to_string(DrawOrder o) { return o == DrawOrder::kZyx ? "zyx" : "xyz"; }

inline Vec3 random_unit(std::mt19937_64& rng, DrawOrder order = DrawOrder::kZyx) {
    std::normal_distribution<double> g;
    // One draw per statement: the same seed gives the same direction in every build.
    const double first = g(rng), second = g(rng), third = g(rng);
    Vec3 v = order == DrawOrder::kZyx ? Vec3(third, second, first) : Vec3(first, second, third);
    return v / v.norm();
}

inline Vec3 face_centroid(const kerf::mesh::TriMesh& m, kerf::mesh::FaceHandle f) {
    Vec3 c(0, 0, 0);
    for (auto v : m.fv_range(f)) c += m.point(v);
    return c / 3.0;
}

/// A random plane through a random point of the bounding box (shrunk by 20 %).
inline Plane random_plane(const kerf::mesh::TriMesh& m, std::mt19937_64& rng,
                          DrawOrder order = DrawOrder::kZyx) {
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (auto v : m.vertices()) lo.minimize(m.point(v)), hi.maximize(m.point(v));
    std::uniform_real_distribution<double> u(0.1, 0.9);
    Vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * u(rng);
    return *Plane::make(p, random_unit(rng, order));
}

/// A seed: the centroid of a random face crossing `plane`, or invalid when none crosses.
inline Seed random_seed(const kerf::mesh::TriMesh& m, const Plane& plane, std::mt19937_64& rng) {
    std::vector<kerf::mesh::FaceHandle> crossing;
    for (auto f : m.faces()) {
        int pos = 0, neg = 0;
        for (auto v : m.fv_range(f)) {
            const double d = plane.signed_distance(m.point(v));
            pos += d > 0, neg += d < 0;
        }
        if (pos && neg) crossing.push_back(f);
    }
    if (crossing.empty()) return Seed{Vec3(0, 0, 0), kerf::mesh::FaceHandle(), 0.0};
    const auto f =
        crossing[std::uniform_int_distribution<std::size_t>(0, crossing.size() - 1)(rng)];
    return Seed{face_centroid(m, f),
                std::uniform_int_distribution<int>(0, 1)(rng) ? f : kerf::mesh::FaceHandle(), -1.0};
}

/// One cut on a fresh copy of `shape`, checked; adds to `c`.
inline void checked_cut(const kerf::mesh::TriMesh& shape, const Plane& plane, const Seed* seed,
                        SweepCounts& c) {
    kerf::mesh::TriMesh m = shape;
    const double v0 = signed_volume(m);
    const auto before = snapshot(m);
    CutContext ctx(m);
    CrossSection cs;
    const CutResult r =
        seed ? slice_by_plane(ctx, plane, *seed, cs) : slice_by_plane(ctx, plane, cs);
    if (is_refusal(r.status)) {
        ++c.refused;
        c.cap_refusals += r.status == CutStatus::kCapTriangulationFailed;
        c.sliver_refusals += r.status == CutStatus::kSliverSplit;
        if (!(snapshot(m) == before)) ++c.failed, ADD_FAILURE() << "refusal changed the mesh";
        return;
    }
    if (!r.ok()) {
        ++c.failed;
        ADD_FAILURE() << "cut failed: " << to_string(r.status);
        return;
    }
    const int failures_before =
        ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count();
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * std::abs(v0));
    expect_face_normals_agree(m);
    expect_cross_section_consistent(m, cs, ctx.tolerance_m(), r.stats.vertices_snapped);
    const int failures_after =
        ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count();
    (failures_after == failures_before ? c.cut : c.failed) += 1;
}

/// `n` random planes on copies of `shape`, full-plane or localised from random seeds.
inline SweepCounts sweep_random_planes(const kerf::mesh::TriMesh& shape, std::mt19937_64& rng,
                                       int n, bool localised) {
    SweepCounts c;
    for (int i = 0; i < n; ++i) {
        const Plane plane = random_plane(shape, rng);
        if (!localised) {
            checked_cut(shape, plane, nullptr, c);
            continue;
        }
        const Seed seed = random_seed(shape, plane, rng);
        if (seed.tolerance_m == 0.0) continue;
        checked_cut(shape, plane, &seed, c);
    }
    return c;
}

/// `n` successive random cuts on ONE copy (crossing earlier caps), checked after each.
inline SweepCounts sweep_sequence(const kerf::mesh::TriMesh& shape, std::mt19937_64& rng, int n) {
    SweepCounts c;
    kerf::mesh::TriMesh m = shape;
    const double v0 = signed_volume(m);
    CutContext ctx(m);
    CrossSection cs;
    for (int i = 0; i < n; ++i) {
        const Plane plane = random_plane(m, rng);
        const bool localised = i % 2 == 1;
        const Seed seed = random_seed(m, plane, rng);
        if (localised && seed.tolerance_m == 0.0) continue;
        const auto before = snapshot(m);
        const CutResult r =
            localised ? slice_by_plane(ctx, plane, seed, cs) : slice_by_plane(ctx, plane, cs);
        if (!r.ok()) {
            const bool refusal = is_refusal(r.status);
            c.cap_refusals += r.status == CutStatus::kCapTriangulationFailed;
            c.sliver_refusals += r.status == CutStatus::kSliverSplit;
            if (!refusal) ADD_FAILURE() << "cut " << i << " failed: " << to_string(r.status);
            if (!(snapshot(m) == before)) ADD_FAILURE() << "refusal changed the mesh";
            (refusal ? c.refused : c.failed) += 1;
            continue;
        }
        ++c.cut;
        const auto rep = expect_closed_2_manifold(m);
        EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * std::abs(v0)) << "after cut " << i;
        expect_face_normals_agree(m);
        expect_cross_section_consistent(m, cs, ctx.tolerance_m(), r.stats.vertices_snapped);
        if (!rep.ok) ++c.failed;
    }
    return c;
}

}  // namespace kerf::cut::testing
