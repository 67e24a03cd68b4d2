// kerf run, the kiosk form, with real processes (kerf-hapsim, kerf-rt, kerf-display) in real
// time: the display SIGKILLed is restarted while kerf-rt keeps running (same pid); SIGTERM stops
// everything with exit 0 and leaves no process, socket or work folder; a session left by a
// SIGKILLed run is removed at the next start; the journal folder is pruned to its bound.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;
using kerf::test::slurp;
using Clock = std::chrono::steady_clock;

/// Pids whose command line holds `program` and `mark` (the session name).
std::vector<pid_t> pids_of(const std::string& program, const std::string& mark) {
    std::vector<pid_t> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc", ec)) {
        const std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::string cmd = slurp(e.path() / "cmdline");
        std::replace(cmd.begin(), cmd.end(), '\0', ' ');
        if (cmd.find(program) != std::string::npos && cmd.find(mark) != std::string::npos &&
            slurp(e.path() / "stat").find(") Z") == std::string::npos)
            out.push_back(pid_t(std::stol(name)));
    }
    return out;
}

/// Waits (at most 20 s) until every process of `pids` has finished exiting: gone, or a zombie
/// whose threads have all exited. A SIGKILLed process's leader turns zombie first; its files
/// (kerf-rt's listening session socket) are closed only when its last thread has exited, which
/// under load takes a while after kill() returned (a listener still there: "live session").
bool wait_gone(const std::vector<pid_t>& pids) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    for (const pid_t p : pids) {
        const fs::path stat = fs::path("/proc") / std::to_string(p) / "stat";
        while (true) {
            const std::string st = slurp(stat);
            std::size_t threads = 0;
            std::error_code ec;
            for (auto it = fs::directory_iterator(stat.parent_path() / "task", ec);
                 !ec && it != fs::directory_iterator(); it.increment(ec))
                ++threads;
            const bool dead =
                st.find(") Z") != std::string::npos || st.find(") X") != std::string::npos;
            if (st.empty() || (dead && threads <= 1)) break;
            if (std::chrono::steady_clock::now() > until) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    return true;
}

class KerfRun : public ::testing::Test {
protected:
    void SetUp() override {
        if (access(KERF_BIN_DIR "/kerf-rt", X_OK) != 0) GTEST_SKIP() << "no kerf-rt built";
        root_ = fs::temp_directory_path() / ("kerf-run-test-" + std::to_string(getpid()));
        fs::create_directories(root_ / "journal");
        // The runs' work folders go here, not /tmp: a `kerf run` started meanwhile by another
        // test removes the work folders of dead runs it finds (the one this test kills on purpose).
        tmp_ = root_ / "tmp";
        fs::create_directories(tmp_);
        runtime_ = root_ / "runtime";
        fs::create_directories(runtime_);
        fs::permissions(runtime_, fs::perms::owner_all);
        session_ = "kruntest" + std::to_string(getpid());
        // A small scene so the processes start quickly.
        fs::copy(fs::path(KERF_SOURCE_DIR) / "config", root_ / "config",
                 fs::copy_options::recursive);
        std::string scene = slurp(root_ / "config/scenes/builtin_foot.toml");
        const auto at = scene.find("target_triangles");
        scene.replace(at, scene.find('\n', at) - at, "target_triangles = 20000");
        std::ofstream(root_ / "config/scenes/builtin_foot.toml") << scene;
        std::string main = slurp(root_ / "config/kerf.toml");
        const auto files = main.find("max_files");
        main.replace(files, main.find('\n', files) - files, "max_files = 3");
        std::ofstream(root_ / "config/kerf.toml") << main;
    }
    void TearDown() override {
        if (pid_ > 0) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
        for (pid_t run : runs_)
            for (const char* p : {"kerf-rt", "kerf-display", "kerf-hapsim"})
                for (pid_t c : pids_of(p, mark(run))) kill(c, SIGKILL);
        std::error_code ec;
        if (!root_.empty()) fs::remove_all(root_, ec);
    }
    /// Starts `kerf run` (real time, the emulator); output into `log`.
    void start(const fs::path& log) {
        pid_ = fork();
        if (pid_ == 0) {
            setenv("KERF_RUNTIME_DIR", runtime_.c_str(), 1);
            setenv("TMPDIR", tmp_.c_str(), 1);
            if (!std::freopen(log.c_str(), "w", stdout)) _exit(126);
            dup2(fileno(stdout), 2);
            const std::string exe = KERF_BIN_DIR "/kerf";
            std::vector<std::string> args = {
                exe,         "run",    "--config",      (root_ / "config/kerf.toml").string(),
                "--session", session_, "--journal-dir", (root_ / "journal").string()};
            std::vector<char*> argv;
            for (auto& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            execv(exe.c_str(), argv.data());
            _exit(127);
        }
        runs_.push_back(pid_);
    }
    /// What the command lines of a run's children hold: its work folder TMPDIR/kerf-run-PID-*.
    static std::string mark(pid_t run) { return "kerf-run-" + std::to_string(run) + "-"; }
    /// Waits (up to `limit`) until `log` holds `text`.
    bool wait_for(const fs::path& log, const std::string& text,
                  std::chrono::seconds limit = std::chrono::seconds(120)) {
        const auto end = Clock::now() + limit;
        while (Clock::now() < end) {
            if (slurp(log).find(text) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return false;
    }
    int wait_exit(std::chrono::seconds limit = std::chrono::seconds(60)) {
        const auto end = Clock::now() + limit;
        int status = 0;
        while (waitpid(pid_, &status, WNOHANG) == 0) {
            if (Clock::now() > end) return -2;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    bool session_socket_exists() const { return fs::exists(runtime_ / session_ / "socket"); }

    fs::path root_, tmp_, runtime_;
    std::string session_;
    pid_t pid_ = -1;
    std::vector<pid_t> runs_;
};

TEST_F(KerfRun, DisplayKilledIsRestartedRtKeepsRunningSigtermLeavesNothing) {
    // Old journals beyond the bound (max_files = 3): pruned at start, oldest first.
    for (int i = 0; i < 6; ++i) {
        const fs::path j = root_ / "journal" / ("old" + std::to_string(i) + ".kjournal");
        std::ofstream(j) << std::string(1000, 'x');
        fs::last_write_time(j, fs::file_time_type::clock::now() - std::chrono::hours(10 - i));
    }
    const fs::path log = root_ / "run.log";
    start(log);
    const pid_t run = pid_;
    ASSERT_TRUE(wait_for(log, "kerf run: running")) << slurp(log);
    const std::vector<pid_t> rt = pids_of("kerf-rt", mark(run));
    const std::vector<pid_t> display = pids_of("kerf-display", mark(run));
    ASSERT_EQ(rt.size(), 1u) << slurp(log);
    ASSERT_EQ(display.size(), 1u) << slurp(log);
    EXPECT_TRUE(session_socket_exists());
    // Bound: the 3 newest old journals stay... until the session's own journal counts too.
    EXPECT_NE(slurp(log).find("journal: removed 3 old journals"), std::string::npos) << slurp(log);
    EXPECT_FALSE(fs::exists(root_ / "journal/old0.kjournal"));
    EXPECT_TRUE(fs::exists(root_ / "journal/old5.kjournal"));

    kill(display[0], SIGKILL);
    ASSERT_TRUE(wait_for(log, "kerf-display restarted (1)")) << slurp(log);
    const auto end = Clock::now() + std::chrono::seconds(60);
    std::vector<pid_t> again;
    while (Clock::now() < end && (again = pids_of("kerf-display", mark(run))).empty())
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_EQ(again.size(), 1u);
    EXPECT_NE(again[0], display[0]);
    EXPECT_EQ(pids_of("kerf-rt", mark(run)), rt) << "kerf-rt was restarted or died";

    kill(pid_, SIGTERM);
    const int rc = wait_exit();
    const std::string text = slurp(log);
    EXPECT_EQ(rc, 0) << text;
    EXPECT_NE(text.find("stopped by signal 15"), std::string::npos) << text;
    EXPECT_NE(text.find("kerf-rt summary"), std::string::npos) << text;  // stopped in order
    for (const char* p : {"kerf-rt", "kerf-display", "kerf-hapsim"})
        EXPECT_TRUE(pids_of(p, mark(run)).empty()) << p << " left running";
    EXPECT_FALSE(session_socket_exists());
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(tmp_, ec))
        EXPECT_NE(e.path().filename().string().rfind(mark(run), 0), 0u) << "work folder left";
    // The session's journal is on disk, and the bound still holds.
    int journals = 0;
    for (const auto& e : fs::directory_iterator(root_ / "journal"))
        journals += e.path().extension() == ".kjournal";
    EXPECT_EQ(journals, 3);
}

TEST_F(KerfRun, ASessionLeftByAKilledRunIsRemovedAtStart) {
    const fs::path first = root_ / "first.log";
    start(first);
    ASSERT_TRUE(wait_for(first, "kerf run: running")) << slurp(first);
    // Everything killed at once, nothing cleaned: the session socket and work folder stay.
    const pid_t run = pid_;
    kill(run, SIGKILL);
    waitpid(run, nullptr, 0);
    pid_ = -1;
    std::vector<pid_t> children;
    for (const char* p : {"kerf-rt", "kerf-display", "kerf-hapsim"})
        for (pid_t c : pids_of(p, mark(run))) children.push_back(c);
    for (const pid_t c : children) kill(c, SIGKILL);
    ASSERT_TRUE(wait_gone(children)) << "the killed children did not exit within 20 s";
    ASSERT_TRUE(session_socket_exists()) << "the killed run left no socket to clean";
    bool work_left = false;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(tmp_, ec))
        work_left |=
            e.path().filename().string().rfind("kerf-run-" + std::to_string(run) + "-", 0) == 0;
    EXPECT_TRUE(work_left);

    const fs::path second = root_ / "second.log";
    start(second);
    ASSERT_TRUE(wait_for(second, "kerf run: running")) << slurp(second);
    const std::string text = slurp(second);
    EXPECT_NE(text.find("removed stale session " + session_), std::string::npos) << text;
    EXPECT_NE(text.find("removed the work folder of a dead kerf run"), std::string::npos) << text;
    kill(pid_, SIGTERM);
    EXPECT_EQ(wait_exit(), 0) << slurp(second);
    for (const auto& e : fs::directory_iterator(tmp_, ec))
        EXPECT_NE(e.path().filename().string().rfind("kerf-run-" + std::to_string(run) + "-", 0),
                  0u);
}

}  // namespace
