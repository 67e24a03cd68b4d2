#include "display/mesh/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "display/mesh/validate.hpp"

namespace kerf::mesh {
namespace {

constexpr double kPi = std::numbers::pi;

void expect_closed_oriented_solid(const ValidationReport& r, std::size_t shells) {
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.oriented);
    EXPECT_EQ(r.boundary_edges, 0u);
    EXPECT_EQ(r.non_manifold_edges, 0u);
    EXPECT_EQ(r.non_manifold_vertices, 0u);
    EXPECT_EQ(r.misoriented_edges, 0u);
    EXPECT_EQ(r.degenerate_triangles, 0u);
    EXPECT_EQ(r.unreferenced_vertices, 0u);
    EXPECT_EQ(r.shells.size(), shells);
    EXPECT_GT(r.volume_m3, 0.0);
}

TEST(Shapes, BoxIsAClosedOrientedCuboidWithExactVolumeAndArea) {
    const TriMesh box = make_box(Point{-0.01, 0.0, 1.0}, Point{0.02, 0.005, 1.04}, 3);
    const ValidationReport r = validate(box);
    expect_closed_oriented_solid(r, 1);
    EXPECT_EQ(r.triangles, 12u * 9u);
    EXPECT_EQ(r.vertices, 6u * 16u - 12u * 4u + 8u);  // grid points minus shared edges/corners
    EXPECT_NEAR(r.volume_m3, 0.03 * 0.005 * 0.04, 1e-15);
    EXPECT_NEAR(r.area_m2, 2.0 * (0.03 * 0.005 + 0.03 * 0.04 + 0.005 * 0.04), 1e-14);
    EXPECT_EQ(r.shells[0].euler_characteristic, 2);
}

TEST(Shapes, UvSphereHitsItsTriangleTargetAndConvergesToTheBallVolume) {
    for (std::size_t target : {600u, 5'000u, 200'000u}) {
        const TriMesh s = make_uv_sphere(0.02, target, Point{0.1, -0.2, 0.3});
        const ValidationReport r = validate(s);
        expect_closed_oriented_solid(r, 1);
        EXPECT_NEAR(static_cast<double>(r.triangles), static_cast<double>(target),
                    0.1 * static_cast<double>(target));
        const double exact = 4.0 / 3.0 * kPi * 0.02 * 0.02 * 0.02;
        EXPECT_LT(r.volume_m3, exact);  // inscribed polyhedron
        EXPECT_NEAR(r.volume_m3, exact, exact * 30.0 / static_cast<double>(target));
    }
}

TEST(Shapes, TorusIsOneClosedShellOfGenusOneWithAnalyticVolume) {
    const TriMesh t = make_torus(0.03, 0.01, 96, 48);
    const ValidationReport r = validate(t);
    expect_closed_oriented_solid(r, 1);
    EXPECT_EQ(r.triangles, 2u * 96u * 48u);
    EXPECT_EQ(r.shells[0].euler_characteristic, 0);  // genus 1
    const double exact = 2.0 * kPi * kPi * 0.03 * 0.01 * 0.01;
    EXPECT_NEAR(r.volume_m3, exact, exact * 0.005);
}

TEST(Shapes, HollowTubeVolumeIsTheAnnulusTimesLengthAndTheCanalIsCancellous) {
    const TriMesh t = make_hollow_tube(0.05, 0.008, 0.004, 32, 10);
    const ValidationReport r = validate(t);
    expect_closed_oriented_solid(r, 1);
    EXPECT_EQ(r.triangles, 4u * 32u * 10u + 4u * 32u);
    EXPECT_EQ(r.shells[0].euler_characteristic, 0);  // a thick ring: genus 1
    const double annulus = inscribed_polygon_area(0.008, 32) - inscribed_polygon_area(0.004, 32);
    EXPECT_NEAR(r.volume_m3, annulus * 0.05, 1e-15);
    std::size_t cancellous = 0;
    for (const VertexHandle v : t.vertices()) {
        const Point p = t.point(v);
        const double radius = std::hypot(p[0], p[1]);
        const Material m = t.data(v).material();
        EXPECT_EQ(m, radius < 0.006 ? Material::kCancellous : Material::kCortical);
        cancellous += m == Material::kCancellous ? 1 : 0;
    }
    EXPECT_EQ(cancellous, 32u * 11u);
}

TEST(Shapes, GeneratedMeshesCarryUnitNormalsPointingOutward) {
    const TriMesh s = make_uv_sphere(1.0, 2'000);
    for (const FaceHandle f : s.faces()) {
        const auto n = s.normal(f);
        EXPECT_NEAR(n.norm(), 1.0, 1e-9);
        EXPECT_GT(n | s.calc_face_centroid(f), 0.0);
    }
    for (const VertexHandle v : s.vertices()) {
        EXPECT_GT(s.normal(v) | s.point(v), 0.9);
    }
}

TEST(Shapes, GenerationIsDeterministic) {
    const ValidationReport a = validate(make_torus(0.03, 0.01, 40, 20));
    const ValidationReport b = validate(make_torus(0.03, 0.01, 40, 20));
    EXPECT_EQ(a.volume_m3, b.volume_m3);
    EXPECT_EQ(a.area_m2, b.area_m2);
}

}  // namespace
}  // namespace kerf::mesh
