// RenderMesh: the flat GL-ready copy of a TriMesh and its dirty ranges (no GL needed).
#include "display/render/render_mesh.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "display/cut/cut_context.hpp"
#include "display/cut/cut_session.hpp"
#include "display/cut/separate.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/display/session_scenes.hpp"

namespace kerf::render {
namespace {

using mesh::TriMesh;

bool same_arrays(const RenderMesh& a, const RenderMesh& b) {
    const auto n = a.triangle_count() * 3;
    if (a.triangle_count() != b.triangle_count()) return false;
    for (std::uint32_t i = 0; i < n; ++i) {
        const RenderVertex &va = a.vertices()[a.indices()[i]], &vb = b.vertices()[b.indices()[i]];
        if (std::memcmp(&va, &vb, sizeof va) != 0) return false;
    }
    return true;
}

TEST(DirtyRanges, MergesNearbyMarksAndKeepsDistantOnesApart) {
    DirtyRanges d;
    d.mark(10);
    d.mark(12);
    d.mark(5000);
    d.mark(11);
    const auto r = d.ranges();
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].first, 10u);
    EXPECT_EQ(r[0].count, 3u);
    EXPECT_EQ(r[1].first, 5000u);
    EXPECT_EQ(d.element_count(), 4u);
    d.clear();
    EXPECT_TRUE(d.empty());
}

TEST(RenderMesh, BuildCopiesEveryVertexAndFaceWithItsMaterial) {
    const TriMesh m = mesh::make_hollow_tube(0.05, 0.01, 0.005, 32, 8);
    RenderMesh rm = RenderMesh::build(m);
    ASSERT_EQ(rm.triangle_count(), m.n_faces());
    EXPECT_GE(rm.vertex_capacity(), 2 * m.n_vertices());
    int canal = 0;
    for (auto v : m.vertices()) {
        const RenderVertex& r = rm.vertices()[static_cast<std::size_t>(v.idx())];
        EXPECT_FLOAT_EQ(r.position[2], static_cast<float>(m.point(v)[2]));
        const bool is_canal = m.data(v).material() == mesh::Material::kCancellous;
        EXPECT_EQ(r.kind, static_cast<std::uint8_t>(is_canal ? SurfaceKind::kCanal
                                                             : SurfaceKind::kCortical));
        canal += is_canal;
    }
    EXPECT_GT(canal, 0);
    EXPECT_TRUE(rm.needs_realloc());
    EXPECT_EQ(rm.cap_vertex_count(), 0u);
}

TEST(RenderMesh, SliceMarksOnlyTheEditAndMatchesAFullRebuild) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.01, 0.005, 64, 64);
    RenderMesh rm = RenderMesh::build(m);
    rm.dirty_vertices().clear();
    rm.dirty_indices().clear();
    cut::CutContext ctx(m);
    cut::CrossSection cs;
    ASSERT_TRUE(cut::slice_by_plane(ctx, *cut::Plane::make({0, 0, 0.0251}, {0.1, 0, 1}), cs).ok());
    const MeshSyncStats st = rm.update_after_edit(m);
    EXPECT_FALSE(st.rebuilt);
    EXPECT_GT(rm.cap_vertex_count(), 0u);
    // Only a small part of the buffers changed: the cross-section band, its caps, appended faces.
    const auto total_vertices = static_cast<double>(m.n_vertices());
    EXPECT_LT(static_cast<double>(rm.dirty_vertices().element_count()), 0.25 * total_vertices);
    EXPECT_LT(static_cast<double>(rm.dirty_indices().element_count()), 0.25 * 3 * m.n_faces());
    EXPECT_GT(rm.dirty_indices().element_count(), 0u);
    // The incremental result draws exactly what a fresh conversion draws.
    EXPECT_TRUE(same_arrays(rm, RenderMesh::build(m)));
    // Cap triangles use their own corners, shaded as cut bone with plane coordinates.
    int cut_corners = 0;
    for (std::uint32_t i = 0; i < rm.triangle_count() * 3; ++i) {
        const RenderVertex& v = rm.vertices()[rm.indices()[i]];
        if (v.kind >= static_cast<std::uint8_t>(SurfaceKind::kCutCortical)) {
            ++cut_corners;
            EXPECT_GE(rm.indices()[i], rm.vertex_capacity());
        }
    }
    EXPECT_EQ(static_cast<std::uint32_t>(cut_corners), rm.cap_vertex_count());
}

TEST(RenderMesh, SeparationUpdatesMovedVerticesAndTheirCapCorners) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.01, 0.005, 64, 64);
    cut::CutContext ctx(m);
    cut::CrossSection cs;
    ASSERT_TRUE(cut::slice_by_plane(ctx, *cut::Plane::make({0, 0, 0.0251}, {0, 0, 1}), cs).ok());
    RenderMesh rm = RenderMesh::build(m);
    rm.dirty_vertices().clear();
    rm.dirty_indices().clear();
    auto sep = cut::Separator::make(ctx, cs, 0.001);
    ASSERT_TRUE(sep);
    sep->sweep_all();
    rm.update_after_edit(m, sep->moved_vertices());
    EXPECT_GT(rm.dirty_vertices().element_count(), 0u);
    EXPECT_EQ(rm.dirty_indices().element_count(), 0u);  // no topology change
    EXPECT_TRUE(same_arrays(rm, RenderMesh::build(m)));
}

TEST(RenderMesh, UpdateAllMarksNothingWhenNothingChanged) {
    const TriMesh m = mesh::make_hollow_tube(0.05, 0.01, 0.005, 32, 8);
    RenderMesh rm = RenderMesh::build(m);
    rm.dirty_vertices().clear();
    rm.dirty_indices().clear();
    rm.update_all(m);
    EXPECT_TRUE(rm.dirty_vertices().empty());
    EXPECT_TRUE(rm.dirty_indices().empty());
}

TEST(RenderMesh, GrowingPastCapacityRebuildsAndSaysSo) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.01, 0.005, 16, 2);
    RenderMesh rm = RenderMesh::build(m, 1.0);
    cut::CutContext ctx(m);
    cut::CrossSection cs;
    for (double z : {0.011, 0.021, 0.031, 0.041}) {
        ASSERT_TRUE(cut::slice_by_plane(ctx, *cut::Plane::make({0, 0, z}, {0, 0, 1}), cs).ok());
    }
    const MeshSyncStats st = rm.update_after_edit(m);
    EXPECT_TRUE(st.rebuilt);
    EXPECT_TRUE(rm.needs_realloc());
    EXPECT_TRUE(same_arrays(rm, RenderMesh::build(m)));
}

TEST(RenderMesh, MoreCapFacesThanTheCapRegionHoldsRebuildsWithMoreRoom) {
    TriMesh m = mesh::make_hollow_tube(0.05, 0.01, 0.005, 200, 4);  // 400 cap faces a slice
    RenderMesh rm = RenderMesh::build(m);
    cut::CutContext ctx(m);
    cut::CrossSection cs;
    bool rebuilt = false;
    for (double z : {0.006, 0.016, 0.026, 0.036, 0.046}) {  // 2000 cap faces, 6000 corners
        ASSERT_TRUE(cut::slice_by_plane(ctx, *cut::Plane::make({0, 0, z}, {0, 0, 1}), cs).ok());
        rebuilt = rm.update_after_edit(m).rebuilt || rebuilt;
    }
    EXPECT_TRUE(rebuilt);
    EXPECT_GT(rm.cap_vertex_count(), 3u * 1024u);
    EXPECT_TRUE(same_arrays(rm, RenderMesh::build(m)));
    std::uint32_t cut_corners = 0;
    for (std::uint32_t i = 0; i < rm.triangle_count() * 3; ++i)
        cut_corners += rm.vertices()[rm.indices()[i]].kind >= 2;
    EXPECT_EQ(cut_corners, rm.cap_vertex_count());  // every cap face drawn as cut bone
}

TEST(RenderMesh, FollowsACutSessionThroughBeginProgressAndEnd) {
    cut::CutSession session(cut::test::tube());
    cut::SessionChanges changes;
    session.take_changes(changes);
    RenderMesh rm = RenderMesh::build(session.mesh());
    rm.dirty_vertices().clear();
    rm.dirty_indices().clear();
    const auto sync = [&] {
        session.take_changes(changes);
        rm.apply(session.mesh(), changes);
        if (changes.bodies)
            rm.assign_bodies(session.mesh(),
                             [&](mesh::VertexHandle v) { return session.body_of(v); });
        EXPECT_TRUE(same_arrays(rm, RenderMesh::build(session.mesh())) || changes.bodies);
    };
    ASSERT_EQ(session.begin(cut::test::begin_across(1)).outcome, cut::EventOutcome::kApplied);
    sync();
    EXPECT_GT(rm.cap_vertex_count(), 0u);
    EXPECT_LT(rm.dirty_vertices().element_count(), session.mesh().n_vertices() / 4);
    cut::CutProgress p;
    p.cut_id = 1;
    p.blade = cut::test::blade_across(0.0);
    p.swept = {-0.01, 0.01, -0.01, 0.0};
    session.progress(p);
    sync();
    session.end({1, cut::CutEndKind::kCompleted});
    sync();
    ASSERT_GE(session.bodies().size(), 2u);
    // Every vertex carries its session body; a fresh build with the same bodies draws the same.
    RenderMesh fresh = RenderMesh::build(session.mesh());
    fresh.assign_bodies(session.mesh(), [&](mesh::VertexHandle v) { return session.body_of(v); });
    EXPECT_TRUE(same_arrays(rm, fresh));
    int moved_piece = 0;
    for (auto v : session.mesh().vertices())
        moved_piece += rm.vertices()[static_cast<std::size_t>(v.idx())].body == 1;
    EXPECT_GT(moved_piece, 0);
}

}  // namespace
}  // namespace kerf::render
