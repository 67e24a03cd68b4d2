// Gradual separation: the kerf opens where the blade swept, never folds or flips a triangle, is
// exactly a kerf wide when complete, and matches the biplanar subtraction.
#include "display/cut/separate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "display/cut/components.hpp"
#include "display/cut/mesh_hash.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/self_intersection.hpp"
#include "tests/cut/test_shapes.hpp"

namespace kerf::cut {
namespace {

using mesh::TriMesh;

constexpr double kKerf = 1.0e-3;  // a 1 mm blade

/// Face normals before separation, to detect flips (index = face index).
std::vector<Vec3> normals_of(const TriMesh& m) {
    std::vector<Vec3> n(m.n_faces());
    for (const auto f : m.faces()) n[static_cast<std::size_t>(f.idx())] = m.calc_face_normal(f);
    return n;
}

/// Every live face still faces the way it did and keeps a non-degenerate area.
void expect_no_flip(const TriMesh& m, const std::vector<Vec3>& before) {
    int flipped = 0;
    double min_area = 1e300;
    for (const auto f : m.faces()) {
        auto it = m.cfv_iter(f);
        const auto a = m.point(*it++);
        const auto b = m.point(*it++);
        const auto c = m.point(*it);
        const Vec3 n = OpenMesh::cross(b - a, c - a);
        min_area = std::min(min_area, 0.5 * n.norm());
        if (OpenMesh::dot(n, before[static_cast<std::size_t>(f.idx())]) <= 0) ++flipped;
    }
    EXPECT_EQ(flipped, 0);
    EXPECT_GT(min_area, 1e-15 * std::pow(testing::used_bbox_diagonal(m), 2));
}

struct CutTube {
    TriMesh mesh = mesh::make_hollow_tube(0.05, 0.006, 0.003, 64, 60);
    CrossSection cs;
};

/// A tube of length 50 mm cut across at z = 20 mm (a plane through no vertex ring).
void cut_tube(CutTube& t, CutContext& ctx) {
    const auto plane = *Plane::make(Vec3(0, 0, 0.0201), Vec3(0, 0, 1));
    const auto r = slice_by_plane(ctx, plane, t.cs);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
}

/// The blade's footprint: the half-plane u < x_m (as a large rectangle).
std::vector<Vec2> swept_up_to(double x_m) {
    return {Vec2(-1, -1), Vec2(x_m, -1), Vec2(x_m, 1), Vec2(-1, 1)};
}

double rim_gap(const TriMesh& m, const CrossSection& cs, std::size_t loop, std::size_t j) {
    return OpenMesh::dot(m.point(cs.positive.loops[loop][j]) - m.point(cs.negative.loops[loop][j]),
                         cs.plane.normal());
}

TEST(Separate, SweptRimPairsOpenByTheKerfAndTheRestStayShut) {
    CutTube t;
    CutContext ctx(t.mesh);
    cut_tube(t, ctx);
    const auto before = normals_of(t.mesh);
    auto sep = Separator::make(ctx, t.cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    ASSERT_TRUE(sep->sweep(swept_up_to(-0.002)));  // the blade has come in from -u to u = -2 mm
    for (std::size_t l = 0; l < t.cs.positive.loops.size(); ++l) {
        for (std::size_t j = 0; j < t.cs.positive.loops[l].size(); ++j) {
            const double u = t.cs.loops_2d[l][j][0];
            const double gap = rim_gap(t.mesh, t.cs, l, j);
            if (u <= -0.002) {
                EXPECT_NEAR(gap, kKerf, 1e-15);
            } else if (u >= -0.002 + kKerf) {
                EXPECT_EQ(gap, 0.0);
            }
            EXPECT_GE(gap, 0.0);
        }
    }
    testing::expect_closed_2_manifold(t.mesh);
    expect_no_flip(t.mesh, before);
    EXPECT_GT(sep->stats().rim_pairs_swept, 0u);
    EXPECT_LT(sep->stats().rim_pairs_swept, sep->stats().rim_pairs);
}

TEST(Separate, ABladeAdvancingStepByStepNeverFlipsOrFlattensATriangle) {
    CutTube t;
    CutContext ctx(t.mesh);
    cut_tube(t, ctx);
    const auto before = normals_of(t.mesh);
    auto sep = Separator::make(ctx, t.cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    for (double x = -0.007; x <= 0.007; x += 0.0002) {  // 0.2 mm per progress event
        // The footprint at this event: a 10 mm deep blade, its front edge at u = x.
        const std::vector<Vec2> blade{Vec2(x - 0.01, -0.0015), Vec2(x, -0.0015), Vec2(x, 0.0015),
                                      Vec2(x - 0.01, 0.0015)};
        ASSERT_TRUE(sep->sweep(blade));
        EXPECT_LT(sep->stats().moved_last_sweep, sep->stats().band_vertices / 4);
        EXPECT_EQ(sep->moved_vertices().size(), sep->stats().moved_last_sweep);
    }
    testing::expect_closed_2_manifold(t.mesh);
    expect_no_flip(t.mesh, before);
}

TEST(Separate, FullySweptTheGapIsExactlyTheKerfAndNoVertexIsLeftInIt) {
    CutTube t;
    CutContext ctx(t.mesh);
    cut_tube(t, ctx);
    const auto before = normals_of(t.mesh);
    auto sep = Separator::make(ctx, t.cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    sep->sweep_all();
    EXPECT_EQ(sep->stats().rim_pairs_swept, sep->stats().rim_pairs);
    for (const auto v : t.mesh.vertices()) {
        const double d = t.cs.plane.signed_distance(t.mesh.point(v));
        EXPECT_GE(std::abs(d), 0.5 * kKerf - 1e-12) << "vertex " << v.idx() << " inside the kerf";
    }
    for (std::size_t j = 0; j < t.cs.positive.loops[0].size(); ++j) {
        EXPECT_NEAR(rim_gap(t.mesh, t.cs, 0, j), kKerf, 1e-15);
    }
    testing::expect_closed_2_manifold(t.mesh);
    expect_no_flip(t.mesh, before);
}

TEST(Separate, CompleteSeparationMatchesTheBiplanarSubtraction) {
    // Walls at right angles to the plane (a tube): the same pieces as subtract_slab, to rounding.
    CutTube a;
    CutTube b;
    const auto plane = *Plane::make(Vec3(0, 0, 0.0201), Vec3(0, 0, 1));
    CutContext ctx_a(a.mesh);
    cut_tube(a, ctx_a);
    auto sep = Separator::make(ctx_a, a.cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    sep->sweep_all();
    CutContext ctx_b(b.mesh);
    SlabCut slab;
    const auto r = subtract_slab(ctx_b, plane, kKerf,
                                 Seed{Vec3(0.006, 0, 0.0201), mesh::FaceHandle(), -1.0}, slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const auto pa = find_components(a.mesh);
    const auto pb = find_components(b.mesh);
    ASSERT_EQ(pa.size(), 2u);
    ASSERT_EQ(pb.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(pa[i].volume_m3, pb[i].volume_m3, 1e-9 * pb[i].volume_m3);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(pa[i].bbox_min_m[k], pb[i].bbox_min_m[k], 1e-12);
            EXPECT_NEAR(pa[i].bbox_max_m[k], pb[i].bbox_max_m[k], 1e-12);
        }
    }
}

TEST(Separate, SlantedWallsStayCloseToTheBiplanarVolume) {
    // A sphere cut off-centre: walls meet the plane at an angle, the shifted band differs from
    // the slab by at most slope * kerf / 2 across the rim; volumes agree to a small fraction.
    TriMesh a = mesh::make_uv_sphere(0.01, 20000);
    TriMesh b = a;
    const auto plane = *Plane::make(Vec3(0, 0, 0.004), Vec3(0, 0.1, 1));
    CutContext ctx_a(a);
    CrossSection cs;
    ASSERT_TRUE(slice_by_plane(ctx_a, plane, cs).ok());
    const auto before = normals_of(a);
    auto sep = Separator::make(ctx_a, cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    sep->sweep_all();
    expect_no_flip(a, before);
    CutContext ctx_b(b);
    SlabCut slab;
    const double x0 = std::sqrt(0.01 * 0.01 - 0.004 * 0.004) * 0.999;
    const auto r = subtract_slab(ctx_b, plane, kKerf,
                                 Seed{Vec3(x0, 0, 0.004), mesh::FaceHandle(), -1.0}, slab);
    ASSERT_EQ(r.status, CutStatus::kOk) << to_string(r.status);
    const double v0 = testing::signed_volume(mesh::make_uv_sphere(0.01, 20000));
    const double removed_sep = v0 - testing::signed_volume(a);
    const double removed_slab = v0 - testing::signed_volume(b);
    EXPECT_GT(removed_slab, 0.0);
    EXPECT_NEAR(removed_sep, removed_slab, 0.05 * removed_slab);
}

TEST(Separate, OtherShellsCrossingThePlaneNeverMove) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, 48, 40);
    const TriMesh other = mesh::make_hollow_tube(0.05, 0.004, 0.002, 48, 40);
    const auto base = static_cast<int>(m.n_vertices());
    for (const auto v : other.vertices()) m.add_vertex(other.point(v) + Vec3(0.02, 0, 0));
    for (const auto f : other.faces()) {
        std::vector<mesh::VertexHandle> vs;
        for (const auto v : other.fv_range(f)) vs.emplace_back(v.idx() + base);
        m.add_face(vs);
    }
    CutContext ctx(m);
    CrossSection cs;
    const auto plane = *Plane::make(Vec3(0, 0, 0.0201), Vec3(0, 0, 1));
    ASSERT_TRUE(
        slice_by_plane(ctx, plane, Seed{Vec3(-0.006, 0, 0.0201), mesh::FaceHandle(), -1.0}, cs)
            .ok());
    std::vector<Vec3> others;
    for (int i = base; i < base + static_cast<int>(other.n_vertices()); ++i) {
        others.push_back(m.point(mesh::VertexHandle(i)));
    }
    auto sep = Separator::make(ctx, cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    sep->sweep_all();
    for (int i = 0; i < static_cast<int>(others.size()); ++i) {
        EXPECT_EQ(m.point(mesh::VertexHandle(base + i)), others[static_cast<std::size_t>(i)]);
    }
}

TEST(Separate, AWallLeaningOverAPartlyOpenedCapIsLiftedAboveTheCap) {
    // A cut just below the pole of a large sphere: above the plane the wall leans over the cap at
    // a grazing angle (a ring 25 um above the plane, 0.66 mm inside the rim). The blade sweeps
    // one side only (a withdrawn cut): caps are built on rim points only, so a cap triangle from
    // a swept rim point across the section rises as a wedge, up to 0.5 mm over ring vertices
    // the swept region's fall-off leaves where they were: the cap went through the wall.
    TriMesh m = testing::uv_sphere_by_rings(0.05, 200, 64);
    CutContext ctx(m);
    CrossSection cs;
    const auto plane = *Plane::make(Vec3(0, 0, 0.04995), Vec3(0, 0, 1));
    ASSERT_TRUE(slice_by_plane(ctx, plane, cs).ok());
    const auto near_cut = [&](mesh::FaceHandle f) {  // the faces within 2 kerfs of the plane
        for (const auto v : m.fv_range(f))
            if (std::abs(plane.signed_distance(m.point(v))) < 2 * kKerf) return true;
        return false;
    };
    ASSERT_TRUE(testing::crossing_face_pairs(m, 5e-4, 1e-12, near_cut).empty());
    const auto before = normals_of(m);
    auto sep = Separator::make(ctx, cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    for (double x = -0.0025; x <= -0.0010; x += 0.0002) {  // the blade comes in from -u
        ASSERT_TRUE(sep->sweep(swept_up_to(x)));
        const auto crossing = testing::crossing_face_pairs(m, 5e-4, 1e-12, near_cut);
        EXPECT_TRUE(crossing.empty())
            << crossing.size() << " faces cross with the blade at u = " << x * 1e3 << " mm";
    }
    EXPECT_GT(sep->stats().rim_pairs_swept, 0u);
    EXPECT_LT(sep->stats().rim_pairs_swept, sep->stats().rim_pairs);
    testing::expect_closed_2_manifold(m);
    expect_no_flip(m, before);
    sep->sweep_all();  // and completed: the gap is the kerf, nothing crosses
    EXPECT_TRUE(testing::crossing_face_pairs(m, 5e-4, 1e-12, near_cut).empty());
    expect_no_flip(m, before);
}

TEST(Separate, BadKerfOrCutIsRefusedAndBadPolygonsAreIgnored) {
    CutTube t;
    CutContext ctx(t.mesh);
    cut_tube(t, ctx);
    for (double bad : {0.0, -1e-3, std::nan(""), HUGE_VAL}) {
        auto r = Separator::make(ctx, t.cs, bad);
        ASSERT_FALSE(r.has_value());
        EXPECT_EQ(r.error(), CutStatus::kInvalidArgument);
    }
    EXPECT_FALSE(Separator::make(ctx, CrossSection{}, kKerf).has_value());
    auto sep = Separator::make(ctx, t.cs, kKerf);
    ASSERT_TRUE(sep.has_value());
    const auto hash = mesh_hash(t.mesh);
    const std::vector<Vec2> two{Vec2(0, 0), Vec2(1, 0)};
    const std::vector<Vec2> flat{Vec2(0, 0), Vec2(1, 0), Vec2(2, 0)};
    const std::vector<Vec2> nan{Vec2(0, 0), Vec2(std::nan(""), 0), Vec2(0, 1)};
    EXPECT_FALSE(sep->sweep(two));
    EXPECT_FALSE(sep->sweep(flat));
    EXPECT_FALSE(sep->sweep(nan));
    EXPECT_EQ(mesh_hash(t.mesh), hash);
}

TEST(Separate, TheSameEventsGiveTheSameMeshBitForBit) {
    std::uint64_t hashes[2];
    for (auto& h : hashes) {
        CutTube t;
        // The shape generators leave texture coordinates and colours uninitialised (garbage that
        // differs per run); define them so the hash compares what the cut computed.
        for (const auto v : t.mesh.vertices()) {
            t.mesh.set_texcoord2D(v, TriMesh::TexCoord2D(0.25f, 0.5f));
            t.mesh.set_color(v, TriMesh::Color(0.9f, 0.85f, 0.8f));
        }
        CutContext ctx(t.mesh);
        cut_tube(t, ctx);
        auto sep = Separator::make(ctx, t.cs, kKerf);
        ASSERT_TRUE(sep.has_value());
        for (double x = -0.007; x <= 0.0; x += 0.0005) sep->sweep(swept_up_to(x));
        h = mesh_hash(t.mesh);
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

}  // namespace
}  // namespace kerf::cut
