// Issue 9, items 4, 12 and 13 as a user meets them: every executable given a configuration, a
// device profile or a hand script that is a link to /dev/zero, a FIFO or a directory — at the top
// or referenced from kerf.toml — answers at once with the file's name and what it is, and exits
// non-zero; nothing hangs, aborts or eats memory. Real processes, real files.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;
using kerf::test::ProcessRun;

class ConfigInputs : public ::testing::Test {
protected:
    void SetUp() override {
        char tmpl[] = "/tmp/kerf-config-inputs-XXXXXX";
        dir_ = mkdtemp(tmpl);
    }
    void TearDown() override { fs::remove_all(dir_); }
    ProcessRun run(const std::string& program, std::vector<std::string> args) {
        return kerf::test::run_program(dir_, program, std::move(args), std::chrono::seconds(30));
    }
    /// A link to /dev/zero, a FIFO and a directory, each named `stem` + `extension`.
    struct Bad {
        fs::path path;
        const char* says;  ///< what the message must call it
    };
    std::vector<Bad> bad_files(const std::string& extension) {
        const fs::path zero = dir_ / ("zero" + extension), fifo = dir_ / ("fifo" + extension),
                       folder = dir_ / ("folder" + extension);
        fs::create_symlink("/dev/zero", zero);
        EXPECT_EQ(mkfifo(fifo.c_str(), 0600), 0);
        fs::create_directory(folder);
        return {{zero, "character device"}, {fifo, "FIFO"}, {folder, "directory"}};
    }
    /// A copy of the shipped configuration folder.
    fs::path copy_config() {
        const fs::path to = dir_ / "config";
        fs::copy(fs::path(KERF_SOURCE_DIR) / "config", to, fs::copy_options::recursive);
        return to;
    }
    fs::path dir_;
};

// A hang shows as -2, an abort as 134, bad_alloc eating memory as a kill: none of those, and the
// message names the file and what it is.
void expect_refused(const ProcessRun& r, const fs::path& path, const char* says,
                    const std::string& who) {
    EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << who << ": exit " << r.exit_code << "\n"
                                                      << r.err;
    EXPECT_NE(r.err.find(path.filename().string()), std::string::npos) << who << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << who << ": " << r.err;
}

TEST_F(ConfigInputs, EveryProgramRefusesAConfigProfileOrScriptThatIsNotARegularFile) {
    for (const Bad& b : bad_files(".toml")) {
        expect_refused(run("kerf-rt", {"--config", b.path.string()}), b.path, b.says, "kerf-rt");
        expect_refused(run("kerf-display", {"--config", b.path.string()}), b.path, b.says,
                       "kerf-display");
        expect_refused(
            run("kerf-hapsim", {"--socket", (dir_ / "s").string(), "--profile", b.path.string()}),
            b.path, b.says, "kerf-hapsim --profile");
        expect_refused(
            run("kerf", {"demo", "--config", b.path.string(), "-o", (dir_ / "demo-out").string()}),
            b.path, b.says, "kerf demo");
    }
    for (const Bad& b : bad_files(".csv")) {
        expect_refused(
            run("kerf-hapsim", {"--socket", (dir_ / "s").string(), "--script", b.path.string()}),
            b.path, b.says, "kerf-hapsim --script");
    }
    EXPECT_FALSE(fs::exists(dir_ / "s"));  // refused before anything listened
}

// The profiles kerf.toml names are read by the same rule: a FIFO or a /dev/zero link in the
// config folder is named by its path, not reported as a missing profile or waited on.
TEST_F(ConfigInputs, AProfileReferencedFromKerfTomlIsReadOnlyWhenItIsARegularFile) {
    const fs::path config = copy_config();
    fs::remove(config / "force" / "default.toml");
    ASSERT_EQ(mkfifo((config / "force" / "default.toml").c_str(), 0600), 0);
    ProcessRun r = run("kerf-rt", {"--config", (config / "kerf.toml").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("force/default.toml: cannot read: is a FIFO"), std::string::npos) << r.err;

    fs::remove(config / "force" / "default.toml");
    fs::copy_file(fs::path(KERF_SOURCE_DIR) / "config" / "force" / "default.toml",
                  config / "force" / "default.toml");
    fs::remove(config / "devices" / "simulated.toml");
    fs::create_symlink("/dev/zero", config / "devices" / "simulated.toml");
    r = run("kerf-display", {"--config", (config / "kerf.toml").string()});
    EXPECT_NE(r.exit_code, 0) << r.err;
    EXPECT_LT(r.exit_code, 128) << r.err;
    EXPECT_NE(r.err.find("devices/simulated.toml: cannot read: is a character device"),
              std::string::npos)
        << r.err;
}

// `kerf devices` reads every profile of its folder the same way.
TEST_F(ConfigInputs, DevicesRefusesAProfileFolderHoldingAFifo) {
    const fs::path devices = dir_ / "devices";
    fs::create_directory(devices);
    ASSERT_EQ(mkfifo((devices / "stuck.toml").c_str(), 0600), 0);
    const ProcessRun r = run("kerf", {"devices", "--devices-dir", devices.string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("stuck.toml: cannot read: is a FIFO"), std::string::npos) << r.err;
}

// Item 12: a folder without profiles says so (it said "config/devices/*.toml" whatever the folder);
// an empty --devices-dir is a usage error, not the default folder in disguise.
TEST_F(ConfigInputs, DevicesSaysWhichFolderItSearchedAndThatItHeldNoProfile) {
    const fs::path devices = dir_ / "no-profiles";
    fs::create_directory(devices);
    ProcessRun r = run("kerf", {"devices", "--devices-dir", devices.string()});
    if (r.exit_code == 1 && r.out.empty()) GTEST_SKIP() << "no USB/HID backend here: " << r.err;
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.find("config/devices"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("no Kerf HID profile in " + devices.string()), std::string::npos) << r.out;

    r = run("kerf", {"devices", "--devices-dir", ""});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--devices-dir: an empty path"), std::string::npos) << r.err;
}

// Item 10: `kerf devices --json` is one document a parser accepts, whatever the folder's name.
TEST_F(ConfigInputs, DevicesJsonIsOneValidDocumentWhateverTheFolderIsCalled) {
    const fs::path devices = dir_ / "q\"x\\y";
    fs::copy(fs::path(KERF_SOURCE_DIR) / "config" / "devices", devices);
    const ProcessRun r = run("kerf", {"devices", "--devices-dir", devices.string(), "--json"});
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
    const auto doc = nlohmann::json::parse(r.out);  // throws (fails the test) on invalid JSON
    EXPECT_EQ(doc["devices_dir"].get<std::string>(), devices.string());
    EXPECT_TRUE(doc["devices"].is_array());
    EXPECT_TRUE(doc["errors"].is_array());
}

// Item 13: an unknown ${var} in a profile's socket_path is named at its line (it ended as
// "--socket is required"); an empty profile reports what is missing.
TEST_F(ConfigInputs, HapsimNamesABadSocketVariableAndAnEmptyProfile) {
    std::string text =
        kerf::test::slurp(fs::path(KERF_SOURCE_DIR) / "config/devices/simulated.toml");
    const std::string from = "${runtime}/kerf-hapsim.sock";
    text.replace(text.find(from), from.size(), "${nope}/kerf-hapsim.sock");
    std::ofstream(dir_ / "bad_var.toml") << text;
    ProcessRun r = run("kerf-hapsim", {"--profile", (dir_ / "bad_var.toml").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("bad_var.toml:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("emulator.socket_path"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("cannot expand ${nope}"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("--socket is required"), std::string::npos) << r.err;

    std::ofstream(dir_ / "empty.toml") << "# nothing here\n";
    r = run("kerf-hapsim", {"--profile", (dir_ / "empty.toml").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("missing key"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("holds no settings"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("falcon_delta"), std::string::npos) << r.err;
}

}  // namespace
