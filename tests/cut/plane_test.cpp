#include "display/cut/plane.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "display/cut/cut_result.hpp"

namespace kerf::cut {
namespace {

TEST(Plane, MakeNormalisesTheNormalAndBuildsARightHandedFrame) {
    auto p = Plane::make(Vec3(1, 2, 3), Vec3(0, 0, 5));
    ASSERT_TRUE(p);
    EXPECT_DOUBLE_EQ(p->normal().norm(), 1.0);
    for (const Vec3& n : {Vec3(0, 0, 1), Vec3(1, 1, 1), Vec3(-0.3, 0.9, 0.01), Vec3(1, 0, 0)}) {
        auto q = Plane::make(Vec3(0, 0, 0), n);
        ASSERT_TRUE(q);
        EXPECT_NEAR(q->u().norm(), 1.0, 1e-15);
        EXPECT_NEAR(q->v().norm(), 1.0, 1e-15);
        EXPECT_NEAR(OpenMesh::dot(q->u(), q->normal()), 0.0, 1e-15);
        EXPECT_NEAR((OpenMesh::cross(q->u(), q->v()) - q->normal()).norm(), 0.0, 1e-15);
    }
}

TEST(Plane, RejectsZeroAndNonFiniteInputWithInvalidPlane) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (auto r :
         {Plane::make(Vec3(0, 0, 0), Vec3(0, 0, 0)), Plane::make(Vec3(nan, 0, 0), Vec3(0, 0, 1)),
          Plane::make(Vec3(0, 0, 0), Vec3(0, inf, 1)),
          Plane::make(Vec3(0, 0, 0), Vec3(1e-300, 0, 0))}) {
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error(), CutStatus::kInvalidPlane);
    }
}

TEST(Plane, SignedDistanceSideAndFrameRoundTrip) {
    auto p = Plane::make(Vec3(0, 0, 0.1), Vec3(0, 0, 1));
    ASSERT_TRUE(p);
    EXPECT_DOUBLE_EQ(p->signed_distance(Vec3(5, 5, 0.3)), 0.3 - 0.1);
    EXPECT_EQ(p->side(Vec3(0, 0, 0.1 + 1e-9), 1e-8), 0);
    EXPECT_EQ(p->side(Vec3(0, 0, 0.2), 1e-8), 1);
    EXPECT_EQ(p->side(Vec3(0, 0, 0.0), 1e-8), -1);
    const Vec3 q(0.25, -0.5, 0.1);
    EXPECT_NEAR((p->to_3d(p->to_2d(q)) - q).norm(), 0.0, 1e-15);
    const Plane up = p->offset(0.05);
    EXPECT_NEAR(up.signed_distance(Vec3(0, 0, 0.15)), 0.0, 1e-15);
    EXPECT_EQ(up.u(), p->u());
}

TEST(CutStatus, EveryValueHasADistinctName) {
    EXPECT_EQ(to_string(CutStatus::kOk), "ok");
    EXPECT_EQ(to_string(CutStatus::kPlaneMissesMesh), "plane_misses_mesh");
    EXPECT_EQ(to_string(CutStatus::kSeedNotOnSurface), "seed_not_on_surface");
    EXPECT_EQ(to_string(CutStatus::kNonManifoldInput), "non_manifold_input");
    EXPECT_EQ(to_string(CutStatus::kInvalidPlane), "invalid_plane");
    EXPECT_EQ(to_string(static_cast<CutStatus>(200)), "unknown");
}

}  // namespace
}  // namespace kerf::cut
