// Issue 9, items 1, 4 and 10 as a user meets them: the real `kerf` binary on real files, FIFOs and
// links to devices. No input may hang it or eat memory; no output may overwrite an input or leave
// a half-written or mixed set; machine output must parse as JSON.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "display/mesh/mesh_io.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;
using kerf::test::ProcessRun;

class SafeInputs : public ::testing::Test {
protected:
    void SetUp() override {
        char tmpl[] = "/tmp/kerf-safe-inputs-XXXXXX";
        dir_ = mkdtemp(tmpl);
        ASSERT_TRUE(kerf::mesh::save_mesh(kerf::mesh::make_uv_sphere(0.01, 2000), bone(),
                                          kerf::LengthUnit::kMillimetre));
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path bone() const { return dir_ / "bone.stl"; }
    ProcessRun kerf(std::vector<std::string> args,
                    std::chrono::seconds limit = std::chrono::seconds(30)) {
        return kerf::test::run_program(dir_, "kerf", std::move(args), limit);
    }
    std::string contents(const fs::path& p) { return kerf::test::slurp(p); }
    fs::path dir_;
};

TEST_F(SafeInputs, ALinkToDevZeroOrDevUrandomIsRefusedAtOnceWithExit1) {
    fs::create_symlink("/dev/zero", dir_ / "z.stl");
    fs::create_symlink("/dev/urandom", dir_ / "u.obj");
    for (const char* name : {"z.stl", "u.obj"}) {
        const ProcessRun r = kerf({"mesh", "info", (dir_ / name).string()});
        EXPECT_EQ(r.exit_code, 1) << name << ": " << r.err;  // not 134 (abort), not -2 (hang)
        EXPECT_NE(r.err.find("character device, not a regular file"), std::string::npos) << r.err;
    }
}

TEST_F(SafeInputs, AFifoNamedLikeAMeshIsRefusedNotWaitedOn) {
    ASSERT_EQ(mkfifo((dir_ / "f.stl").c_str(), 0600), 0);
    const ProcessRun r = kerf({"mesh", "info", (dir_ / "f.stl").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("FIFO"), std::string::npos) << r.err;
    const ProcessRun c = kerf({"cut", (dir_ / "f.stl").string(), "--plane", "0,0,0,0,0,1", "-o",
                               (dir_ / "o.stl").string()});
    EXPECT_EQ(c.exit_code, 1) << c.err;
}

TEST_F(SafeInputs, CutRefusesToOverwriteItsOwnInputAndLeavesItIntact) {
    fs::copy_file(bone(), dir_ / "x_1.stl");
    const std::string before = contents(dir_ / "x_1.stl");
    const ProcessRun r = kerf({"cut", (dir_ / "x_1.stl").string(), "--plane", "0,0,2,0,0,1", "-o",
                               (dir_ / "x.stl").string()});
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.err.find("is the input"), std::string::npos) << r.err;
    EXPECT_EQ(contents(dir_ / "x_1.stl"), before);
    EXPECT_FALSE(fs::exists(dir_ / "x_2.stl"));
}

TEST_F(SafeInputs, CutWritesAllPiecesOrNoneWhenOneTargetIsADirectory) {
    fs::copy_file(bone(), dir_ / "out_1.stl");  // an earlier result that must survive
    const std::string before = contents(dir_ / "out_1.stl");
    fs::create_directory(dir_ / "out_2.stl");
    const ProcessRun r =
        kerf({"cut", bone().string(), "--plane", "0,0,2,0,0,1", "-o", (dir_ / "out.stl").string()});
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.err.find("out_2.stl"), std::string::npos) << r.err;
    EXPECT_EQ(contents(dir_ / "out_1.stl"), before);
    for (const auto& e : fs::directory_iterator(dir_)) {
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
    }
}

TEST_F(SafeInputs, PiecesOfAnEarlierRunDoNotMixWithTheNewSet) {
    for (const char* stale : {"out_3.stl", "out_4.stl"}) fs::copy_file(bone(), dir_ / stale);
    fs::copy_file(bone(), dir_ / "out_10.txt");  // not a piece: another extension
    const ProcessRun r =
        kerf({"cut", bone().string(), "--plane", "0,0,2,0,0,1", "-o", (dir_ / "out.stl").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir_ / "out_1.stl"));
    EXPECT_TRUE(fs::exists(dir_ / "out_2.stl"));
    EXPECT_FALSE(fs::exists(dir_ / "out_3.stl"));
    EXPECT_FALSE(fs::exists(dir_ / "out_4.stl"));
    EXPECT_TRUE(fs::exists(dir_ / "out_10.txt"));
}

TEST_F(SafeInputs, CutJsonIsValidJsonWhateverThePathHolds) {
    const std::string out = (dir_ / "q\"x\\y.stl").string();
    const ProcessRun r =
        kerf({"cut", bone().string(), "--plane", "0,0,2,0,0,1", "-o", out, "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto doc = nlohmann::json::parse(r.out);  // throws (fails the test) on invalid JSON
    ASSERT_EQ(doc["pieces"].size(), 2u);
    EXPECT_EQ(doc["pieces"][0]["file"].get<std::string>(), (dir_ / "q\"x\\y_1.stl").string());
}

// Item 16: usage errors name what is wrong and exit 2; nothing wraps silently.
TEST_F(SafeInputs, UsageErrorsNameTheProblemAndExit2) {
    ProcessRun r = kerf({"frobnicate"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("unknown command 'frobnicate'"), std::string::npos) << r.err;
    const std::string out = (dir_ / "foot.stl").string();
    for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{
             {"--triangles", "-1"}, {"--seed", "-1"}, {"--seed", "18446744073709551616"}}) {
        r = kerf({"gen", "foot", option, value, "-o", out});
        EXPECT_EQ(r.exit_code, 2) << option << " " << value << ": " << r.err;
        EXPECT_NE(r.err.find("is not a whole number"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
    // A denormal is a number (it used to say "is not a number").
    r = kerf(
        {"cut", bone().string(), "--plane", "0,0,2,0,4e-320,1", "-o", (dir_ / "d.stl").string()});
    EXPECT_EQ(r.err.find("is not a number"), std::string::npos) << r.err;
}

// Item 12: `kerf devices` finds its profiles from any folder (it worked only at the repo root).
TEST_F(SafeInputs, DevicesFindsItsProfilesFromAnyFolder) {
    const fs::path before = fs::current_path();
    fs::current_path(dir_);  // the child inherits it: not the repository root
    const ProcessRun r = kerf({"devices"});
    fs::current_path(before);
    EXPECT_EQ(r.err.find("cannot read"), std::string::npos) << r.err;
    EXPECT_NE(r.exit_code, 2) << r.err;
    EXPECT_TRUE(r.out.find("devices/*.toml") != std::string::npos ||
                r.out.find("profile") != std::string::npos)
        << r.out;
}

// Item 10: `kerf demo --json` is one JSON document (it printed two).
TEST_F(SafeInputs, DemoJsonIsOneValidDocument) {
    const std::string out =
        (fs::temp_directory_path() / ("kdemo-json-" + std::to_string(getpid()))).string();
    const ProcessRun r = kerf({"demo", "--lockstep", "--triangles", "20000", "--json", "-o", out},
                              std::chrono::seconds(120));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto doc = nlohmann::json::parse(r.out);  // throws on a second document
    EXPECT_TRUE(doc.contains("hash"));
    EXPECT_TRUE(doc.contains("events"));
    std::error_code ec;
    fs::remove_all(out, ec);
}

}  // namespace
