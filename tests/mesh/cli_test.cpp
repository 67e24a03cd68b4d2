// `kerf mesh info`, `kerf gen foot` and `kerf demo` run as real processes (fork/exec).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;

using kerf::test::ProcessRun;

class KerfCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("kerf_cli_test_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    ProcessRun kerf(std::vector<std::string> args) {
        return kerf::test::run_process(std::string(KERF_BIN_DIR) + "/kerf", std::move(args), dir_);
    }

    fs::path dir_;
};

fs::path shared(const char* file) { return fs::path(KERF_SHARED_MESHES) / file; }

TEST_F(KerfCli, MeshInfoSaysTheOpensimFootIsOpenWithThreeBoundaryEdges) {
    const fs::path file = shared("opensim_gait2392_foot_OPEN_metres.stl");
    if (!fs::exists(file)) GTEST_SKIP() << "shared meshes not present: " << file;
    const ProcessRun r = kerf({"mesh", "info", file.string(), "--units", "m"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("triangles:             1955\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("closed:                no (3 boundary edges)"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("shells:                11\n"), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;  // in metres, read as metres: a plausible foot
    // Read as millimetres (the default), it is a 0.19 mm foot: a warning names the unit.
    const ProcessRun mm = kerf({"mesh", "info", file.string()});
    EXPECT_EQ(mm.exit_code, 0) << mm.err;
    EXPECT_NE(mm.err.find("smaller than a bone"), std::string::npos) << mm.err;
    EXPECT_NE(mm.err.find("is the file in m?"), std::string::npos) << mm.err;
}

TEST_F(KerfCli, MeshInfoJsonReportsTheReadmeCountsForTheCalcaneus) {
    const fs::path file = shared("jma_norm01_calcaneus_right.stl");
    if (!fs::exists(file)) GTEST_SKIP() << "shared meshes not present: " << file;
    const ProcessRun r = kerf({"mesh", "info", file.string(), "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\"triangles\": 58334"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"closed\": true"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"units\": \"mm\""), std::string::npos) << r.out;
    EXPECT_EQ(r.out.front(), '{');
}

TEST_F(KerfCli, MeshInfoOnAMissingFileFailsWithExitOneNamingThePath) {
    const ProcessRun r = kerf({"mesh", "info", "/no/such/bone.stl"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err, "kerf mesh info: cannot load mesh: /no/such/bone.stl: no such file (io)\n");
    EXPECT_TRUE(r.out.empty());
}

TEST_F(KerfCli, MeshInfoOnAMalformedFileNamesTheLine) {
    const fs::path bad = dir_ / "bad.obj";
    std::ofstream(bad) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    const ProcessRun r = kerf({"mesh", "info", bad.string()});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find(bad.string() + ":4: face refers to vertex 9"), std::string::npos) << r.err;
}

TEST_F(KerfCli, UnknownUnitIsAUsageError) {
    const ProcessRun r = kerf({"mesh", "info", "x.stl", "--units", "furlong"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("furlong"), std::string::npos) << r.err;
}

TEST_F(KerfCli, HelpSaysTheDefaultUnitIsMillimetres) {
    const ProcessRun r = kerf({"mesh", "info", "--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("STL carries no unit"), std::string::npos) << r.out;
}

TEST_F(KerfCli, GenFootWritesAClosedFootThatMeshInfoReadsBack) {
    const fs::path out = dir_ / "foot.ply";
    const ProcessRun gen =
        kerf({"gen", "foot", "--triangles", "20000", "--seed", "3", "-o", out.string()});
    ASSERT_EQ(gen.exit_code, 0) << gen.err;
    EXPECT_NE(gen.out.find("first metatarsal axis"), std::string::npos);
    const ProcessRun info = kerf({"mesh", "info", out.string(), "--json"});
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("\"closed\": true"), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("\"oriented\": true"), std::string::npos) << info.out;
    const auto doc = nlohmann::json::parse(info.out);  // one valid document
    EXPECT_EQ(doc["report"]["shells"].size(), 38u);
    EXPECT_EQ(doc["coincidence"]["repeated_triangles"], 0);
}

// Issue 9, item 14: two triangles on the same three points made "closed: yes, genus 0". The
// report now names the repeated triangle (and warns), and vertices that coincide without being
// bit-identical are listed with their positions.
TEST_F(KerfCli, MeshInfoReportsRepeatedTrianglesAndCoincidentVertices) {
    const fs::path sheet = dir_ / "sheet.stl";
    std::ofstream(sheet) << "solid s\n"
                            "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\n"
                            "vertex 0 10 0\nendloop\nendfacet\n"
                            "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 10 0\n"
                            "vertex 10 0 0\nendloop\nendfacet\nendsolid s\n";
    ProcessRun r = kerf({"mesh", "info", sheet.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("repeated triangles:    1 "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("triangle 1 repeats triangle 0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("warning: 'closed' pairs repeated triangles"), std::string::npos) << r.out;

    // A tetrahedron whose apex is written twice, 1 nm apart (well under 1e-6 of its diagonal).
    const fs::path tet = dir_ / "tet.obj";
    std::ofstream(tet) << "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nv 0 0 10.000001\n"
                          "f 1 3 2\nf 1 2 4\nf 2 3 5\nf 3 1 4\n";
    r = kerf({"mesh", "info", tet.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("closed:                no"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("coincident vertices:   1 pairs closer than"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("vertex 3 and vertex 4, 1e-06 mm apart: (0, 0, 10) and (0, 0, 10)"),
              std::string::npos)
        << r.out;
}

// Issue 9, item 10: `kerf mesh info --json` is one document a parser accepts, whatever the path.
TEST_F(KerfCli, MeshInfoJsonIsValidWhateverThePathHolds) {
    const fs::path odd = dir_ / "q\"x\\y.stl";
    std::ofstream(odd) << "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\n"
                          "vertex 0 10 0\nendloop\nendfacet\nendsolid s\n";
    const ProcessRun r = kerf({"mesh", "info", odd.string(), "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto doc = nlohmann::json::parse(r.out);  // throws (fails the test) on invalid JSON
    EXPECT_EQ(doc["file"].get<std::string>(), odd.string());
    EXPECT_EQ(doc["report"]["triangles"], 1);
    EXPECT_EQ(doc["coincidence"]["coincident_vertex_pairs"], 0);
    EXPECT_GT(doc["coincidence"]["tolerance_m"].get<double>(), 0.0);
}

// Issue 9, item 16: a file in metres read as millimetres (the default) is a 0.2 mm "bone": warn,
// naming the unit that fits. A plausible size says nothing.
TEST_F(KerfCli, MeshInfoWarnsWhenTheSizeIsImplausibleForTheUnit) {
    const fs::path tiny = dir_ / "metres.obj";
    std::ofstream(tiny) << "v 0 0 0\nv 0.2 0 0\nv 0 0.2 0\nv 0 0 0.2\n"
                           "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    ProcessRun r = kerf({"mesh", "info", tiny.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: the mesh is 0.2 mm across (largest side), smaller than a bone"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("is the file in m? (--units m reads it as 200 mm)"), std::string::npos)
        << r.err;
    r = kerf({"mesh", "info", tiny.string(), "--units", "m", "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const auto doc = nlohmann::json::parse(r.out, nullptr, false);
    EXPECT_FALSE(doc.is_discarded()) << r.out;
}

TEST_F(KerfCli, GenFootRefusesAnOutOfRangeTargetAndAnUnwritablePath) {
    const ProcessRun small =
        kerf({"gen", "foot", "--triangles", "10", "-o", (dir_ / "f.stl").string()});
    EXPECT_EQ(small.exit_code, 1);
    EXPECT_NE(small.err.find("kerf gen foot: --triangles: target_triangles 10 is outside"),
              std::string::npos)
        << small.err;
    const ProcessRun unwritable =
        kerf({"gen", "foot", "--triangles", "10000", "-o", "/no/such/dir/f.stl"});
    EXPECT_EQ(unwritable.exit_code, 1);
    EXPECT_NE(unwritable.err.find("/no/such/dir/f.stl"), std::string::npos) << unwritable.err;
}

// The demo itself (three processes) is tested in tests/demo; here only its command line.
TEST_F(KerfCli, DemoRefusesAnOutOfRangeTriangleCount) {
    const ProcessRun r = kerf({"demo", "--triangles", "10"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--triangles"), std::string::npos) << r.err;
}

}  // namespace
