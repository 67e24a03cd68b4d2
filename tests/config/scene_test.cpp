// Scenes: mesh sources, units, the two rotation forms, path variables, and bad input.
#include "config/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "tests/config/config_test_support.hpp"

namespace kerf::config {
namespace {

using test::edit;
using test::error_of;
using test::line_of;
using test::shipped;

const std::string kBuiltin = shipped("scenes/builtin_foot.toml");
const std::string kCalcaneus = shipped("scenes/calcaneus.toml");

ConfigError parse_error(const std::string& text) {
    return error_of(parse_scene(text, "scenes/test.toml"));
}

TEST(SceneParse, BuiltinFootHasTargetTrianglesAndSeed) {
    auto s = parse_scene(kBuiltin, "b");
    ASSERT_TRUE(s) << s.error().message();
    ASSERT_EQ(s->bodies.size(), 1u);
    const SceneBody& b = s->bodies[0];
    EXPECT_EQ(b.mesh.kind, MeshSourceKind::kBuiltinFoot);
    EXPECT_EQ(b.mesh.target_triangles, 200'000u);
    EXPECT_EQ(b.mesh.seed, 1u);
    EXPECT_EQ(b.material, BodyMaterial::kCortical);
    EXPECT_DOUBLE_EQ(b.transform.rotation_wxyz[0], 1.0);
}

TEST(SceneParse, FileMeshKeepsItsPathTemplateAndUnits) {
    auto s = parse_scene(kCalcaneus, "c");
    ASSERT_TRUE(s) << s.error().message();
    const SceneBody& b = s->bodies.at(0);
    EXPECT_EQ(b.mesh.kind, MeshSourceKind::kFile);
    EXPECT_EQ(b.mesh.path, "${shared}/meshes/jma_norm01_calcaneus_right.stl");
    EXPECT_EQ(b.mesh.units, LengthUnit::kMillimetre);
    EXPECT_DOUBLE_EQ(metres_per_unit(b.mesh.units), 0.001);
    EXPECT_DOUBLE_EQ(b.transform.translation_m[1], 0.11307);
}

TEST(SceneParse, DeviceMappingAndPlannedCutOfTheCalcaneusScene) {
    auto s = parse_scene(kCalcaneus, "c");
    ASSERT_TRUE(s) << s.error().message();
    EXPECT_FALSE(s->device_mapping.origin_given);  // the default: above the scene's bounds
    EXPECT_DOUBLE_EQ(s->device_mapping.scale, 1.0);
    EXPECT_DOUBLE_EQ(s->device_mapping.rotation_wxyz[0], 1.0);
    ASSERT_TRUE(s->has_planned_cut);
    EXPECT_DOUBLE_EQ(s->planned_cut.point_m[2], 0.025);
    EXPECT_DOUBLE_EQ(s->planned_cut.normal[2], 1.0);
    EXPECT_DOUBLE_EQ(s->planned_cut.edge[0], 1.0);
}

TEST(SceneParse, NoMappingAndNoPlannedCutMeanTheDefaults) {
    auto s = parse_scene(kBuiltin, "b");
    ASSERT_TRUE(s) << s.error().message();
    EXPECT_FALSE(s->device_mapping.origin_given);
    EXPECT_DOUBLE_EQ(s->device_mapping.scale, 1.0);
    EXPECT_FALSE(s->has_planned_cut);
}

TEST(SceneParse, MappingOriginScaleAndRotationAreRead) {
    auto text = edit(kCalcaneus, "scale = 1.0 ",
                     "origin_m = [0.01, 0.07, -0.02]\nscale = 2.5\nrotation_axis = [0, 1, 0]\n"
                     "rotation_angle_deg = 90.0\n#");
    auto s = parse_scene(text, "c");
    ASSERT_TRUE(s) << s.error().message();
    const DeviceMapping& m = s->device_mapping;
    EXPECT_TRUE(m.origin_given);
    EXPECT_DOUBLE_EQ(m.origin_m[1], 0.07);
    EXPECT_DOUBLE_EQ(m.scale, 2.5);
    EXPECT_NEAR(m.rotation_wxyz[0], std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(m.rotation_wxyz[2], std::sqrt(0.5), 1e-12);
}

TEST(SceneParse, AnEdgeOffThePlaneIsProjectedIntoIt) {
    auto s = parse_scene(edit(kCalcaneus, "edge = [1.0, 0.0, 0.0]", "edge = [2.0, 0.0, 1.0]"), "c");
    ASSERT_TRUE(s) << s.error().message();
    EXPECT_NEAR(s->planned_cut.edge[0], 1.0, 1e-12);
    EXPECT_NEAR(s->planned_cut.edge[2], 0.0, 1e-12);
}

TEST(SceneParse, BadMappingAndPlannedCutValuesNameTheirFileLineAndKey) {
    struct Case {
        const char* from;
        const char* to;
        const char* key;
        ConfigErrc kind;
    };
    const Case cases[] = {
        {"scale = 1.0 ", "scale = 0.0 ", "device_mapping.scale", ConfigErrc::kOutOfRange},
        {"scale = 1.0 ", "scale = 1.0 \norigin_m = [0, 20, 0]\n#", "device_mapping.origin_m[1]",
         ConfigErrc::kOutOfRange},
        {"normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 0.0]", "planned_cut.normal",
         ConfigErrc::kOutOfRange},
        {"edge = [1.0, 0.0, 0.0]", "edge = [0.0, 0.0, 3.0]", "planned_cut.edge",
         ConfigErrc::kBadValue},
        {"point_m = [0.0, 0.0, 0.025]", "point_m = [0.0, 0.025]", "planned_cut.point_m",
         ConfigErrc::kOutOfRange},
        {"scale = 1.0 ", "scale = 1.0 \norigin_mm = [0, 0, 0]\n#", "device_mapping.origin_mm",
         ConfigErrc::kBadUnit},
    };
    for (const Case& c : cases) {
        const std::string text = edit(kCalcaneus, c.from, c.to);
        const ConfigError e = parse_error(text);
        EXPECT_EQ(e.key, c.key) << c.to << ": " << e.message();
        EXPECT_EQ(e.code, c.kind) << c.to << ": " << e.message();
        EXPECT_NE(e.message().find("scenes/test.toml:"), std::string::npos) << e.message();
        EXPECT_GT(e.line, 0) << e.message();
    }
}

TEST(SceneParse, AxisAngleBecomesANormalisedQuaternion) {
    auto text = edit(edit(kBuiltin, "rotation_axis = [0.0, 0.0, 1.0]", "rotation_axis = [0, 0, 2]"),
                     "rotation_angle_deg = 0.0", "rotation_angle_deg = 90.0");
    auto s = parse_scene(text, "t");
    ASSERT_TRUE(s) << s.error().message();
    const auto& q = s->bodies[0].transform.rotation_wxyz;
    EXPECT_NEAR(q[0], std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(q[1], 0.0, 1e-12);
    EXPECT_NEAR(q[3], std::sqrt(0.5), 1e-12);
}

TEST(SceneParse, UnknownLengthUnitIsABadUnitListingTheAcceptedOnes) {
    auto text = edit(kCalcaneus, "units = \"mm\"", "units = \"furlong\"");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kBadUnit);
    EXPECT_EQ(e.key, "bodies[0].mesh.units");
    EXPECT_EQ(e.value, "\"furlong\"");
    EXPECT_EQ(e.line, line_of(text, "units ="));
    EXPECT_EQ(e.expected, "one of \"m\", \"cm\", \"mm\", \"um\", \"in\"");
}

TEST(SceneParse, AngleInRadiansIsABadUnit) {
    auto e = parse_error(edit(kBuiltin, "rotation_angle_deg = 0.0", "rotation_angle_rad = 0.0"));
    EXPECT_EQ(e.code, ConfigErrc::kBadUnit);
    EXPECT_EQ(e.key, "bodies[0].transform.rotation_angle_rad");
}

TEST(SceneParse, BothRotationFormsAtOnceAreRejected) {
    auto e = parse_error(edit(kBuiltin, "rotation_angle_deg = 0.0",
                              "rotation_angle_deg = 0.0\nrotation_quaternion_wxyz = [1, 0, 0, 0]"));
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_NE(e.note.find("write the rotation once"), std::string::npos);
}

TEST(SceneParse, NonUnitQuaternionIsOutOfRange) {
    auto e = parse_error(edit(kCalcaneus, "[1.0, 0.0, 0.0, 0.0]", "[0.5, 0.0, 0.0, 0.0]"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "bodies[0].transform.rotation_quaternion_wxyz");
    EXPECT_NE(e.note.find("|q| = 0.5"), std::string::npos);
}

TEST(SceneParse, ZeroRotationAxisIsOutOfRange) {
    auto e =
        parse_error(edit(kBuiltin, "rotation_axis = [0.0, 0.0, 1.0]", "rotation_axis = [0, 0, 0]"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "bodies[0].transform.rotation_axis");
}

TEST(SceneParse, AxisWithoutAngleIsAMissingKey) {
    auto e = parse_error(edit(kBuiltin, "rotation_angle_deg = 0.0", ""));
    EXPECT_EQ(e.code, ConfigErrc::kMissingKey);
    EXPECT_EQ(e.key, "bodies[0].transform.rotation_angle_deg");
}

TEST(SceneParse, TooFewTrianglesIsOutOfRange) {
    auto e = parse_error(edit(kBuiltin, "target_triangles = 200_000", "target_triangles = 12"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.expected, "an integer, 10000 <= value <= 4000000");
}

TEST(SceneParse, FileKeysOnABuiltinMeshAreBadValues) {
    auto e = parse_error(edit(kBuiltin, "seed = 1", "seed = 1\nunits = \"mm\""));
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_EQ(e.key, "bodies[0].mesh.units");
}

TEST(SceneParse, UnknownPathVariableIsADanglingReference) {
    auto e = parse_error(edit(kCalcaneus, "${shared}/meshes", "${home}/meshes"));
    EXPECT_EQ(e.code, ConfigErrc::kBadReference);
    EXPECT_NE(e.note.find("${home}"), std::string::npos);
}

TEST(SceneParse, DuplicateBodyNamesAreRejected) {
    auto body = kBuiltin.substr(kBuiltin.find("[[bodies]]"));
    auto e = parse_error(kBuiltin + "\n" + body);
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_EQ(e.key, "bodies[1].name");
}

TEST(SceneParse, BodiesMustBeAnArrayOfTables) {
    auto e = parse_error("name = \"x\"\nbodies = 3\n");
    EXPECT_EQ(e.code, ConfigErrc::kWrongType);
    EXPECT_EQ(e.key, "bodies");
    EXPECT_EQ(e.line, 2u);
}

TEST(SceneResolve, MissingMeshFileIsADanglingReference) {
    auto s = parse_scene(kCalcaneus, "c");
    ASSERT_TRUE(s);
    auto e = error_of(resolve_mesh_path(s->bodies[0], {"/nonexistent", "/nonexistent/shared"}));
    EXPECT_EQ(e.code, ConfigErrc::kBadReference);
    EXPECT_NE(e.note.find("/nonexistent/shared/meshes/jma_norm01_calcaneus_right.stl"),
              std::string::npos)
        << e.note;
}

TEST(SceneResolve, SharedCalcaneusResolvesWhenTheSharedMeshesArePresent) {
    std::filesystem::path meshes(KERF_SHARED_MESHES);
    if (!std::filesystem::exists(meshes / "jma_norm01_calcaneus_right.stl"))
        GTEST_SKIP() << "shared meshes not found at " << meshes;
    auto s = parse_scene(kCalcaneus, "c");
    ASSERT_TRUE(s);
    auto p = resolve_mesh_path(s->bodies[0], {test::kConfigDir, meshes.parent_path()});
    ASSERT_TRUE(p) << p.error().message();
    EXPECT_TRUE(std::filesystem::is_regular_file(*p));
}

TEST(ExpandPath, RelativePathsAreTakenFromTheConfigFolder) {
    auto p = expand_path("meshes/a.stl", {"/etc/kerf", "/srv/shared"});
    ASSERT_TRUE(p);
    EXPECT_EQ(*p, "/etc/kerf/meshes/a.stl");
    auto q = expand_path("${shared}/../x/${config}", {"/c", "/s"});
    ASSERT_TRUE(q);
    EXPECT_EQ(*q, "/x/c");
    EXPECT_FALSE(expand_path("${shared", {"/c", "/s"}));
    EXPECT_FALSE(expand_path("", {"/c", "/s"}));
}

}  // namespace
}  // namespace kerf::config
