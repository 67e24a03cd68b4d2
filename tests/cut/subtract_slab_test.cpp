// Biplanar subtraction (paper §3.4): the kerf's slab is removed and both walls are capped.
#include "display/cut/subtract_slab.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include "display/mesh/shapes.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/test_shapes.hpp"

namespace kerf::cut {
namespace {

using namespace kerf::cut::testing;
using mesh::FaceHandle;

Vec3 centroid(const TriMesh& m, FaceHandle f) {
    Vec3 c(0, 0, 0);
    for (auto v : m.fv_range(f)) c += m.point(v);
    return c / 3.0;
}

// A seed on the outermost face crossing `plane` (largest distance from the z axis).
Seed outer_seed(const TriMesh& m, const Plane& plane) {
    FaceHandle best;
    double r = -1;
    for (auto f : m.faces()) {
        int pos = 0, neg = 0;
        for (auto v : m.fv_range(f)) {
            const double d = plane.signed_distance(m.point(v));
            pos += d > 0, neg += d < 0;
        }
        const Vec3 c = centroid(m, f);
        if (pos && neg && std::hypot(c[0], c[1]) > r) r = std::hypot(c[0], c[1]), best = f;
    }
    return Seed{centroid(m, best), best, -1.0};
}

// Volumes of the face-connected pieces whose vertices all lie within `band` of `plane`.
double volume_within(const TriMesh& m, const Plane& plane, double band) {
    std::vector<int> comp(m.n_faces(), -1);
    double total = 0;
    for (auto f : m.faces()) {
        if (comp[f.idx()] >= 0) continue;
        std::vector<FaceHandle> piece{f};
        comp[f.idx()] = 1;
        for (std::size_t i = 0; i < piece.size(); ++i)
            for (auto g : m.ff_range(piece[i]))
                if (comp[g.idx()] < 0) comp[g.idx()] = 1, piece.push_back(g);
        bool inside = true;
        double v = 0;
        for (FaceHandle g : piece) {
            auto it = m.cfv_iter(g);
            const auto a = m.point(*it++), b = m.point(*it++), c = m.point(*it);
            v += OpenMesh::dot(a, OpenMesh::cross(b, c)) / 6.0;
            for (auto p : {a, b, c}) inside &= std::abs(plane.signed_distance(p)) <= band;
        }
        if (inside) total += v;
    }
    return total;
}

TEST(SubtractSlab, RemovesExactlyTheKerfFromAHollowTubeAndCapsBothWalls) {
    auto m = mesh::make_hollow_tube(0.05, 0.01, 0.006, 48, 20);
    const double v0 = signed_volume(m);
    const Plane plane = *Plane::make(Vec3(0, 0, 0.0213), Vec3(0, 0, 1));
    CutContext ctx(m);
    SlabCut slab;
    const auto r = subtract_slab(ctx, plane, 0.001, outer_seed(m, plane), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 2u);
    // A prism: the slab's volume is the annulus polygon area times the kerf.
    const double ring =
        mesh::inscribed_polygon_area(0.01, 48) - mesh::inscribed_polygon_area(0.006, 48);
    EXPECT_NEAR(v0 - rep.total_volume_m3, ring * 0.001, 1e-9 * v0);
    EXPECT_EQ(slab.lower.loops_2d.size(), 2u);
    EXPECT_EQ(slab.upper.loops_2d.size(), 2u);
    EXPECT_GT(r.stats.triangles_removed, 0u);
    expect_face_normals_agree(m);
    for (auto f : slab.lower.negative.cap_faces) EXPECT_FALSE(m.status(f).deleted());
    for (auto f : slab.lower.positive.cap_faces) EXPECT_TRUE(m.status(f).deleted());
    for (auto f : slab.upper.positive.cap_faces) EXPECT_FALSE(m.status(f).deleted());
}

TEST(SubtractSlab, MatchesTwoUniplanarCutsOnATiltedSphere) {
    const TriMesh shape = mesh::make_uv_sphere(0.01, 4000);
    const Plane plane = *Plane::make(Vec3(0.001, 0, 0.0021), Vec3(0.2, 0.3, 1));
    const double kerf = 0.0008;
    TriMesh a = shape;
    CutContext actx(a);
    SlabCut slab;
    ASSERT_TRUE(subtract_slab(actx, plane, kerf, outer_seed(a, plane), slab).ok());
    const auto rep = expect_closed_2_manifold(a);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 2u);
    TriMesh b = shape;
    CutContext bctx(b);
    CrossSection cs;
    ASSERT_TRUE(slice_by_plane(bctx, plane.offset(-kerf / 2), cs).ok());
    ASSERT_TRUE(slice_by_plane(bctx, plane.offset(kerf / 2), cs).ok());
    const double slab_volume = volume_within(b, plane, kerf / 2 + 1e-9);
    EXPECT_GT(slab_volume, 0.0);
    EXPECT_NEAR(rep.total_volume_m3, signed_volume(shape) - slab_volume,
                1e-9 * signed_volume(shape));
}

// A seed on a face crossing `plane` whose centroid has the largest y.
Seed seed_at_largest_y(const TriMesh& m, const Plane& plane) {
    FaceHandle best;
    double y = -1e300;
    for (auto f : m.faces()) {
        int pos = 0, neg = 0;
        for (auto v : m.fv_range(f)) {
            const double d = plane.signed_distance(m.point(v));
            pos += d > 0, neg += d < 0;
        }
        if (pos && neg && centroid(m, f)[1] > y) y = centroid(m, f)[1], best = f;
    }
    return Seed{centroid(m, best), best, -1.0};
}

// Issue 10 item 1: a slab through the bridge of a U meets the lower plane in two loops. Both must
// be cut; before, only the seed's was, and the flood from the inner cap deleted the solid beyond
// the other loop (here: nearly the whole ring). The reference is independent: two full-plane
// slices and the pieces between them.
TEST(SubtractSlab, ASlabComponentWithTwoLoopsOnOneWallIsCutOnBoth) {
    const TriMesh shape = mesh::make_torus(0.01, 0.003, 96, 32);
    // x = 0.0068 misses the ring's inner equator (x = 0.007): two loops; x = 0.0078 crosses it:
    // one.
    const Plane plane = *Plane::make(Vec3(0.0073, 0, 0), Vec3(1, 0, 0));
    const double kerf = 0.001;
    TriMesh a = shape;
    CutContext actx(a);
    SlabCut slab;
    const auto r =
        subtract_slab(actx, plane, kerf, seed_at_largest_y(a, plane.offset(-kerf / 2)), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto rep = expect_closed_2_manifold(a);
    expect_face_normals_agree(a);
    EXPECT_EQ(slab.lower.loops_2d.size(), 2u);
    EXPECT_EQ(slab.upper.loops_2d.size(), 1u);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 2u);  // the ring beyond the upper wall, and the rest
    TriMesh b = shape;
    CutContext bctx(b);
    CrossSection cs;
    ASSERT_TRUE(slice_by_plane(bctx, plane.offset(-kerf / 2), cs).ok());
    ASSERT_TRUE(slice_by_plane(bctx, plane.offset(kerf / 2), cs).ok());
    const double slab_volume = volume_within(b, plane, kerf / 2 + 1e-9);
    const double v0 = signed_volume(shape);
    EXPECT_GT(slab_volume, 0.0);
    EXPECT_NEAR(v0 - rep.total_volume_m3, slab_volume, 1e-9 * v0);
}

TEST(SubtractSlab, ATipThinnerThanTheKerfIsRemovedWhole) {
    auto m = uv_sphere_by_rings(0.01, 16, 32);
    const double v0 = signed_volume(m);
    // Lower plane cuts near the north pole; the upper plane is above the sphere.
    const Plane plane = *Plane::make(Vec3(0, 0, 0.0098), Vec3(0, 0, 1));
    CutContext ctx(m);
    SlabCut slab;
    const auto r = subtract_slab(ctx, plane, 0.001, outer_seed(m, plane.offset(-0.0005)), slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto rep = expect_closed_2_manifold(m);
    EXPECT_EQ(rep.piece_volumes_m3.size(), 1u);
    EXPECT_LT(rep.total_volume_m3, v0);
    EXPECT_TRUE(slab.upper.loops_2d.empty());
}

TEST(SubtractSlab, BadKerfWidthIsRefusedAndTheMeshIsUnchanged) {
    auto m = uv_sphere_by_rings(0.01, 16, 32);
    const auto before = snapshot(m);
    CutContext ctx(m);
    SlabCut slab;
    const Plane plane = *Plane::make(Vec3(0, 0, 0), Vec3(0, 0, 1));
    for (double w : {0.0, -0.001, std::nan(""), 1e-15})
        EXPECT_EQ(subtract_slab(ctx, plane, w, outer_seed(m, plane), slab).status,
                  CutStatus::kInvalidArgument);
    EXPECT_EQ(
        subtract_slab(ctx, plane, 0.001, Seed{Vec3(1, 1, 1), FaceHandle(), -1.0}, slab).status,
        CutStatus::kSeedNotOnSurface);
    EXPECT_TRUE(snapshot(m) == before);
}

}  // namespace
}  // namespace kerf::cut
