// Localised slices (paper §3.7): only the seed's cross-section and the loops nested in it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/test_shapes.hpp"

namespace kerf::cut {
namespace {

using namespace kerf::cut::testing;
using mesh::FaceHandle;

Plane plane_of(Vec3 p, Vec3 n) { return *Plane::make(p, n); }

Vec3 centroid(const TriMesh& m, FaceHandle f) {
    Vec3 c(0, 0, 0);
    for (auto v : m.fv_range(f)) c += m.point(v);
    return c / 3.0;
}

// A face of `m` crossing `plane` with index in [first, last), or invalid.
FaceHandle crossing_face(const TriMesh& m, const Plane& plane, int first, int last) {
    for (int i = first; i < last; ++i) {
        int pos = 0, neg = 0;
        for (auto v : m.fv_range(FaceHandle(i))) {
            const double d = plane.signed_distance(m.point(v));
            pos += d > 1e-9, neg += d < -1e-9;
        }
        if (pos && neg) return FaceHandle(i);
    }
    return FaceHandle();
}

TEST(LocalisedSlice, CutsOnlyTheToeTheSeedIsOnAndLeavesTheOthersBitIdentical) {
    auto m = uv_sphere_by_rings(0.01, 16, 32, TriMesh::Point(0, 0, 0));
    const int per = static_cast<int>(m.n_faces());
    append(m, uv_sphere_by_rings(0.01, 16, 32, TriMesh::Point(0.03, 0, 0)));
    append(m, uv_sphere_by_rings(0.01, 16, 32, TriMesh::Point(0.06, 0, 0)));
    const Plane plane = plane_of(Vec3(0, 0, 0.00123), Vec3(0, 0.1, 1));
    const auto v0 = signed_volume(m);
    const auto left = snapshot(m, 0, per);
    const auto right = snapshot(m, 2 * per, 3 * per);
    const FaceHandle seed_face = crossing_face(m, plane, per, 2 * per);
    ASSERT_TRUE(seed_face.is_valid());
    CutContext ctx(m);
    CrossSection cs;
    const auto r = slice_by_plane(ctx, plane, Seed{centroid(m, seed_face), FaceHandle(), -1.0}, cs);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    EXPECT_EQ(r.stats.loops, 1u);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 4u);
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
    EXPECT_TRUE(snapshot(m, 0, per) == left);
    EXPECT_TRUE(snapshot(m, 2 * per, 3 * per) == right);
    expect_cross_section_consistent(m, cs, ctx.tolerance_m());
    expect_face_normals_agree(m);
}

TEST(LocalisedSlice, FindsTheCanalNestedInsideTheOuterLoop) {
    auto m = mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20);
    const Plane plane = plane_of(Vec3(0, 0, 0.0213), Vec3(0.1, -0.05, 1));
    const double v0 = signed_volume(m);
    // Seed: a crossing face on the outer wall (farthest from the axis).
    FaceHandle seed_face;
    double best = 0;
    for (auto f : m.faces()) {
        const Vec3 c = centroid(m, f);
        if (crossing_face(m, plane, f.idx(), f.idx() + 1).is_valid() &&
            std::hypot(c[0], c[1]) > best)
            best = std::hypot(c[0], c[1]), seed_face = f;
    }
    ASSERT_TRUE(seed_face.is_valid());
    CutContext ctx(m);
    CrossSection cs;
    const auto r = slice_by_plane(ctx, plane, Seed{centroid(m, seed_face), seed_face, -1.0}, cs);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    EXPECT_EQ(r.stats.loops, 2u);
    ASSERT_EQ(cs.loop_is_hole.size(), 2u);
    EXPECT_EQ(cs.loop_is_hole[0], 0);
    EXPECT_EQ(cs.loop_is_hole[1], 1);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 2u);
    EXPECT_NEAR(rep.total_volume_m3, v0, 1e-9 * v0);
    expect_cross_section_consistent(m, cs, ctx.tolerance_m());
}

// A seed on a hole (the canal wall here; on the bones, the inner loop of a concavity's section)
// touches the material between the hole and the outer loop around it: the cut takes that outer
// loop and everything nested in it, exactly as a seed on the outer wall does.
TEST(LocalisedSlice, ASeedOnTheCanalWallCutsTheRegionAroundTheCanal) {
    const auto shape = mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20);
    const Plane plane = plane_of(Vec3(0, 0, 0.0213), Vec3(0.1, -0.05, 1));
    FaceHandle canal_face, outer_face;
    for (auto f : shape.faces()) {
        if (!crossing_face(shape, plane, f.idx(), f.idx() + 1).is_valid()) continue;
        const Vec3 c = centroid(shape, f);
        (std::hypot(c[0], c[1]) < 0.007 ? canal_face : outer_face) = f;
    }
    ASSERT_TRUE(canal_face.is_valid() && outer_face.is_valid());
    auto cut_from = [&](FaceHandle f, FaceHandle hint) {
        TriMesh m = shape;
        CutContext ctx(m);
        CrossSection cs;
        const auto r = slice_by_plane(ctx, plane, Seed{centroid(shape, f), hint, -1.0}, cs);
        EXPECT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
        EXPECT_EQ(r.stats.loops, 2u);
        const auto rep = expect_closed_2_manifold(m);
        EXPECT_NEAR(rep.total_volume_m3, signed_volume(shape), 1e-9 * signed_volume(shape));
        expect_cross_section_consistent(m, cs, ctx.tolerance_m());
        expect_face_normals_agree(m);
        auto pieces = rep.piece_volumes_m3;
        std::sort(pieces.begin(), pieces.end());
        return pieces;
    };
    const auto from_outer = cut_from(outer_face, outer_face);
    ASSERT_EQ(from_outer.size(), 2u);
    const auto from_canal = cut_from(canal_face, canal_face);
    const auto from_canal_no_hint = cut_from(canal_face, FaceHandle());
    ASSERT_EQ(from_canal.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(from_canal[i], from_outer[i], 1e-12 * from_outer[i]);
        EXPECT_EQ(from_canal_no_hint[i], from_canal[i]);
    }
}

// Only a hole with no outer loop around it is refused: an inward-facing shell on its own.
TEST(LocalisedSlice, ASeedOnAHoleWithNothingAroundItIsRefusedAsAnInnerBoundary) {
    const auto sphere = uv_sphere_by_rings(0.01, 16, 32);
    TriMesh m;
    std::vector<mesh::VertexHandle> vs;
    for (auto v : sphere.vertices()) vs.push_back(m.add_vertex(sphere.point(v)));
    for (auto f : sphere.faces()) {
        std::vector<mesh::VertexHandle> c;
        for (auto v : sphere.fv_range(f)) c.push_back(vs[v.idx()]);
        m.add_face(c[2], c[1], c[0]);  // reversed: normals point inwards
    }
    const Plane plane = plane_of(Vec3(0, 0, 0.00123), Vec3(0, 0.1, 1));
    const FaceHandle seed_face = crossing_face(m, plane, 0, static_cast<int>(m.n_faces()));
    ASSERT_TRUE(seed_face.is_valid());
    const auto before = snapshot(m);
    CutContext ctx(m);
    CrossSection cs;
    EXPECT_EQ(slice_by_plane(ctx, plane, Seed{centroid(m, seed_face), seed_face, -1.0}, cs).status,
              CutStatus::kSeedOnInnerBoundary);
    EXPECT_TRUE(snapshot(m) == before);
}

TEST(LocalisedSlice, ASeedFarFromThePlaneIsRefused) {
    auto m = uv_sphere_by_rings(0.01, 16, 32);
    const auto before = snapshot(m);
    CutContext ctx(m);
    CrossSection cs;
    // Seed at the north pole region, plane near the south pole: not reachable near the plane.
    const Seed seed{centroid(m, FaceHandle(0)), FaceHandle(0), -1.0};
    const auto r = slice_by_plane(ctx, plane_of(Vec3(0, 0, -0.0099), Vec3(0, 0, 1)), seed, cs);
    EXPECT_TRUE(r.status == CutStatus::kOk || r.status == CutStatus::kSeedFarFromCut);
    const auto miss = slice_by_plane(ctx, plane_of(Vec3(0, 0, 0.5), Vec3(0, 0, 1)), seed, cs);
    EXPECT_EQ(miss.status, CutStatus::kSeedFarFromCut);
    if (r.status != CutStatus::kOk) {
        EXPECT_TRUE(snapshot(m) == before);
    }
}

// Shells (face-connected components) of a mesh, as a component id per face.
std::vector<int> shells(const TriMesh& m) {
    std::vector<int> comp(m.n_faces(), -1);
    int next = 0;
    std::vector<FaceHandle> stack;
    for (auto f : m.faces()) {
        if (comp[f.idx()] >= 0) continue;
        comp[f.idx()] = next;
        stack.push_back(f);
        while (!stack.empty()) {
            const FaceHandle g = stack.back();
            stack.pop_back();
            for (auto o : m.ff_range(g))
                if (comp[o.idx()] < 0) comp[o.idx()] = next, stack.push_back(o);
        }
        ++next;
    }
    return comp;
}

TEST(LocalisedSlice,
     ForefootPlaneAt100mmCutsExactlyTheSeedsRayAndLeavesTheOtherShellsBitIdentical) {
    auto loaded = testing::load_shared_mesh("bp3d_right_forefoot_24shells.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    const Plane plane = plane_of(Vec3(0, 0, 0.100), Vec3(0, 0, 1));
    const std::vector<int> comp = shells(m);
    const int n0 = static_cast<int>(m.n_faces());
    // Which shells the plane crosses: expect one bone of each of the five rays.
    std::vector<int> crossed;
    for (int i = 0; i < n0; ++i)
        if (crossing_face(m, plane, i, i + 1).is_valid() &&
            std::find(crossed.begin(), crossed.end(), comp[i]) == crossed.end())
            crossed.push_back(comp[i]);
    ASSERT_EQ(crossed.size(), 5u);
    const TriMesh original = std::move(m);
    std::vector<double> before(static_cast<std::size_t>(n0) * 9);
    for (int i = 0; i < n0; ++i) {
        int k = 0;
        for (auto v : original.fv_range(FaceHandle(i)))
            for (int a = 0; a < 3; ++a) before[i * 9 + k++] = original.point(v)[a];
    }
    const double v0 = signed_volume(original);
    // A seed on each ray in turn: the cut takes that ray only.
    for (const int seed_shell : crossed) {
        SCOPED_TRACE("seed on shell " + std::to_string(seed_shell));
        FaceHandle seed_face;
        for (int i = 0; i < n0 && !seed_face.is_valid(); ++i)
            if (comp[i] == seed_shell && crossing_face(original, plane, i, i + 1).is_valid())
                seed_face = FaceHandle(i);
        TriMesh cut = original;
        CutContext ctx(cut);
        CrossSection cs;
        const auto r =
            slice_by_plane(ctx, plane, Seed{centroid(cut, seed_face), seed_face, -1.0}, cs);
        ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
        // The file's shell 0 is not a clean manifold (merged bones), so the strict check runs on
        // the ray that was cut: its original faces plus every face the cut made.
        TriMesh ray = extract_faces(
            cut, [&](FaceHandle f) { return f.idx() >= n0 || comp[f.idx()] == seed_shell; });
        TriMesh ray_before =
            extract_faces(original, [&](FaceHandle f) { return comp[f.idx()] == seed_shell; });
        const auto rep = expect_closed_2_manifold(ray);
        EXPECT_EQ(rep.piece_volumes_m3.size(), 2u);
        EXPECT_NEAR(rep.total_volume_m3, signed_volume(ray_before),
                    1e-9 * signed_volume(ray_before));
        EXPECT_NEAR(signed_volume(cut), v0, 1e-9 * v0);
        expect_cross_section_consistent(cut, cs, ctx.tolerance_m());
        int changed_other = 0, changed_seed_shell = 0;
        for (int i = 0; i < n0; ++i) {
            int k = 0;
            bool same = true;
            for (auto v : cut.fv_range(FaceHandle(i)))
                for (int a = 0; a < 3; ++a) same &= before[i * 9 + k++] == cut.point(v)[a];
            (comp[i] == seed_shell ? changed_seed_shell : changed_other) += !same;
        }
        EXPECT_EQ(changed_other, 0);
        EXPECT_GT(changed_seed_shell, 0);
    }
}

}  // namespace
}  // namespace kerf::cut
