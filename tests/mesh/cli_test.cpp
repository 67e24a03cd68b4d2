// `kerf mesh info`, `kerf gen foot` and `kerf demo` run as real processes (fork/exec).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
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
    EXPECT_EQ(r.err, "kerf mesh info: cannot load mesh: /no/such/bone.stl: io: no such file\n");
    EXPECT_TRUE(r.out.empty());
}

TEST_F(KerfCli, MeshInfoOnAMalformedFileNamesTheLine) {
    const fs::path bad = dir_ / "bad.obj";
    std::ofstream(bad) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    const ProcessRun r = kerf({"mesh", "info", bad.string()});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find(bad.string() + ":4: index_out_of_range"), std::string::npos) << r.err;
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
    EXPECT_EQ(std::count(info.out.begin(), info.out.end(), '{'),
              1 + 1 + 38);  // top, report, shells
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
