// The real bone meshes in ../shared/meshes: the validator must report exactly what the meshes
// README states (triangles, vertices, shells, closedness, volume within 0.1 %).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "display/mesh/mesh_io.hpp"
#include "display/mesh/validate.hpp"

namespace kerf::mesh {
namespace {

struct Expected {
    const char* file;
    LengthUnit units;
    std::size_t triangles;
    std::size_t vertices;
    std::size_t shells;
    std::size_t boundary_edges;
    double volume_mm3;  // 0 = not stated (open mesh)
};

constexpr Expected kReadme[] = {
    {"bp3d_right_forefoot_24shells.stl", LengthUnit::kMillimetre, 41'320, 20'654, 24, 0, 72'859},
    {"bp3d_right_first_metatarsal.stl", LengthUnit::kMillimetre, 4'886, 2'445, 1, 0, 13'494},
    {"jma_norm01_calcaneus_right.stl", LengthUnit::kMillimetre, 58'334, 29'169, 1, 0, 68'475},
    {"jma_norm01_talus_right.stl", LengthUnit::kMillimetre, 36'768, 18'386, 1, 0, 35'731},
    {"tcsm_ksbl_L01_talus_left.stl", LengthUnit::kMillimetre, 40'000, 20'002, 1, 0, 23'387},
    {"tcsm_ksbl_L01_tibia_distal_left.stl", LengthUnit::kMillimetre, 40'000, 20'002, 1, 0, 32'643},
    {"tcsm_ksbl_L01_fibula_distal_left.stl", LengthUnit::kMillimetre, 40'000, 20'002, 1, 0, 9'691},
    {"opensim_gait2392_foot_OPEN_metres.stl", LengthUnit::kMetre, 1'955, 1'000, 11, 3, 0},
};

std::filesystem::path meshes_dir() { return KERF_SHARED_MESHES; }

class RealMeshes : public ::testing::TestWithParam<Expected> {};

TEST_P(RealMeshes, ValidatorReportsWhatTheMeshesReadmeStates) {
    const Expected& x = GetParam();
    const auto path = meshes_dir() / x.file;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared meshes not present: " << path;
    auto loaded = load_mesh_file(path, x.units);
    ASSERT_TRUE(loaded) << loaded.error().message();
    const ValidationReport r = validate(loaded->indexed);
    EXPECT_EQ(r.triangles, x.triangles);
    EXPECT_EQ(r.vertices, x.vertices);
    EXPECT_EQ(r.shells.size(), x.shells);
    EXPECT_EQ(r.boundary_edges, x.boundary_edges);
    EXPECT_EQ(r.closed, x.boundary_edges == 0);
    EXPECT_EQ(r.non_manifold_edges, 0u);
    EXPECT_TRUE(r.oriented);
    EXPECT_EQ(loaded->mesh.n_faces(), x.triangles);  // nothing lost on the way into OpenMesh
    if (x.volume_mm3 > 0.0) {
        const double volume_mm3 = r.volume_m3 * 1e9;
        EXPECT_NEAR(volume_mm3, x.volume_mm3, x.volume_mm3 * 1e-3);
    }
}

std::string test_name(const ::testing::TestParamInfo<Expected>& param_info) {
    std::string name = param_info.param.file;
    name = name.substr(0, name.find('.'));
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RealMeshes, ::testing::ValuesIn(kReadme), test_name);

TEST(RealMeshes, OpenFileNamesItsThreeBoundaryEdgesWhereTheReadmeSaysTheHoleIs) {
    const auto path = meshes_dir() / "opensim_gait2392_foot_OPEN_metres.stl";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared meshes not present: " << path;
    auto loaded = load_mesh_file(path, LengthUnit::kMetre);
    ASSERT_TRUE(loaded) << loaded.error().message();
    const ValidationReport r = validate(loaded->indexed);
    ASSERT_EQ(r.boundary_samples_m.size(), 3u);
    const Point hole[3] = {
        {0.0627, 0.0333, 0.0089}, {0.0631, 0.0361, 0.0023}, {0.0644, 0.0339, -0.0016}};
    for (const auto& edge : r.boundary_samples_m) {
        for (const Point& end : edge) {
            double nearest = 1.0;
            for (const Point& h : hole) nearest = std::min(nearest, (end - h).norm());
            EXPECT_LT(nearest, 1e-4);  // README rounds to 0.1 mm
        }
    }
    std::size_t open_shells = 0;
    for (const ShellSummary& s : r.shells) open_shells += s.closed ? 0 : 1;
    EXPECT_EQ(open_shells, 1u);
}

TEST(RealMeshes, ForefootBoundingBoxMatchesTheReadme) {
    const auto path = meshes_dir() / "bp3d_right_forefoot_24shells.stl";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared meshes not present: " << path;
    auto loaded = load_mesh_file(path, LengthUnit::kMillimetre);
    ASSERT_TRUE(loaded) << loaded.error().message();
    const ValidationReport r = validate(loaded->indexed);
    EXPECT_NEAR(r.bbox_min_m[0], 0.0652, 1e-4);
    EXPECT_NEAR(r.bbox_max_m[2], 0.1411, 1e-4);
    EXPECT_NEAR(r.area_m2 * 1e6, 31'362.0, 31.4);
    EXPECT_EQ(r.shells[0].euler_characteristic, 2 - 2 * 27);  // shell 0 has genus 27
}

}  // namespace
}  // namespace kerf::mesh
