// EditUndo (library-internal): the bounded undo that lets a slab cut refuse after its first wall
// was cut. Each slice of a random sequence is applied once or twice (a second slice planned on the
// edited mesh, as the slab's second wall is) and undone: the mesh must be element for element what
// it was, and the same slice then made for real must give what it gives on a copy that was never
// undone (same status, same hash: the face tree and the cap list were put back too).
#include "display/cut/edit_undo.hpp"

#include <gtest/gtest.h>

#include <random>

#include "display/cut/apply_plan.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/mesh_hash.hpp"
#include "display/cut/section_plan.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/cut_sequence.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut {
namespace {

using mesh::FaceHandle;
using mesh::TriMesh;

// Plans the localised slice of `plane` from `seed` as slice_by_plane does.
CutStatus plan(detail::ContextState& s, const Plane& plane, const Seed& seed) {
    std::vector<std::int32_t> snapped;
    return detail::plan_snapped(s, plane, snapped,
                                [&] { return detail::plan_localised(s, plane, seed); });
}

TEST(EditUndo, PutsBackEveryElementAndLaterCutsMatchACopyNeverUndone) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.006, 0.003, 48, 30);
    TriMesh control = m;
    CutContext ctx(m), control_ctx(control);
    detail::ContextState& s = ctx.state();
    std::mt19937_64 rng(7);
    CrossSection cs, cs2;
    int undone = 0, stacked = 0;
    // Until both kinds of undo were exercised often enough (the cuts drawn depend on the caps
    // earlier cuts made, so the counts move when the cap triangulation changes).
    for (int i = 0; i < 200 && (undone < 20 || stacked < 10); ++i) {
        ctx.grow_capacity();
        control_ctx.grow_capacity();
        const auto [plane, seed] = testing::random_face_cut(m, rng);
        if (plan(s, plane, seed) == CutStatus::kOk) {
            detail::EditUndo undo;
            undo.record(s);
            CutStats stats;
            ASSERT_EQ(detail::apply_plan(s, plane, cs, stats), CutStatus::kOk);
            // A second slice on the edited mesh, near the first (a slab's other wall), seeded
            // next to a rim vertex of the first.
            const double gap = 0.005 * ctx.scale_m();
            const Plane near = plane.offset(gap);
            const Seed near_seed{m.point(cs.positive.loops.front().front()) + near.normal() * gap,
                                 FaceHandle(), -1.0};
            if (plan(s, near, near_seed) == CutStatus::kOk) {
                undo.record(s);
                ASSERT_EQ(detail::apply_plan(s, near, cs2, stats), CutStatus::kOk);
                ++stacked;
            }
            undo.restore(s);
            ++undone;
            testing::expect_same_mesh(control, m);
            // The face tree reports no face the undo removed.
            int gone = 0;
            s.tree.for_each_near_point(Vec3(0, 0, 0), 1.0, [&](std::int32_t f) {
                gone += f >= static_cast<std::int32_t>(m.n_faces());
            });
            EXPECT_EQ(gone, 0);
            if (::testing::Test::HasFailure()) return;
        }
        // The same cut made for real on both.
        const CutResult a = slice_by_plane(ctx, plane, seed, cs);
        const CutResult b = slice_by_plane(control_ctx, plane, seed, cs2);
        ASSERT_EQ(a.status, b.status) << "cut " << i;
        ASSERT_EQ(mesh_hash(m), mesh_hash(control)) << "cut " << i;
    }
    testing::expect_closed_2_manifold(m);
    EXPECT_GE(undone, 20);
    EXPECT_GE(stacked, 10);
}

}  // namespace
}  // namespace kerf::cut
