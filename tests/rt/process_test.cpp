// kerf-rt and kerf-hapsim as real processes: determinism in lockstep, survival in real time on
// this machine's stalls, orderly stop on SIGTERM, refusal under require_realtime, the live force
// profile (file watch + SIGHUP, a bad file refused with file:line and the old profile kept).
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/session_socket.hpp"
#include "tests/firmware_host/hapsim_process.hpp"
#include "tests/rt/rt_process_support.hpp"
#include "tests/rt/rt_rig.hpp"

namespace kerf::rt {
namespace {

using firmware_host::test::HapsimProcess;

const char* kCutScript =
    "hold,0.05\nmove,0.0,-0.015,0.0,1.0\nbutton,0,down\nmove,0.0,-0.03,0.0,1.5\n"
    "move,0.0,0.0,0.0,1.0\nbutton,0,up\nhold,30\n";

std::string slurp(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/// The number after `key` in kerf-rt's summary ("ticks 3000," -> 3000), or -1.
long long summary_value(const std::string& out, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex(key + " ([0-9]+)"))) return -1;
    return std::stoll(m[1]);
}

std::string lockstep_trace(const test::TempConfig& cfg, const std::string& stem) {
    HapsimProcess sim({"--protocol", "kerf", "--script", test::write_script(stem, kCutScript)});
    EXPECT_TRUE(sim.ready()) << sim.output();
    const std::string trace = firmware_host::test::temp_path(stem) + ".csv";
    test::RtProcess rt({"--config", cfg.kerf_toml(), "--socket", sim.socket_path(), "--lockstep",
                        "--duration", "4", "--session", test::unique_session(stem), "--trace",
                        trace});
    EXPECT_EQ(rt.wait(120'000), 0) << rt.output();
    EXPECT_EQ(summary_value(rt.output(), "ticks"), 4000) << rt.output();
    const std::string text = slurp(trace);
    std::filesystem::remove(trace);
    return text;
}

TEST(RtProcess, LockstepRunsGiveABitIdenticalForceTrace) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg;
    const std::string a = lockstep_trace(cfg, "det-a");
    const std::string b = lockstep_trace(cfg, "det-b");
    ASSERT_GT(a.size(), 4000u * 20);
    EXPECT_EQ(a, b) << "two lockstep runs with the same script differ";
    // The run really pressed on the bone: some ticks commanded a force.
    std::size_t nonzero = 0;
    std::istringstream lines(a);
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line)) nonzero += line.rfind(",0,0,0") == line.size() - 6 ? 0 : 1;
    EXPECT_GT(nonzero, 200u);
}

// Real time: 5 s against kerf-hapsim in real-time mode. This VM stalls a 1 kHz loop for 1-30 ms
// a few dozen times a minute: the loop must survive them (count, never assert on the maximum).
TEST(RtProcess, RealTimeLoopSurvivesThisMachinesStallsAndCountsThem) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg;
    HapsimProcess sim({"--protocol", "kerf", "--realtime", "--script",
                       test::write_script("rt-real", kCutScript)});
    ASSERT_TRUE(sim.ready()) << sim.output();
    test::RtProcess rt({"--config", cfg.kerf_toml(), "--socket", sim.socket_path(), "--duration",
                        "5", "--session", test::unique_session("real")});
    ASSERT_EQ(rt.wait(60'000), 0) << rt.output();
    const std::string out = rt.output();
    EXPECT_EQ(summary_value(out, "ticks"), 5000) << out;
    EXPECT_GE(summary_value(out, "late wakes"), 0) << out;
    EXPECT_NE(out.find("wake latency us: p50"), std::string::npos) << out;
    std::printf("[ info ] %s\n", out.substr(out.find("kerf-rt summary")).c_str());
}

TEST(RtProcess, SigtermZeroesForceClosesInOrderAndRemovesTheSegment) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg;
    HapsimProcess sim({"--protocol", "kerf", "--realtime", "--script",
                       test::write_script("rt-term", kCutScript)});
    ASSERT_TRUE(sim.ready()) << sim.output();
    const std::string session = test::unique_session("term");
    test::RtProcess rt(
        {"--config", cfg.kerf_toml(), "--socket", sim.socket_path(), "--session", session});
    ASSERT_TRUE(rt.wait_for_output("real-time report", 30'000)) << rt.output();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::string socket = ipc::session_socket_of(ipc::default_runtime_dir(), session);
    EXPECT_TRUE(std::filesystem::exists(socket)) << socket;
    rt.signal(SIGTERM);
    ASSERT_EQ(rt.wait(10'000), 0) << rt.output();
    EXPECT_FALSE(std::filesystem::exists(socket)) << "the session socket is left behind";
    EXPECT_NE(rt.output().find("kerf-rt summary"), std::string::npos) << rt.output();
}

TEST(RtProcess, RequireRealtimeRefusesToRunWhenARequestIsDenied) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg("calcaneus",
                         "cpu_affinity = [1000]\nrequire_realtime = true\n");  // no such CPU
    HapsimProcess sim({"--protocol", "kerf"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    test::RtProcess rt({"--config", cfg.kerf_toml(), "--socket", sim.socket_path(), "--lockstep",
                        "--duration", "1", "--session", test::unique_session("req")});
    EXPECT_EQ(rt.wait(30'000), 3) << rt.output();
    EXPECT_NE(rt.output().find("CPU affinity {1000}: Invalid argument"), std::string::npos)
        << rt.output();
    EXPECT_NE(rt.output().find("require_realtime"), std::string::npos) << rt.output();
}

void replace_in_file(const std::string& path, const std::string& from, const std::string& to) {
    std::string text = slurp(path);
    text.replace(text.find(from), from.size(), to);
    std::ofstream(path + ".new") << text;
    std::filesystem::rename(path + ".new", path);
}

/// Events of one type the consumer sees within `timeout_ms`.
int count_events(ipc::Consumer& c, ipc::EventType type, int want, int timeout_ms) {
    int n = 0;
    for (int waited = 0; waited < timeout_ms && n < want; waited += 5) {
        ipc::EventRecord r;
        while (c.try_next(r) == ipc::Poll::kEvent) n += r.header.type == type ? 1 : 0;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return n;
}

TEST(RtProcess, ForceProfileReloadsLiveAndABadFileIsRefusedWithItsLine) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg;
    HapsimProcess sim({"--protocol", "kerf", "--realtime"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    const std::string session = test::unique_session("reload");
    test::RtProcess rt(
        {"--config", cfg.kerf_toml(), "--socket", sim.socket_path(), "--session", session});
    ASSERT_TRUE(rt.wait_for_output("real-time report", 30'000)) << rt.output();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    auto consumer =
        ipc::ConsumerBuilder().segment_name(session).stale_after_ns(2'000'000'000).attach();
    ASSERT_TRUE(consumer) << consumer.error().message;

    // A rename onto the watched file: two values change -> two ParametersChanged events.
    replace_in_file(cfg.force_toml(), "stiffness_n_per_m = 1500.0", "stiffness_n_per_m = 1200.0");
    replace_in_file(cfg.force_toml(), "static_friction_n = 0.4", "static_friction_n = 0.5");
    EXPECT_EQ(count_events(*consumer, ipc::EventType::kParametersChanged, 2, 5000), 2);

    // A bad value: refused with file:line and key; the loop keeps running.
    replace_in_file(cfg.force_toml(), "damping_n_s_per_m = 2.0", "damping_n_s_per_m = -3.0");
    EXPECT_TRUE(rt.wait_for_output("force profile refused", 5000)) << rt.output();
    EXPECT_TRUE(rt.wait_for_output("default.toml:", 1000)) << rt.output();
    EXPECT_NE(rt.output().find("damping_n_s_per_m"), std::string::npos) << rt.output();

    // Fixed again, and SIGHUP asks explicitly: one more change.
    replace_in_file(cfg.force_toml(), "damping_n_s_per_m = -3.0", "damping_n_s_per_m = 3.0");
    rt.signal(SIGHUP);
    EXPECT_EQ(count_events(*consumer, ipc::EventType::kParametersChanged, 1, 5000), 1);
    rt.signal(SIGINT);
    EXPECT_EQ(rt.wait(10'000), 0) << rt.output();
    EXPECT_NE(rt.output().find("(refused 1)"), std::string::npos) << rt.output();
}

}  // namespace
}  // namespace kerf::rt
