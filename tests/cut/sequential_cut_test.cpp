// Random sequential cuts of every kind on one mesh, as a training session makes them (issue 10
// item 5): each cut on what the earlier ones left — localised, full plane, chevron (a localised
// limb, then a second limb 20-70 degrees from it seeded where they meet) and biplanar slab,
// in turn — on the clean shared meshes (skipped when ../shared/meshes is absent) and on
// generated hollow tubes. After every cut: closed, oriented, no triangle below the one
// threshold (check_closed_2_manifold); a slice conserves the volume (1e-9, plus what its vertex
// merges may move); a slab removes what an independent reference says (the body holding the
// seed's face sliced by two full planes, the piece between them holding the seed on that face);
// no internal_error ever; a refusal leaves the mesh hash unchanged. Refusals are counted by
// status and printed; sequences reach shapes that single cuts of a clean bone do not, so they
// are not failed one by one, but the 60-cut form bounds each sequence's total (a ratchet).
// KERF_SEQUENCE_CUTS cuts per mesh: 4 in the always-run binary; 60 in the stress binary (12 meshes:
// 720 cuts).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "display/cut/mesh_hash.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/chevron_checks.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/cut/slice_sweep.hpp"

#ifndef KERF_SEQUENCE_CUTS
#define KERF_SEQUENCE_CUTS 4
#endif

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

struct SequenceTally {
    int cuts = 0;
    int internal_errors = 0;
    int edited_on_refusal = 0;
    int check_failures = 0;
    int slab_references = 0;  ///< slabs checked against the reference
    std::map<std::string, int> refusals;
};

// Vertices of `m` within `tol_m` of either wall of the slab on `plane`, `kerf_m` wide. The
// reference slices a copy of the seed's body alone, whose context measures a smaller box and so
// a smaller on-plane tolerance: a vertex between the two tolerances is on the wall for the cut
// (its cap passes through it, up to tol off the plane) and split for the reference, each such
// vertex moving the surface by at most tol as a merge does (volume_change_bound).
std::uint32_t vertices_on_walls(const TriMesh& m, const Plane& plane, double kerf_m, double tol_m) {
    const Plane lower = plane.offset(-0.5 * kerf_m), upper = plane.offset(0.5 * kerf_m);
    std::uint32_t n = 0;
    for (auto v : m.vertices()) {
        const Vec3 p = m.point(v);
        n += std::abs(lower.signed_distance(p)) <= tol_m ||
             std::abs(upper.signed_distance(p)) <= tol_m;
    }
    return n;
}

// Cuts `m` KERF_SEQUENCE_CUTS times (planes through random face centroids, random normals).
SequenceTally run_sequence(TriMesh& m, std::uint64_t seed) {
    SequenceTally t;
    CutContext ctx(m);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    CrossSection cs;
    SlabCut slab;
    const double kerf_m = 0.02 * ctx.scale_m();
    TriMesh before;
    for (int i = 0; i < KERF_SEQUENCE_CUTS; ++i) {
        ctx.grow_capacity();
        FaceHandle drawn_face;
        const auto drawn = testing::random_face_cut(m, rng, &drawn_face);
        const Plane& plane = drawn.first;
        const Seed& seed_here = drawn.second;
        const Vec3& p = seed_here.point_m;
        const std::uint64_t hash = mesh_hash(m);
        const double v0 = testing::signed_volume(m);
        const int kind = i % 4;
        CutResult r;
        if (kind == 0) {
            r = slice_by_plane(ctx, plane, seed_here, cs);
        } else if (kind == 1) {
            r = slice_by_plane(ctx, plane, cs);
        } else if (kind == 2) {
            r = slice_by_plane(ctx, plane, seed_here, cs);
            if (r.ok()) {
                const double angle = (20.0 + 50.0 * (0.5 + 0.5 * u(rng))) * M_PI / 180.0;
                const Plane second = testing::chevron_second_limb(plane, p, angle);
                const Seed seed2 = testing::seed_on_both(m, second, plane);
                if (seed2.tolerance_m != 0.0) {
                    const std::uint64_t between = mesh_hash(m);
                    const CutResult r2 = slice_by_plane(ctx, second, seed2, cs);
                    if (!r2.ok()) {
                        if (mesh_hash(m) != between) ++t.edited_on_refusal;
                        r.status = r2.status;
                    }
                    r.stats.vertices_merged += r2.stats.vertices_merged;
                }
            }
        } else {
            before = m;
            // Seeded on the face drawn, as the display seeds on the triangle the blade hit: a
            // point on an earlier cut's cap lies on its other cap too, so only the face says
            // which material the blade touches.
            r = subtract_slab(ctx, plane, kerf_m, Seed{p, drawn_face, -1.0}, slab);
        }
        if (r.status == CutStatus::kPlaneMissesMesh) continue;
        if (r.status == CutStatus::kInternalError) ++t.internal_errors;
        if (!r.ok()) {
            ++t.refusals[std::string(to_string(r.status))];
            std::printf("  cut %d (kind %d) refused: %s\n", i, kind,
                        std::string(to_string(r.status)).c_str());
            // A chevron whose second limb refused keeps its first (a cut of its own).
            if (kind != 2 && mesh_hash(m) != hash) ++t.edited_on_refusal;
            if (kind != 2) continue;
        }
        ++t.cuts;
        const testing::MeshReport rep = testing::check_closed_2_manifold(m);
        if (!rep.ok) {
            ++t.check_failures;
            ADD_FAILURE() << "cut " << i << " kind " << kind << ": " << rep.failures_log;
            continue;
        }
        const double bound = testing::volume_change_bound(
            v0, r.stats.vertices_merged, ctx.tolerance_m(), testing::surface_area(m));
        if (kind == 3) {
            // Against an independent reference, when its slices do not refuse; its slices' own
            // merges, and the vertices on the walls within the cut's tolerance but not the
            // reference's, move its surface as the cut's merges do (never by more than the
            // sequence's tolerance: the body's box is inside the mesh's).
            std::uint32_t reference_merges = 0;
            const double removed = testing::seed_face_slab_reference(before, plane, kerf_m, p,
                                                                     drawn_face, &reference_merges);
            const std::uint32_t on_walls =
                vertices_on_walls(before, plane, kerf_m, ctx.tolerance_m());
            const double slab_bound = testing::volume_change_bound(
                v0, r.stats.vertices_merged + reference_merges + on_walls, ctx.tolerance_m(),
                testing::surface_area(m));
            if (removed >= 0 && std::abs(rep.total_volume_m3 - (v0 - removed)) > slab_bound) {
                ++t.check_failures;
                ADD_FAILURE() << "slab " << i << ": volume " << rep.total_volume_m3 << " after "
                              << v0 << ", the reference removes " << removed << " (merges: cut "
                              << r.stats.vertices_merged << ", reference " << reference_merges
                              << "; vertices on the walls " << on_walls << "; snapped "
                              << r.stats.vertices_snapped << ", chords " << r.stats.cap_chords
                              << ")";
            }
            t.slab_references += removed >= 0;
        } else if (std::abs(rep.total_volume_m3 - v0) > bound) {
            ++t.check_failures;
            ADD_FAILURE() << "cut " << i << " kind " << kind << ": volume " << rep.total_volume_m3
                          << " after " << v0;
        }
    }
    return t;
}

// Refusals allowed per sequence in the 60-cut form (a ratchet: what the gcc build refused when
// each bound was set; a change that cuts refusals lowers them, one that brings refusals back
// fails). 29 of 720 in all since the chords into earlier caps (cap_chords.cpp; 128 before), 26
// since annuli are stitched with every rim point kept (triangulate_strip). The counts are chaotic
// (a change to one cut changes every cut drawn after it): compare totals. That change took "tube
// 20000 x 512" from 11 to 12 while the total fell by 3. 20 since a needle on a near-straight run
// of rim points is mended by two flips of the cap (cap_plan.cpp, `two_flips`): the six clean
// bones 0 in 360 (the calcaneus's one went), the tubes 20. The short form's few cuts are not
// bounded.
int refusal_bound(const std::string& name) {
    if (KERF_SEQUENCE_CUTS != 60) return -1;
    static const std::map<std::string, int> bounds = {{"bp3d_right_first_metatarsal.stl", 0},
                                                      {"jma_norm01_calcaneus_right.stl", 0},
                                                      {"jma_norm01_talus_right.stl", 0},
                                                      {"tcsm_ksbl_L01_talus_left.stl", 0},
                                                      {"tcsm_ksbl_L01_tibia_distal_left.stl", 0},
                                                      {"tcsm_ksbl_L01_fibula_distal_left.stl", 0},
                                                      {"tube 20000 x 32", 0},
                                                      {"tube 20000 x 512", 7},
                                                      {"tube 50000 x 64", 0},
                                                      {"tube 100000 x 128", 0},
                                                      {"tube 200000 x 32", 9},
                                                      {"tube 200000 x 512", 4}};
    const auto it = bounds.find(name);
    return it == bounds.end() ? -1 : it->second;
}

void report(const std::string& name, const SequenceTally& t) {
    std::string refused;
    int total = 0;
    for (const auto& [status, n] : t.refusals)
        refused += " " + status + "=" + std::to_string(n), total += n;
    std::printf("%s: %d cuts (%d slabs against the reference), %d refused%s\n", name.c_str(),
                t.cuts, t.slab_references, total, refused.c_str());
    ::testing::Test::RecordProperty("refusals", total);
    if (const int bound = refusal_bound(name); bound >= 0) {
        EXPECT_LE(total, bound) << name << ": more refusals than the ratchet allows";
    }
    EXPECT_EQ(t.internal_errors, 0) << name;
    EXPECT_EQ(t.edited_on_refusal, 0) << name << ": a refusal changed the mesh";
    EXPECT_EQ(t.check_failures, 0) << name;
}

class SharedMeshSequence : public ::testing::TestWithParam<const char*> {};

TEST_P(SharedMeshSequence, EveryCutKeepsEveryInvariantAndNoRefusalEditsTheMesh) {
    auto loaded = testing::load_shared_mesh(GetParam());
    if (!loaded) GTEST_SKIP() << "real meshes absent";
    TriMesh m = std::move(*loaded);
    report(GetParam(), run_sequence(m, std::hash<std::string>{}(GetParam())));
}

INSTANTIATE_TEST_SUITE_P(Clean, SharedMeshSequence,
                         ::testing::Values("bp3d_right_first_metatarsal.stl",
                                           "jma_norm01_calcaneus_right.stl",
                                           "jma_norm01_talus_right.stl",
                                           "tcsm_ksbl_L01_talus_left.stl",
                                           "tcsm_ksbl_L01_tibia_distal_left.stl",
                                           "tcsm_ksbl_L01_fibula_distal_left.stl"));

struct TubeShape {
    int triangles;
    int segments;
};

class TubeSequence : public ::testing::TestWithParam<TubeShape> {};

TEST_P(TubeSequence, EveryCutKeepsEveryInvariantAndNoRefusalEditsTheMesh) {
    const TubeShape s = GetParam();
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, s.segments,
                                       (s.triangles - 4 * s.segments) / (4 * s.segments));
    const std::string name =
        "tube " + std::to_string(s.triangles) + " x " + std::to_string(s.segments);
    report(name, run_sequence(m, static_cast<std::uint64_t>(s.triangles + s.segments)));
}

INSTANTIATE_TEST_SUITE_P(Generated, TubeSequence,
                         ::testing::Values(TubeShape{20000, 32}, TubeShape{20000, 512},
                                           TubeShape{50000, 64}, TubeShape{100000, 128},
                                           TubeShape{200000, 32}, TubeShape{200000, 512}));

}  // namespace
}  // namespace kerf::cut
