#include "firmware_host/safety/force_safety.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace kerf::firmware_host {
namespace {

double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

SafetyLimits test_limits() {
    SafetyLimits l;
    l.peak_force_n = 8.0;
    l.continuous_force_n = 4.0;
    l.thermal_time_constant_s = 0.2;
    l.max_slew_n_per_s = 2000.0;
    l.ramp_in_s = 0.01;
    l.engage_threshold_n = 0.5;
    l.engage_quiet_ticks = 5;
    l.stale_ticks = 2;
    return l;
}

SafetyInput good(Vec3 f) {
    SafetyInput in;
    in.desired_force_n = f;
    in.read_status = DeviceStatus::kOk;
    in.flags.homed = true;
    return in;
}

// Engages with zero demand, then runs `ticks` at `f`; returns the last output.
Vec3 engage_and_hold(ForceSafety& s, Vec3 f, int ticks) {
    for (int i = 0; i < 10; ++i) s.step(good({0, 0, 0}));
    Vec3 out{};
    for (int i = 0; i < ticks; ++i) out = s.step(good(f));
    return out;
}

TEST(ForceSafety, ClampsAtPeakForceKeepingDirection) {
    ForceSafety s(test_limits());
    const Vec3 out = engage_and_hold(s, {30, -40, 0}, 30);  // |F| = 50 N
    EXPECT_NEAR(norm(out), 8.0, 1e-9);
    EXPECT_NEAR(out[0] / out[1], 30.0 / -40.0, 1e-9);
    EXPECT_TRUE(s.reasons() & kReasonPeakClamp);
}

TEST(ForceSafety, LimitsSustainedForceToTheContinuousRating) {
    ForceSafety s(test_limits());
    const Vec3 out = engage_and_hold(s, {0, 0, 8}, 2000);  // 2 s = 10 time constants at peak
    EXPECT_LE(norm(out), 4.0 + 1e-9);
    EXPECT_LE(s.thermal_state_n2(), 16.0 * 1.05);
    EXPECT_TRUE(s.reasons() & kReasonThermal);
}

TEST(ForceSafety, LimitsTheSlewRate) {
    SafetyLimits l = test_limits();
    l.ramp_in_s = 0;
    ForceSafety s(l);
    engage_and_hold(s, {0, 0, 0}, 1);
    const Vec3 a = s.step(good({0, 0, 8}));
    EXPECT_NEAR(norm(a), 2.0, 1e-9);  // 2000 N/s * 1 ms
    EXPECT_TRUE(s.reasons() & kReasonSlew);
}

TEST(ForceSafety, RampsInAfterEngaging) {
    SafetyLimits l = test_limits();
    l.ramp_in_s = 0.1;
    l.max_slew_n_per_s = 1e9;
    ForceSafety s(l);
    const Vec3 out = engage_and_hold(s, {0, 0, 4}, 10);
    EXPECT_NEAR(norm(out), 4.0 * 16 * 0.001 / 0.1,
                1e-9);  // engaged on quiet tick 5: 6 + 10 ramp steps
    EXPECT_TRUE(s.reasons() & kReasonRamping);
}

TEST(ForceSafety, EngagesOnlyAfterTheDemandWasSmallForSomeTicks) {
    ForceSafety s(test_limits());
    for (int i = 0; i < 50; ++i) EXPECT_EQ(norm(s.step(good({0, 0, 3}))), 0.0);
    EXPECT_FALSE(s.engaged());
    for (int i = 0; i < 5; ++i) s.step(good({0, 0, 0.1}));
    EXPECT_TRUE(s.engaged());
}

TEST(ForceSafety, ZeroesForceWhenInputGoesStaleForTwoTicks) {
    ForceSafety s(test_limits());
    engage_and_hold(s, {0, 0, 3}, 50);
    SafetyInput stale = good({0, 0, 3});
    stale.read_status = DeviceStatus::kNoData;
    EXPECT_GT(norm(s.step(stale)), 0.0);  // one missed sample is tolerated
    EXPECT_EQ(norm(s.step(stale)), 0.0);
    EXPECT_TRUE(s.reasons() & kReasonStale);
}

TEST(ForceSafety, ZeroesForceAtOnceOnEveryHardFault) {
    auto check = [](auto mutate, std::uint32_t reason) {
        ForceSafety s(test_limits());
        engage_and_hold(s, {0, 0, 3}, 50);
        SafetyInput in = good({0, 0, 3});
        mutate(in);
        EXPECT_EQ(norm(s.step(in)), 0.0) << reason;
        EXPECT_TRUE(s.reasons() & reason) << reason;
        EXPECT_FALSE(s.engaged());
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    check([&](SafetyInput& in) { in.desired_force_n[1] = nan; }, kReasonNonFinite);
    check([](SafetyInput& in) { in.desired_force_n[0] = INFINITY; }, kReasonNonFinite);
    check([](SafetyInput& in) { in.flags.estop = true; }, kReasonEStop);
    check([](SafetyInput& in) { in.flags.watchdog_tripped = true; }, kReasonDeviceFault);
    check([](SafetyInput& in) { in.flags.encoder_fault = true; }, kReasonDeviceFault);
    check([](SafetyInput& in) { in.read_status = DeviceStatus::kDisconnected; },
          kReasonDisconnected);
    check([](SafetyInput& in) { in.read_status = DeviceStatus::kMalformed; }, kReasonInvalidInput);
    check([](SafetyInput& in) { in.flags.homed = false; }, kReasonNotHomed);
}

TEST(ForceSafety, RecoversThroughRampInWhenTheFaultClears) {
    ForceSafety s(test_limits());
    engage_and_hold(s, {0, 0, 3}, 50);
    SafetyInput fault = good({0, 0, 3});
    fault.flags.estop = true;
    s.step(fault);
    // Demand still large: stays at zero until it has been small for the quiet ticks.
    EXPECT_EQ(norm(s.step(good({0, 0, 3}))), 0.0);
    const Vec3 out = engage_and_hold(s, {0, 0, 3}, 100);
    EXPECT_NEAR(norm(out), 3.0, 1e-9);
}

// A lone late sample (or a short run of them, or a garbled report) while the user keeps pushing:
// zero force within 2 ticks, then force resumes from zero with the ramp after
// resume_fresh_ticks fresh samples, the demand never having gone quiet.
TEST(ForceSafety, ResumesAfterATransientStaleRunWithoutWaitingForAQuietHand) {
    for (const DeviceStatus bad : {DeviceStatus::kNoData, DeviceStatus::kMalformed}) {
        ForceSafety s(test_limits());
        engage_and_hold(s, {0, 0, 3}, 50);
        SafetyInput late = good({0, 0, 3});
        late.read_status = bad;
        s.step(late);
        EXPECT_EQ(norm(s.step(late)), 0.0);  // zero within 2 ticks
        EXPECT_FALSE(s.engaged());
        const std::uint32_t resume = test_limits().resume_fresh_ticks;
        for (std::uint32_t i = 1; i < resume; ++i) {
            EXPECT_EQ(norm(s.step(good({0, 0, 3}))), 0.0) << "fresh tick " << i;
            EXPECT_TRUE(s.reasons() & kReasonWaitingToEngage);
        }
        const Vec3 first = s.step(good({0, 0, 3}));  // resumes: ramping in from zero
        EXPECT_TRUE(s.engaged());
        EXPECT_GT(norm(first), 0.0);
        EXPECT_LT(norm(first), 3.0);
        EXPECT_TRUE(s.reasons() & kReasonRamping);
        Vec3 out{};
        for (int i = 0; i < 50; ++i) out = s.step(good({0, 0, 3}));
        EXPECT_NEAR(norm(out), 3.0, 1e-9);
    }
}

// Fresh samples interleaved with late ones never resume force: the run must be unbroken.
TEST(ForceSafety, AResumeNeedsAnUnbrokenRunOfFreshSamples) {
    ForceSafety s(test_limits());
    engage_and_hold(s, {0, 0, 3}, 50);
    SafetyInput late = good({0, 0, 3});
    late.read_status = DeviceStatus::kNoData;
    s.step(late);
    s.step(late);
    for (int i = 0; i < 200; ++i) {
        const bool fresh = i % 5 != 4;  // every fifth sample late: 4 fresh in a row at most
        EXPECT_EQ(norm(s.step(fresh ? good({0, 0, 3}) : late)), 0.0) << i;
    }
}

// The loop's timing safe state (interrupt()) resumes the same way, from zero with the ramp.
TEST(ForceSafety, AnInterruptResumesFromZeroAfterFreshSamples) {
    ForceSafety s(test_limits());
    engage_and_hold(s, {0, 0, 3}, 50);
    s.interrupt();
    EXPECT_FALSE(s.engaged());
    Vec3 out{};
    for (std::uint32_t i = 0; i < test_limits().resume_fresh_ticks; ++i)
        out = s.step(good({0, 0, 3}));
    EXPECT_TRUE(s.engaged());
    EXPECT_GT(norm(out), 0.0);
    EXPECT_LE(norm(out), 3.0 * test_limits().period_s / test_limits().ramp_in_s + 1e-12);
}

// A hard fault is different: after an e-stop the user must let go before forces come back,
// however many fresh samples arrive; and a first engage always waits for a quiet demand.
TEST(ForceSafety, AfterAHardFaultOrAtTheFirstEngageForceWaitsForAQuietDemand) {
    ForceSafety s(test_limits());
    for (int i = 0; i < 100; ++i) EXPECT_EQ(norm(s.step(good({0, 0, 3}))), 0.0);
    engage_and_hold(s, {0, 0, 3}, 50);
    SafetyInput fault = good({0, 0, 3});
    fault.flags.estop = true;
    s.step(fault);
    SafetyInput late = good({0, 0, 3});
    late.read_status = DeviceStatus::kNoData;
    s.step(late);  // a stale sample after the e-stop does not turn it into a transient
    s.step(late);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(norm(s.step(good({0, 0, 3}))), 0.0) << i;
    EXPECT_NEAR(norm(engage_and_hold(s, {0, 0, 3}, 100)), 3.0, 1e-9);
}

// Property: random and adversarial demands and faults never exceed the peak, and between two
// ticks without a hard fault the output never moves faster than the slew limit.
TEST(ForceSafetyProperty, RandomAndAdversarialInputsNeverExceedLimitsOrSlew) {
    const SafetyLimits l = test_limits();
    ForceSafety s(l);
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double specials[] = {0.0,      -0.0,      1e308, -1e308, 4.9e-324,
                               INFINITY, -INFINITY, NAN,   8.0,    -8.0000001};
    Vec3 prev{};
    const double max_step = l.max_slew_n_per_s * l.period_s + 1e-9;
    for (int tick = 0; tick < 200000; ++tick) {
        SafetyInput in = good({});
        const int mode = static_cast<int>(rng() % 10);
        for (auto& c : in.desired_force_n) {
            c = mode < 4 ? u(rng) * 20.0 : mode < 7 ? u(rng) * 1e6 : specials[rng() % 10];
        }
        if (rng() % 50 == 0) in.read_status = static_cast<DeviceStatus>(rng() % 5);
        if (rng() % 200 == 0) in.flags.estop = true;
        if (rng() % 300 == 0) in.flags.homed = false;
        const Vec3 out = s.step(in);
        ASSERT_TRUE(std::isfinite(out[0]) && std::isfinite(out[1]) && std::isfinite(out[2]));
        ASSERT_LE(norm(out), l.peak_force_n + 1e-9) << "tick " << tick;
        const bool zeroed_by_fault = (s.reasons() & 0x7FU) != 0;
        if (!zeroed_by_fault) {
            const Vec3 d = {out[0] - prev[0], out[1] - prev[1], out[2] - prev[2]};
            ASSERT_LE(norm(d), max_step) << "tick " << tick;
        } else {
            ASSERT_EQ(norm(out), 0.0);
        }
        ASSERT_LE(s.thermal_state_n2(), l.peak_force_n * l.peak_force_n + 1e-9);
        prev = out;
    }
}

}  // namespace
}  // namespace kerf::firmware_host
