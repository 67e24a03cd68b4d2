// ChildProcess and Supervisor with real processes (/bin/sh scripts): start, exit status, stop
// with SIGTERM then SIGKILL, a stopped (SIGSTOP) child still stops, restart with back-off, an
// essential process ending ends the session, a stop signal ends it. Deadlines are generous (a
// loaded 2-core CI machine) and nothing asserts on how fast a process reacts.
#include "tools/supervise/supervisor.hpp"

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace kerf::supervise {
namespace {

using namespace std::chrono_literals;

ChildSpec shell(std::string name, std::string script, std::filesystem::path log = {}) {
    return ChildSpec{std::move(name), {"/bin/sh", "-c", std::move(script)}, std::move(log), {}};
}

std::filesystem::path temp_dir(const std::string& tag) {
    auto dir = std::filesystem::temp_directory_path() /
               ("kerf_supervise_" + tag + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(ChildProcess, ReportsTheExitCodeOfAProgramThatEnds) {
    auto child = ChildProcess::spawn(shell("three", "exit 3"));
    ASSERT_TRUE(child) << child.error().message();
    const auto& info = child->wait_for(60s);
    ASSERT_TRUE(info.has_value());
    EXPECT_TRUE(info->exited());
    EXPECT_EQ(info->exit_code(), 3);
    EXPECT_EQ(info->describe(), "exited 3");
    EXPECT_FALSE(child->running());
}

TEST(ChildProcess, RefusesAProgramThatDoesNotExistByName) {
    auto child = ChildProcess::spawn({"ghost", {"/nonexistent/kerf-ghost"}, {}, {}});
    ASSERT_FALSE(child);
    EXPECT_EQ(child.error().code, SpawnErrc::kNotExecutable);
    EXPECT_NE(child.error().message().find("/nonexistent/kerf-ghost"), std::string::npos);
}

TEST(ChildProcess, WritesItsOutputToTheLogFile) {
    const auto dir = temp_dir("log");
    auto child = ChildProcess::spawn(shell("echo", "echo hello; echo oops >&2", dir / "echo.log"));
    ASSERT_TRUE(child) << child.error().message();
    ASSERT_TRUE(child->wait_for(60s).has_value());
    std::ifstream in(dir / "echo.log");
    std::string all((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(all, "hello\noops\n");
    std::filesystem::remove_all(dir);
}

TEST(ChildProcess, StopEndsAProgramThatHonoursSigterm) {
    auto child = ChildProcess::spawn(shell("sleeper", "exec sleep 600"));
    ASSERT_TRUE(child);
    const ExitInfo info = child->stop(30s);
    EXPECT_FALSE(info.exited());
    EXPECT_EQ(info.term_signal(), SIGTERM);
}

TEST(ChildProcess, StopKillsAProgramThatIgnoresSigterm) {
    const auto dir = temp_dir("ignore");
    const auto flag = dir / "trapped";
    auto child = ChildProcess::spawn(
        shell("stubborn", "trap '' TERM; touch " + flag.string() + "; while :; do sleep 1; done"));
    ASSERT_TRUE(child);
    for (int i = 0; i < 6000 && !std::filesystem::exists(flag); ++i)
        std::this_thread::sleep_for(10ms);
    ASSERT_TRUE(std::filesystem::exists(flag));
    const ExitInfo info = child->stop(200ms);
    EXPECT_EQ(info.term_signal(), SIGKILL);
    std::filesystem::remove_all(dir);
}

TEST(ChildProcess, StopEndsAStoppedProgram) {
    auto child = ChildProcess::spawn(shell("frozen", "exec sleep 600"));
    ASSERT_TRUE(child);
    child->signal(SIGSTOP);
    const ExitInfo info = child->stop(30s);
    EXPECT_FALSE(info.exited());
    EXPECT_FALSE(child->running());
}

TEST(ChildProcess, DestructorLeavesNoProcessBehind) {
    pid_t pid = -1;
    {
        auto child = ChildProcess::spawn(shell("scoped", "exec sleep 600"));
        ASSERT_TRUE(child);
        pid = child->pid();
    }
    EXPECT_EQ(::kill(pid, 0), -1);  // reaped: no such process
}

TEST(Supervisor, AnEssentialProcessEndingEndsTheSession) {
    Supervisor sup;
    ASSERT_TRUE(sup.add({shell("forever", "exec sleep 600"), Policy::kEssential}));
    ASSERT_TRUE(sup.add({shell("quitter", "exit 4"), Policy::kEssential}));
    const RunOutcome out = sup.run([] { return false; });
    EXPECT_EQ(out.reason, RunOutcome::Reason::kProcessEnded);
    EXPECT_EQ(out.detail, "quitter exited 4");
    sup.stop_all();
    EXPECT_FALSE(sup.find("forever")->running());
}

TEST(Supervisor, RestartsARestartableProcessAndGoesOn) {
    const auto dir = temp_dir("restart");
    const auto count = dir / "starts";
    const auto lines = [&] {
        std::ifstream in(count);
        std::string all((std::istreambuf_iterator<char>(in)), {});
        for (const char c : all) EXPECT_TRUE(c == 'x' || c == '\n') << all;
        return static_cast<int>(std::count(all.begin(), all.end(), '\n'));
    };
    Supervisor sup;
    ASSERT_TRUE(
        sup.add({shell("display", "echo x >> " + count.string() + "; exit 1"), Policy::kRestart}));
    int told = 0;
    // Stop once three starts have written their line, not once the second restart was spawned: on
    // a loaded machine the third start may not have run its `echo` yet when the supervisor stops.
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    const RunOutcome out =
        sup.run([&] { return lines() >= 3 || std::chrono::steady_clock::now() > deadline; },
                [&](const std::string& name, int n) {
                    EXPECT_EQ(name, "display");
                    told = n;
                });
    EXPECT_TRUE(out.ok());
    const int restarts = sup.restarts("display");
    EXPECT_GE(restarts, 2);
    EXPECT_EQ(told, restarts);  // told of every restart, with its count
    sup.stop_all();
    // Every start writes one line, except possibly the last one, stopped before it ran `echo`.
    EXPECT_GE(lines(), 3);
    EXPECT_LE(lines(), restarts + 1);
    std::filesystem::remove_all(dir);
}

TEST(Supervisor, AFinishedJobIsNotAnError) {
    Supervisor sup;
    ASSERT_TRUE(sup.add({shell("job", "exit 0"), Policy::kMayFinish}));
    auto* job = sup.find("job");
    const RunOutcome out = sup.run([&] { return job->exit_info().has_value(); });
    EXPECT_TRUE(out.ok());
    EXPECT_TRUE(job->exit_info()->success());
}

TEST(Supervisor, AStopSignalEndsTheSessionAndStopsEveryone) {
    Supervisor sup;
    ASSERT_TRUE(sup.add({shell("a", "exec sleep 600"), Policy::kEssential}));
    ASSERT_TRUE(sup.add({shell("b", "exec sleep 600"), Policy::kRestart}));
    ::raise(SIGTERM);  // handled by the supervisor: a stop request, not our death
    const RunOutcome out = sup.run([] { return false; });
    EXPECT_EQ(out.reason, RunOutcome::Reason::kStopSignal);
    EXPECT_EQ(out.detail, "SIGTERM");
    sup.stop_all();
    EXPECT_FALSE(sup.find("a")->running());
    EXPECT_FALSE(sup.find("b")->running());
}

TEST(Supervisor, WaitsUntilAProcessIsReady) {
    const auto dir = temp_dir("ready");
    const auto flag = dir / "ready";
    Supervisor sup;
    auto started = sup.add(
        {shell("slow", "sleep 0.2; touch " + flag.string() + "; exec sleep 600"),
         Policy::kEssential},
        [&] { return std::filesystem::exists(flag); }, 120s);
    ASSERT_TRUE(started) << started.error().message();
    EXPECT_TRUE(std::filesystem::exists(flag));
    auto dead = sup.add(
        {shell("dies", "exit 7"), Policy::kEssential}, [] { return false; }, 120s);
    ASSERT_FALSE(dead);
    EXPECT_NE(dead.error().message().find("ended before it was ready (exited 7"),
              std::string::npos);
    sup.stop_all();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace kerf::supervise
