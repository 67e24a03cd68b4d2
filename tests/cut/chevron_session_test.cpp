// A chevron osteotomy as surgeons cut it, through CutSession: two partial cuts (each limb ends
// withdrawn, its blade stopped where the limbs meet inside the bone) that together free the head.
// On the built-in foot's first metatarsal and on the shared-mesh first metatarsal: exactly 2
// pieces, volumes conserved (a zero-width blade, so nothing is removed), every piece closed.
// Limbs that stop short of each other, or one limb alone, free nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "display/cut/cut_session.hpp"
#include "display/mesh/foot_generator.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

/// Where the chevron goes: the apex (inside the bone), the bone's axis towards the head, the
/// dorsal direction (perpendicular to the axis) and the half-angle of the V.
struct Chevron {
    Vec3 apex_m;
    Vec3 axis;
    Vec3 dorsal;
    double half_angle_rad = 30.0 * M_PI / 180.0;
    double reach_m = 0.05;  ///< how far the blade's rectangle reaches beyond the apex
};

/// One limb: +1 the dorsal one, -1 the plantar one. It runs from the apex away from the head.
struct Limb {
    Vec3 direction;  ///< from the apex along the limb
    BladeFrame blade;
};

Limb limb(const Chevron& c, double side) {
    const Vec3 ml = OpenMesh::cross(c.axis, c.dorsal).normalized();
    const Vec3 d =
        (-c.axis * std::cos(c.half_angle_rad) + c.dorsal * (side * std::sin(c.half_angle_rad)))
            .normalized();
    const Vec3 n = OpenMesh::cross(d, ml).normalized();
    return Limb{d, BladeFrame{c.apex_m, n, ml}};
}

/// The limb's swept rectangle in its blade frame: the whole width of the bone, from `past_apex_m`
/// beyond the apex (negative: stopping short of it) out past the surface.
SweptRect limb_rect(const Chevron& c, const Limb& l, double past_apex_m) {
    const Vec3 v = OpenMesh::cross(l.blade.normal, l.blade.u);
    SweptRect r{-c.reach_m, c.reach_m, -past_apex_m, c.reach_m};
    if (OpenMesh::dot(v, l.direction) < 0)
        r = SweptRect{-c.reach_m, c.reach_m, -c.reach_m, past_apex_m};
    return r;
}

/// Where the blade enters the bone for a limb: the centroid of the face crossing the limb's
/// plane farthest from the apex along the limb (the outer surface).
Vec3 entry_point(const TriMesh& m, const Limb& l, std::uint32_t body, const CutSession& s) {
    double best = -1e300;
    Vec3 out(0, 0, 0);
    for (const auto f : m.faces()) {
        if (s.body_of(f) != body) continue;
        int pos = 0, neg = 0;
        Vec3 centroid(0, 0, 0);
        for (const auto v : m.fv_range(f)) {
            const double d = OpenMesh::dot(m.point(v) - l.blade.point_m, l.blade.normal);
            pos += d > 0, neg += d < 0;
            centroid += m.point(v) / 3.0;
        }
        const double along = OpenMesh::dot(centroid - l.blade.point_m, l.direction);
        if (pos && neg && along > best) best = along, out = centroid;
    }
    return out;
}

/// Signed volume of every body, m^3.
std::vector<double> body_volumes(const CutSession& s) {
    std::vector<double> v(s.bodies().size(), 0.0);
    const TriMesh& m = s.mesh();
    for (const auto f : m.faces()) {
        Vec3 p[3];
        int k = 0;
        for (const auto x : m.fv_range(f)) p[k++] = m.point(x);
        v[s.body_of(f)] += OpenMesh::dot(p[0], OpenMesh::cross(p[1], p[2])) / 6.0;
    }
    return v;
}

/// Cuts one limb: begin (touching at its entry point), one progress over its rectangle, end.
void cut_limb(CutSession& s, std::uint32_t id, std::uint32_t body, const Chevron& c, double side,
              double past_apex_m, double kerf_m, CutEndKind end) {
    const Limb l = limb(c, side);
    CutBegin b;
    b.cut_id = id;
    b.body_id = body;
    b.blade = l.blade;
    b.seed_m = entry_point(s.mesh(), l, body, s);
    b.kerf_width_m = kerf_m;
    const ApplyReport begun = s.begin(b);
    ASSERT_EQ(begun.outcome, EventOutcome::kApplied) << begun.why << " " << to_string(begun.status);
    EXPECT_GE(begun.slice.loops, 1u);
    const ApplyReport swept = s.progress(CutProgress{id, l.blade, limb_rect(c, l, past_apex_m)});
    EXPECT_NE(swept.outcome, EventOutcome::kRefused) << swept.why;
    ASSERT_EQ(s.end(CutEnd{id, end}).outcome, EventOutcome::kApplied);
}

struct ChevronOutcome {
    std::size_t bodies_before = 0;
    std::size_t bodies_after_first = 0;
    std::size_t bodies_after = 0;
    double volume_before_m3 = 0;
    std::vector<double> volumes_after_m3;  ///< of the bone's body and every body it gave
};

ChevronOutcome cut_chevron(TriMesh scene, FaceHandle bone_face, const Chevron& c,
                           double past_apex_m, double kerf_m) {
    CutSession s(std::move(scene));
    ChevronOutcome o;
    const std::uint32_t bone = s.body_of(bone_face);
    o.bodies_before = s.bodies().size();
    o.volume_before_m3 = body_volumes(s)[bone];
    cut_limb(s, 1, bone, c, +1.0, past_apex_m, kerf_m, CutEndKind::kWithdrawn);
    o.bodies_after_first = s.bodies().size();
    cut_limb(s, 2, bone, c, -1.0, past_apex_m, kerf_m, CutEndKind::kWithdrawn);
    o.bodies_after = s.bodies().size();
    testing::expect_closed_2_manifold(s.mesh());
    const std::vector<double> v = body_volumes(s);
    o.volumes_after_m3.push_back(v[bone]);
    for (const SessionBody& b : s.bodies())
        if (b.parent == bone) o.volumes_after_m3.push_back(v[b.id]);
    return o;
}

/// The chevron on the built-in foot's first metatarsal: apex on the axis at 80 % towards the
/// head, dorsal = +y.
Chevron foot_chevron(const mesh::BoneInfo& bone) {
    Chevron c;
    c.axis = (bone.head_m - bone.base_m).normalized();
    Vec3 up(0, 1, 0);
    c.dorsal = (up - c.axis * OpenMesh::dot(up, c.axis)).normalized();
    c.apex_m = bone.base_m + (bone.head_m - bone.base_m) * 0.8;
    c.reach_m = 4.0 * bone.max_radius_m;
    return c;
}

mesh::Foot small_foot() {
    auto foot = mesh::generate_foot(mesh::FootParams{20'000, 1});
    EXPECT_TRUE(foot) << (foot ? "" : foot.error());
    return std::move(*foot);
}

TEST(ChevronSession, TwoWithdrawnLimbsMeetingInsideTheFootsFirstMetatarsalFreeTheHead) {
    mesh::Foot foot = small_foot();
    const Chevron c = foot_chevron(foot.first_metatarsal());
    const auto face = FaceHandle(static_cast<int>(foot.first_metatarsal().first_triangle));
    const ChevronOutcome o = cut_chevron(std::move(foot.mesh), face, c, 3e-4, 0.0);
    EXPECT_EQ(o.bodies_after_first, o.bodies_before) << "one limb alone frees nothing";
    ASSERT_EQ(o.bodies_after, o.bodies_before + 1) << "the head comes free: 2 pieces";
    ASSERT_EQ(o.volumes_after_m3.size(), 2u);
    EXPECT_NEAR(o.volumes_after_m3[0] + o.volumes_after_m3[1], o.volume_before_m3,
                1e-9 * o.volume_before_m3);
    EXPECT_GT(o.volumes_after_m3[1], 0.02 * o.volume_before_m3);  // the head, not a crumb
    EXPECT_GT(o.volumes_after_m3[0], o.volumes_after_m3[1]);      // the shaft is the larger
}

TEST(ChevronSession, LimbsThatStopShortOfEachOtherFreeNothing) {
    mesh::Foot foot = small_foot();
    const Chevron c = foot_chevron(foot.first_metatarsal());
    const auto face = FaceHandle(static_cast<int>(foot.first_metatarsal().first_triangle));
    // Each blade stops 1 mm before the apex: a bridge of bone holds the head.
    const ChevronOutcome o = cut_chevron(std::move(foot.mesh), face, c, -1e-3, 0.0);
    EXPECT_EQ(o.bodies_after, o.bodies_before);
}

TEST(ChevronSession, WithABladeOfRealWidthTheHeadComesFreeToo) {
    mesh::Foot foot = small_foot();
    const Chevron c = foot_chevron(foot.first_metatarsal());
    const auto face = FaceHandle(static_cast<int>(foot.first_metatarsal().first_triangle));
    const ChevronOutcome o = cut_chevron(std::move(foot.mesh), face, c, 3e-4, 0.6e-3);
    ASSERT_EQ(o.bodies_after, o.bodies_before + 1);
    ASSERT_EQ(o.volumes_after_m3.size(), 2u);
    // The opened kerfs took bone away: less than before, but not more than two limbs' worth.
    const double sum = o.volumes_after_m3[0] + o.volumes_after_m3[1];
    EXPECT_LT(sum, o.volume_before_m3);
    EXPECT_GT(sum, 0.8 * o.volume_before_m3);
}

TEST(ChevronSession, TwoWithdrawnLimbsFreeTheHeadOfTheSharedFirstMetatarsal) {
    auto loaded = testing::load_shared_mesh("bp3d_right_first_metatarsal.stl");
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    // The bone's long axis and a perpendicular (principal axes of its vertices).
    Vec3 centre(0, 0, 0);
    for (const auto v : m.vertices()) centre += m.point(v);
    centre /= static_cast<double>(m.n_vertices());
    double cov[3][3] = {};
    for (const auto v : m.vertices()) {
        const Vec3 d = m.point(v) - centre;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) cov[i][j] += d[i] * d[j];
    }
    auto principal = [&](const Vec3& not_along) {
        Vec3 x(0.3, 0.5, 0.8);
        for (int it = 0; it < 200; ++it) {
            Vec3 y(0, 0, 0);
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) y[i] += cov[i][j] * x[j];
            y -= not_along * OpenMesh::dot(y, not_along);
            x = y.normalized();
        }
        return x;
    };
    Chevron c;
    c.axis = principal(Vec3(0, 0, 0));
    c.dorsal = principal(c.axis);
    double lo = 1e300, hi = -1e300;
    for (const auto v : m.vertices()) {
        const double t = OpenMesh::dot(m.point(v) - centre, c.axis);
        lo = std::min(lo, t), hi = std::max(hi, t);
    }
    c.apex_m = centre + c.axis * (lo + 0.75 * (hi - lo));
    c.reach_m = hi - lo;
    const ChevronOutcome o = cut_chevron(std::move(m), FaceHandle(0), c, 3e-4, 0.0);
    EXPECT_EQ(o.bodies_after_first, o.bodies_before);
    ASSERT_EQ(o.bodies_after, o.bodies_before + 1);
    ASSERT_EQ(o.volumes_after_m3.size(), 2u);
    EXPECT_NEAR(o.volumes_after_m3[0] + o.volumes_after_m3[1], o.volume_before_m3,
                1e-9 * o.volume_before_m3);
    EXPECT_GT(std::min(o.volumes_after_m3[0], o.volumes_after_m3[1]), 0.02 * o.volume_before_m3);
}

}  // namespace
}  // namespace kerf::cut
