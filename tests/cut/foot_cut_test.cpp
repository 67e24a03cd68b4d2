// Cuts on the built-in synthetic forefoot (display/mesh/foot_generator.hpp): 19 bones, each an
// outer cortical shell with a separate medullary canal shell.
#include <gtest/gtest.h>

#include <random>

#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "display/mesh/foot_generator.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/slice_sweep.hpp"

namespace kerf::cut {
namespace {

using namespace kerf::cut::testing;
using mesh::FaceHandle;
using mesh::TriMesh;

const mesh::Foot& foot() {
    static const mesh::Foot f = *mesh::generate_foot(mesh::FootParams{20'000, 1});
    return f;
}

// A plane across a bone's axis at `fraction` of its length, tilted by `tilt` towards +x.
Plane across(const mesh::BoneInfo& b, double fraction, Vec3 tilt = Vec3(0, 0, 0)) {
    const Vec3 axis = (b.head_m - b.base_m) / b.length_m;
    return *Plane::make(b.base_m + (b.head_m - b.base_m) * fraction, axis + tilt);
}

// The crossing face of bone `b` farthest from its axis (on the outer shell).
Seed outer_seed(const TriMesh& m, const mesh::BoneInfo& b, const Plane& plane) {
    const Vec3 axis = (b.head_m - b.base_m) / b.length_m;
    FaceHandle best;
    double far = -1;
    for (std::size_t i = b.first_triangle; i < b.first_triangle + b.triangle_count; ++i) {
        const FaceHandle f(static_cast<int>(i));
        int pos = 0, neg = 0;
        for (auto v : m.fv_range(f)) {
            const double d = plane.signed_distance(m.point(v));
            pos += d > 0, neg += d < 0;
        }
        const Vec3 c = face_centroid(m, f) - b.base_m;
        const double r = (c - axis * OpenMesh::dot(c, axis)).norm();
        if (pos && neg && r > far) far = r, best = f;
    }
    return Seed{face_centroid(m, best), best, -1.0};
}

bool outside_bone_unchanged(const TriMesh& before, const TriMesh& after, const mesh::BoneInfo& b) {
    const int lo = static_cast<int>(b.first_triangle),
              hi = static_cast<int>(b.first_triangle + b.triangle_count);
    const int n = static_cast<int>(before.n_faces());
    return snapshot(before, 0, lo) == snapshot(after, 0, lo) &&
           snapshot(before, hi, n) == snapshot(after, hi, n);
}

TEST(FootCut, LocalisedCutAcrossTheFirstMetatarsalShaftCutsCortexAndCanalOnly) {
    TriMesh m = foot().mesh;
    const auto& mt1 = foot().first_metatarsal();
    const Plane plane = across(mt1, 0.5, Vec3(0.1, 0.05, 0));
    const double v0 = signed_volume(m);
    CutContext ctx(m);
    CrossSection cs;
    const auto r = slice_by_plane(ctx, plane, outer_seed(m, mt1, plane), cs);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    EXPECT_EQ(r.stats.loops, 2u);  // the cortex and the canal: an annulus
    ASSERT_EQ(cs.loop_is_hole.size(), 2u);
    EXPECT_EQ(cs.loop_is_hole[0] + cs.loop_is_hole[1], 1);
    const auto rep = expect_closed_2_manifold(m);
    // The bone's two shells (cortex, canal) become two pieces, each joined by its annular cap.
    EXPECT_EQ(rep.piece_volumes_m3.size(), 38u);
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
    expect_face_normals_agree(m);
    expect_cross_section_consistent(m, cs, ctx.tolerance_m());
    EXPECT_TRUE(outside_bone_unchanged(foot().mesh, m, mt1));
}

TEST(FootCut, ChevronOsteotomyOfTheFirstMetatarsalCutsThroughTheFirstCap) {
    TriMesh m = foot().mesh;
    const auto& mt1 = foot().first_metatarsal();
    const double v0 = signed_volume(m);
    CutContext ctx(m);
    CrossSection cs;
    // Two planes meeting at an apex on the axis, 60 degrees apart (a distal chevron).
    const Plane a = across(mt1, 0.6, Vec3(0.0, 0.6, 0));
    const Plane b = across(mt1, 0.6, Vec3(0.0, -0.6, 0));
    ASSERT_TRUE(slice_by_plane(ctx, a, outer_seed(m, mt1, a), cs).ok());
    const auto r = slice_by_plane(ctx, b, outer_seed(m, mt1, b), cs);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 39u);  // proximal, wedge, distal
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
    expect_face_normals_agree(m);
    EXPECT_TRUE(outside_bone_unchanged(foot().mesh, m, mt1));
}

TEST(FootCut, RandomLocalisedCutsOnRandomBonesStayClosedAndLocal) {
    std::mt19937_64 rng(314);
    int cut = 0;
    for (int i = 0; i < 12; ++i) {
        const auto& bone =
            foot()
                .bones[std::uniform_int_distribution<std::size_t>(0, foot().bones.size() - 1)(rng)];
        const Plane plane = across(bone, std::uniform_real_distribution<double>(0.2, 0.8)(rng),
                                   random_unit(rng) * 0.4);
        TriMesh m = foot().mesh;
        const double v0 = signed_volume(m);
        CutContext ctx(m);
        CrossSection cs;
        const auto r = slice_by_plane(ctx, plane, outer_seed(m, bone, plane), cs);
        ASSERT_TRUE(r.ok() || r.status == CutStatus::kCapTriangulationFailed)
            << to_string(r.status);
        if (!r.ok()) continue;
        ++cut;
        const auto rep = expect_closed_2_manifold(m);
        EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
        expect_cross_section_consistent(m, cs, ctx.tolerance_m());
        EXPECT_TRUE(outside_bone_unchanged(foot().mesh, m, bone));
    }
    EXPECT_GE(cut, 11);
}

TEST(FootCut, SlabThroughTheFirstMetatarsalLeavesTwoWallsAndTheOtherBones) {
    TriMesh m = foot().mesh;
    const auto& mt1 = foot().first_metatarsal();
    const Plane plane = across(mt1, 0.45);
    CutContext ctx(m);
    SlabCut slab;
    const auto r =
        subtract_slab(ctx, plane, 0.001, outer_seed(m, mt1, plane.offset(-0.0005)), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 38u);  // two walls; the slab between is gone
    EXPECT_LT(rep.total_volume_m3, signed_volume(foot().mesh));
    EXPECT_EQ(slab.lower.loops_2d.size(), 2u);
    EXPECT_EQ(slab.upper.loops_2d.size(), 2u);
}

}  // namespace
}  // namespace kerf::cut
