// The collision mesh kerf-display publishes: every body in its own frame with its pose, a
// material per triangle, accepted by the mailbox's own validation and read back intact.
#include "display/app/collision_export.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "tests/display/session_scenes.hpp"

namespace kerf::display {
namespace {

TEST(CollisionExport, EveryBodyWithItsPoseAndCapsAsCutSurface) {
    cut::CutSession s(cut::test::two_tubes());
    ASSERT_EQ(s.begin(cut::test::begin_across(1)).outcome, cut::EventOutcome::kApplied);
    ASSERT_EQ(s.end({1, cut::CutEndKind::kCompleted}).outcome, cut::EventOutcome::kApplied);
    ASSERT_EQ(s.move_body({2, cut::RigidPose{cut::Vec3(0.01, 0, 0), {1, 0, 0, 0}}}).outcome,
              cut::EventOutcome::kApplied);
    auto out = std::make_unique<ipc::CollisionMesh>();
    ASSERT_TRUE(export_collision(s, *out).has_value());
    EXPECT_EQ(out->body_count, 3u);
    EXPECT_EQ(out->vertex_count, s.mesh().n_vertices());
    EXPECT_EQ(out->index_count, 3 * s.mesh().n_faces());
    EXPECT_EQ(out->bodies[2].world_from_body[12], 0.01f);  // translation x, column-major
    std::size_t cut_surface = 0, cancellous = 0;
    for (std::uint32_t t = 0; t < out->index_count / 3; ++t) {
        cut_surface += out->materials[t] == std::uint8_t(ipc::TriangleMaterial::kCutSurface);
        cancellous += out->materials[t] == std::uint8_t(ipc::TriangleMaterial::kCancellous);
    }
    EXPECT_GT(cut_surface, 0u);  // both caps of the cut
    EXPECT_GT(cancellous, 0u);   // the canal walls
    std::string where;
    EXPECT_EQ(ipc::validate_mesh(*out, where), ipc::MeshFault::kNone) << where;
}

TEST(CollisionExport, AWithdrawnCutIsClosedWhereTheRenderedMeshKeepsItOpen) {
    // Half the rim swept, then withdrawn: the rendered mesh keeps that half open by the kerf (and
    // its caps as wedges across the tube); the collision mesh has both copies of every rim point
    // at one position on the plane, and every cap corner on it.
    cut::CutSession s(cut::test::tube());
    ASSERT_EQ(s.begin(cut::test::begin_across(3)).outcome, cut::EventOutcome::kApplied);
    const cut::CutProgress half{3, cut::test::blade_across(0.0), {-1.0, 0.0, -1.0, 1.0}};
    ASSERT_EQ(s.progress(half).outcome, cut::EventOutcome::kApplied);
    ASSERT_EQ(s.end({3, cut::CutEndKind::kWithdrawn}).outcome, cut::EventOutcome::kApplied);
    ASSERT_EQ(s.withdrawn_cuts().size(), 1u);
    auto out = std::make_unique<ipc::CollisionMesh>();
    ASSERT_TRUE(export_collision(s, *out).has_value());
    EXPECT_EQ(out->index_count, 3 * s.mesh().n_faces());  // triangle hints still index them
    const auto at = [&](mesh::VertexHandle v, int k) {    // one body: vertex index = export index
        return out->vertices_m[3 * std::size_t(v.idx()) + std::size_t(k)];
    };
    std::size_t opened = 0;
    for (const cut::Glue& pair : s.withdrawn_rim_pairs()) {
        opened += (s.mesh().point(pair.a) - s.mesh().point(pair.b)).norm() > 0.5 * cut::test::kKerf;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(at(pair.a, k), at(pair.b, k));
        EXPECT_NEAR(at(pair.a, 2), cut::test::kCutZ, 1e-7);
    }
    EXPECT_GT(opened, 10u);  // the rendered mesh is open there
    std::size_t caps = 0;
    for (std::uint32_t t = 0; t < out->index_count / 3; ++t) {
        if (out->materials[t] != std::uint8_t(ipc::TriangleMaterial::kCutSurface)) continue;
        ++caps;
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(out->vertices_m[3 * std::size_t(out->indices[3 * t + c]) + 2],
                        cut::test::kCutZ, 1e-7);
        }
    }
    EXPECT_GT(caps, 0u);
    std::string where;
    EXPECT_EQ(ipc::validate_mesh(*out, where), ipc::MeshFault::kNone) << where;
}

TEST(CollisionExport, TheOneMillionTriangleFootFitsAndLargerCountsAreRefused) {
    // The built-in foot at 1M triangles (499,909 vertices, 999,666 triangles, 19 bones) fits
    // with room for cuts; a mesh past either capacity, or with too many bodies, is named.
    EXPECT_EQ(mailbox_misfit(19, 499'909, 999'666), "");
    EXPECT_EQ(mailbox_misfit(64, ipc::kMeshMaxVertices, ipc::kMeshMaxTriangles), "");
    EXPECT_NE(mailbox_misfit(1, ipc::kMeshMaxVertices + 1, 4).find("the mailbox holds"),
              std::string::npos);
    EXPECT_NE(mailbox_misfit(1, 4, ipc::kMeshMaxTriangles + 1).find("the mailbox holds"),
              std::string::npos);
    EXPECT_NE(mailbox_misfit(65, 4, 4).find("65 bodies"), std::string::npos);
}

}  // namespace
}  // namespace kerf::display
