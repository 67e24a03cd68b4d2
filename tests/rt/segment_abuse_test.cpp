// Nothing another process does to the session can change the loop: with a consumer stalled
// (SIGSTOP, its rings fill), a consumer SIGKILLed mid-run and a scribbler writing random bytes over
// the header, the slots, the rings and the mesh mailbox, the loop's force trace is bit-identical
// to a clean run's (both in lockstep with the same scripted hand on the same real bone).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include "tests/rt/rt_rig.hpp"

extern char** environ;

namespace kerf::rt {
namespace {

constexpr std::uint64_t kTicks = 20'000;
const char* kScript = "hold,0.05\nmove,0.0,-0.02,0.0,3.0\nmove,0.004,0.0,0.002,4.0\nhold,60\n";

pid_t spawn_peer(std::vector<std::string> args) {
    args.insert(args.begin(), std::string(KERF_BIN_DIR) + "/ipc_test_peer");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    if (posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

std::vector<TraceRow> run(test::Rig& rig, const std::function<void()>& meanwhile) {
    std::vector<TraceRow> trace(kTicks);
    RunOptions o;
    o.lockstep = true;
    o.max_ticks = kTicks;
    o.trace = trace;
    std::thread loop([&] { run_loop(rig.loop(), o); });
    if (meanwhile) meanwhile();
    loop.join();
    return trace;
}

TEST(RtSegmentAbuse, StalledKilledAndScribblingPeersChangeNothingInTheLoop) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    std::vector<TraceRow> clean, abused;
    {
        test::Rig rig({kScript, {}, 100'000, true});
        ASSERT_TRUE(rig.ok()) << rig.error();
        clean = run(rig, nullptr);
    }
    std::uint64_t rejected = 0;
    {
        test::Rig rig({kScript, {}, 100'000, true});
        ASSERT_TRUE(rig.ok()) << rig.error();
        const std::string name = rig.producer().segment_name();
        abused = run(rig, [&] {
            const pid_t stalled = spawn_peer({"consumer", "--name", name, "--out", "/dev/null",
                                              "--events", "1000000", "--tolerant"});
            const pid_t killed = spawn_peer({"consumer", "--name", name, "--out", "/dev/null",
                                             "--events", "1000000", "--tolerant"});
            const pid_t scribbler =
                spawn_peer({"scribbler", "--name", name, "--ms", "3000", "--seed", "7"});
            ASSERT_GT(stalled, 0);
            ASSERT_GT(killed, 0);
            ASSERT_GT(scribbler, 0);
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            kill(stalled, SIGSTOP);
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            kill(killed, SIGKILL);
            int status = 0;
            waitpid(killed, &status, 0);
            waitpid(scribbler, &status, 0);
            kill(stalled, SIGKILL);
            waitpid(stalled, &status, 0);
        });
        rejected = rig.builder().stats().rejected;
        EXPECT_EQ(rig.loop().stats().ticks, kTicks);
        EXPECT_EQ(rig.loop().stats().worlds_swapped, 1u);  // no scribbled mesh got in
        EXPECT_EQ(rig.loop().world_generation(), 0u);
    }
    int pushing = 0;
    for (const TraceRow& r : clean) pushing += r.force_n[1] > 0.1 ? 1 : 0;
    EXPECT_GT(pushing, 1000) << "the tool never pressed into the bone";
    ASSERT_EQ(clean.size(), abused.size());
    EXPECT_EQ(std::memcmp(clean.data(), abused.data(), clean.size() * sizeof(TraceRow)), 0)
        << "the force trace changed under abuse";
    std::printf("[ info ] mailbox generations refused during the scribble: %llu\n",
                static_cast<unsigned long long>(rejected));
}

}  // namespace
}  // namespace kerf::rt
