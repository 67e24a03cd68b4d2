// `cmake --install` into a temporary prefix, then the installed `kerf demo` run from another
// folder: the executables find each other and the installed data (share/kerf), not the source
// tree's, and the three-process demo works.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;

/// Runs `argv` in `cwd` without $KERF_DATA_DIR, stdout+stderr into `log`; returns the exit code.
int run_in(const fs::path& cwd, std::vector<std::string> argv, const fs::path& log) {
    const pid_t pid = fork();
    if (pid == 0) {
        if (chdir(cwd.c_str()) != 0) _exit(126);
        unsetenv("KERF_DATA_DIR");
        if (!std::freopen(log.c_str(), "w", stdout)) _exit(126);
        dup2(fileno(stdout), 2);
        std::vector<char*> args;
        for (std::string& a : argv) args.push_back(a.data());
        args.push_back(nullptr);
        execv(args[0], args.data());
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(KerfInstall, InstalledDemoRunsFromAnotherFolderOnInstalledData) {
    if (access(KERF_BIN_DIR "/kerf-rt", X_OK) != 0) GTEST_SKIP() << "no kerf-rt built";
    const fs::path root =
        fs::temp_directory_path() / ("kerf-install-test-" + std::to_string(getpid()));
    const fs::path prefix = root / "prefix", elsewhere = root / "elsewhere";
    fs::create_directories(elsewhere);
    ASSERT_EQ(
        run_in(elsewhere, {KERF_CMAKE_COMMAND, "--install", KERF_BUILD_DIR, "--prefix", prefix},
               root / "install.log"),
        0)
        << kerf::test::slurp(root / "install.log");
    for (const char* f : {"bin/kerf", "bin/kerf-rt", "bin/kerf-display", "bin/kerf-hapsim"})
        EXPECT_EQ(access((prefix / f).c_str(), X_OK), 0) << f;
    for (const char* f : {"share/kerf/kerf.toml", "share/kerf/devices/simulated.toml",
                          "share/kerf/devices/falcon.toml", "share/kerf/force/default.toml",
                          "share/kerf/scenes/builtin_foot.toml",
                          "lib/udev/rules.d/70-kerf-haptics.rules", "share/doc/kerf/README.md"})
        EXPECT_TRUE(fs::is_regular_file(prefix / f)) << f;

    const int rc = run_in(elsewhere,
                          {(prefix / "bin/kerf").string(), "demo", "--lockstep", "--triangles",
                           "20000", "--json", "-o", "out"},
                          root / "demo.log");
    const std::string log = kerf::test::slurp(root / "demo.log");
    ASSERT_EQ(rc, 0) << log;
    const auto report =
        nlohmann::json::parse(kerf::test::slurp(elsewhere / "out/report.json"), nullptr, false);
    ASSERT_FALSE(report.is_discarded()) << log;
    EXPECT_EQ(report["config"], (prefix / "share/kerf/kerf.toml").string()) << log;
    EXPECT_EQ(report["hashes_equal"], true) << log;
    EXPECT_EQ(report["cuts_ended_otherwise"], 2) << log;  // the chevron's two withdrawn limbs
    EXPECT_EQ(report["bodies_after"], report["bodies_before"].get<int>() + 1) << log;
    EXPECT_TRUE(fs::is_regular_file(elsewhere / "out/3-after.png"));
    // `kerf devices` matches against the installed device profiles.
    EXPECT_EQ(run_in(elsewhere, {(prefix / "bin/kerf").string(), "devices"}, root / "dev.log"), 0);
    const std::string devices = kerf::test::slurp(root / "dev.log");
    EXPECT_NE(devices.find((prefix / "share/kerf/devices").string()), std::string::npos) << devices;
    std::error_code ec;
    fs::remove_all(root, ec);
}

}  // namespace
