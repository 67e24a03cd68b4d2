// kerf soak's checks on made-up telemetry: each rule passes what it should and names what it
// should not.
#include "tools/kerf/soak_checks.hpp"

#include <gtest/gtest.h>

#include "firmware_host/safety/force_safety.hpp"
#include "rt_core/ipc/records.hpp"

namespace kerf::cli {
namespace {

constexpr std::uint64_t kMs = 1'000'000;

/// 1 kHz ticks from t = 0 for `n` ms, pushing `force` N.
std::vector<TickSample> ticks(std::size_t n, float force) {
    std::vector<TickSample> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        out[i].time_ns = i * kMs;
        out[i].tick = i;
        out[i].force_n = force;
    }
    return out;
}

/// Marks ticks [from, to) as seeing a stale device and commands `force` there.
void bad_from(std::vector<TickSample>& t, std::size_t from, std::size_t to, float force = 0) {
    for (std::size_t i = from; i < to; ++i) {
        t[i].safety_reasons = firmware_host::kReasonStale;
        t[i].force_n = force;
    }
}

TEST(SoakDeviceFaultCheck, ZeroForceWithinTwoTicksAndRecoveryPasses) {
    auto t = ticks(3000, 2.0f);
    bad_from(t, 1003, 1800);
    t[1003].force_n = 1.0f;  // the first bad tick may still push, and the next
    t[1004].force_n = 0.5f;
    const auto v = check_device_faults(t, {{SoakFault::kDrop, 1000 * kMs, 1790 * kMs}});
    ASSERT_EQ(v.size(), 1u);
    EXPECT_TRUE(v[0].ok()) << v[0].problem;
    EXPECT_TRUE(v[0].seen);
    EXPECT_TRUE(v[0].pushing);
    EXPECT_EQ(v[0].first_bad_tick, 1003u);
    EXPECT_EQ(v[0].ticks_to_zero, 2);
    EXPECT_TRUE(v[0].recovered);
    EXPECT_NEAR(v[0].recovery_s, 0.010, 1e-9);
}

TEST(SoakDeviceFaultCheck, ForceOnTheThirdBadTickFails) {
    auto t = ticks(3000, 2.0f);
    bad_from(t, 1000, 1800);
    for (std::size_t i = 1000; i < 1003; ++i) t[i].force_n = 1.0f;
    const auto v = check_device_faults(t, {{SoakFault::kCorrupt, 1000 * kMs, 1790 * kMs}});
    EXPECT_FALSE(v[0].ok());
    EXPECT_EQ(v[0].ticks_to_zero, 3);
    EXPECT_NE(v[0].problem.find("2 ticks"), std::string::npos) << v[0].problem;
}

TEST(SoakDeviceFaultCheck, ForceReturningWhileTheInputIsBadFails) {
    auto t = ticks(3000, 2.0f);
    bad_from(t, 1000, 1800);
    t[1500].force_n = 0.3f;
    const auto v = check_device_faults(t, {{SoakFault::kDelay, 1000 * kMs, 1790 * kMs}});
    EXPECT_EQ(v[0].nonzero_while_bad, 1u);
    EXPECT_FALSE(v[0].ok());
}

TEST(SoakDeviceFaultCheck, AFaultKerfRtNeverSawOrNeverLeftFails) {
    auto t = ticks(3000, 2.0f);
    auto v = check_device_faults(t, {{SoakFault::kEStop, 1000 * kMs, 1500 * kMs}});
    EXPECT_FALSE(v[0].seen);
    EXPECT_NE(v[0].problem.find("never saw"), std::string::npos);
    for (std::size_t i = 1000; i < 3000; ++i) {
        t[i].loop_flags = ipc::kLoopFlagDeviceFault;  // unplugged and never back
        t[i].force_n = 0;
    }
    v = check_device_faults(t, {{SoakFault::kUnplug, 1000 * kMs, 1500 * kMs}}, 1.0);
    EXPECT_TRUE(v[0].seen);
    EXPECT_FALSE(v[0].recovered);
    EXPECT_NE(v[0].problem.find("no recovery"), std::string::npos) << v[0].problem;
}

TEST(SoakDeviceFaultCheck, NoTelemetryAroundTheFaultIsUnverifiedNotFailed) {
    auto t = ticks(1000, 2.0f);
    const auto v = check_device_faults(t, {{SoakFault::kDrop, 2000 * kMs, 2500 * kMs}});
    EXPECT_FALSE(v[0].covered);
    EXPECT_TRUE(v[0].ok());
}

TEST(SoakForceCheck, CountsSamplesAboveTheLimit) {
    auto t = ticks(100, 7.9f);
    EXPECT_TRUE(check_force_limit(t, 8.0).ok());
    t[50].force_n = 8.2f;
    const ForceVerdict v = check_force_limit(t, 8.0);
    EXPECT_EQ(v.over, 1u);
    EXPECT_FLOAT_EQ(float(v.peak_n), 8.2f);
}

TEST(SoakSequenceCheck, EqualSequencesPassAndTheFirstDifferenceIsNamed) {
    std::vector<SeenEvent> journal;
    for (std::uint64_t i = 0; i < 10; ++i) journal.push_back({i, std::uint32_t(i * 7), 2});
    EXPECT_TRUE(compare_sequences(journal, journal).ok());
    auto other = journal;
    other[4].checksum ^= 1;
    EXPECT_EQ(compare_sequences(journal, other).first_difference, 4);
    other = journal;
    other.pop_back();
    EXPECT_EQ(compare_sequences(journal, other).first_difference, 9);
    EXPECT_FALSE(compare_sequences(journal, other).ok());
}

TEST(SoakMemoryCheck, GrowthIsTheEndAgainstTheWarmedUpValue) {
    std::vector<double> t;
    std::vector<std::uint64_t> kb;
    for (int i = 0; i < 60; ++i) {
        t.push_back(i);
        kb.push_back(i < 10 ? 1000 + 100 * std::uint64_t(i) : 10'000 + std::uint64_t(i - 10));
    }
    const MemoryVerdict v = memory_growth(t, kb, 20);
    ASSERT_TRUE(v.measured);
    EXPECT_EQ(v.warm_kb, 10'012u);
    EXPECT_EQ(v.end_kb, 10'047u);
    EXPECT_NEAR(v.growth_pct, 100.0 * 35 / 10'012, 1e-9);
    EXPECT_FALSE(memory_growth({0, 1}, {1, 2}, 20).measured);
}

}  // namespace
}  // namespace kerf::cli
