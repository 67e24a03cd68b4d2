// The CI soak: `kerf soak --duration 120` with every fault on the real processes (kerf-hapsim,
// kerf-rt, kerf-display headless) — every fault injected at least once, every check passed, the
// report, summary and plots written, nothing left behind.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;

// The check is on kerf-rt's RssAnon. Since kerf-rt allocates from one malloc arena it stays flat
// after warm-up (0.00 % in 2-minute foot rounds and in 20 shared-mesh rounds); before, the world
// builder thread's own arena grew 0.6-2.3 % inside a round. 1 % is kerf soak's default; CI keeps
// 2 % as margin.
constexpr const char* kRtGrowthLimitPct = "2";

TEST(KerfSoak, TwoMinutesOfFaultsPassEveryCheck) {
    const fs::path dir = fs::temp_directory_path() / ("kerf-soak-test-" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    setenv("KERF_SHARED_MESHES", KERF_SHARED_MESHES, 0);
    const auto run = kerf::test::run_program(
        dir, "kerf",
        {"soak", "--duration", "120", "--faults", "all", "--rt-growth-limit-pct", kRtGrowthLimitPct,
         "--seed", "1", "-o", (dir / "out").string()},
        std::chrono::seconds(600));
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
    EXPECT_NE(run.out.find("kerf soak: PASSED"), std::string::npos) << run.out;

    const auto report = nlohmann::json::parse(kerf::test::slurp(dir / "out" / "report.json"));
    EXPECT_TRUE(report["passed"].get<bool>()) << report["failures"].dump();
    EXPECT_GE(report["rounds"].size(), 2u);
    EXPECT_GT(report["events"].get<std::uint64_t>(), 0u);
    EXPECT_GT(report["cut_begins"].get<std::uint64_t>(), 0u);
    EXPECT_EQ(report["rounds_hash_equal"].get<std::size_t>(), report["rounds"].size());
    // Every fault of the list at least once; device faults checked against the telemetry.
    std::set<std::string> injected;
    for (const auto& [name, count] : report["faults_injected"].items())
        if (count.get<int>() > 0) injected.insert(name);
    for (const auto& name : report["faults"]) EXPECT_TRUE(injected.count(name)) << name;
    EXPECT_GT(report["device_faults_ok"].get<int>(), 0);
    EXPECT_EQ(report["device_faults_failed"].get<int>(), 0);
    EXPECT_GT(report["ticks"].get<std::uint64_t>(), 60'000u);
    EXPECT_GT(report["wake_p50_us"].get<double>(), 0);
    for (const char* png : {"wake-latency.png", "force-penetration.png", "memory.png"}) {
        const std::string bytes = kerf::test::slurp(dir / "out" / png);
        ASSERT_GT(bytes.size(), 1000u) << png;
        EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
    }
    EXPECT_FALSE(kerf::test::slurp(dir / "out" / "summary.txt").empty());
    EXPECT_TRUE(fs::exists(dir / "out" / "rounds" / "0" / "session.kjournal"));
    fs::remove_all(dir);
}

}  // namespace
