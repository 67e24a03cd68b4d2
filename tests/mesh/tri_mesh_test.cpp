#include "display/mesh/tri_mesh.hpp"

#include <gtest/gtest.h>

namespace kerf::mesh {
namespace {

TEST(TriMesh, CarriesEveryAttributeTheCutterInterpolates) {
    TriMesh m = make_mesh();
    EXPECT_TRUE(m.has_vertex_normals());
    EXPECT_TRUE(m.has_vertex_texcoords2D());
    EXPECT_TRUE(m.has_vertex_colors());
    EXPECT_TRUE(m.has_vertex_status());
    EXPECT_TRUE(m.has_face_status());
    EXPECT_TRUE(m.has_edge_status());
    const VertexHandle v = m.add_vertex(Point{0.0, 0.0, 0.0});
    EXPECT_EQ(m.data(v).material(), Material::kCortical);
    m.data(v).set_material(Material::kCutSurface);
    EXPECT_EQ(to_string(m.data(v).material()), "cut_surface");
}

}  // namespace
}  // namespace kerf::mesh
