#include "firmware_host/open/open_device.hpp"

#include <gtest/gtest.h>

#include "firmware_host/falcon/delta_kinematics.hpp"

namespace kerf::firmware_host {
namespace {

config::DeviceProfile load(const char* name) {
    auto p = config::load_device_profile(std::string(KERF_SOURCE_DIR) + "/config/devices/" + name);
    EXPECT_TRUE(p) << p.error().message();
    return p ? *p : config::DeviceProfile{};
}

TEST(ProfileAdapter, FalconProfileGivesTheLibnifalconGeometry) {
    const auto g = delta_geometry_from(load("falcon.toml"));
    const falcon::DeltaGeometry reference;
    EXPECT_DOUBLE_EQ(g.a_m, reference.a_m);
    EXPECT_DOUBLE_EQ(g.b_m, reference.b_m);
    EXPECT_DOUBLE_EQ(g.r_m, reference.r_m);
    EXPECT_DOUBLE_EQ(g.s_m, reference.s_m);
    EXPECT_EQ(g.leg_angles_deg, reference.leg_angles_deg);
    EXPECT_DOUBLE_EQ(g.counts_per_rev, 1280.0);
    EXPECT_EQ(g.command_limit, 32767);
}

TEST(ProfileAdapter, SafetyLimitsTakeTheTighterOfDeviceAndForceProfile) {
    const auto device = load("falcon.toml");
    config::ForceProfile force;
    force.limits.max_force_n = 5.0;
    force.limits.slew_rate_n_per_s = 100000.0;
    force.limits.ramp_in_s = 0.3;
    force.limits.engage_threshold_n = 0.2;
    force.limits.engage_quiet_ticks = 7;
    const auto l = safety_limits_from(device, &force, 0.001);
    EXPECT_DOUBLE_EQ(l.peak_force_n, 5.0);
    EXPECT_DOUBLE_EQ(l.continuous_force_n, 4.0);
    EXPECT_DOUBLE_EQ(l.max_slew_n_per_s, device.limits.max_slew_n_per_s);
    EXPECT_DOUBLE_EQ(l.ramp_in_s, 0.3);
    EXPECT_EQ(l.engage_quiet_ticks, 7U);
    const auto device_only = safety_limits_from(device, nullptr, 0.001);
    EXPECT_DOUBLE_EQ(device_only.peak_force_n, 8.9);
}

TEST(ProfileAdapter, KerfHidOptionsCarryIdsAndWatchdog) {
    const auto o = kerf_hid_options_from(load("kerf_hid_reference.toml"));
    EXPECT_EQ(o.expected_vendor_id, 0x1209);
    EXPECT_EQ(o.expected_product_id, 0x0001);
    EXPECT_EQ(o.watchdog_ms, 10);
}

TEST(OpenDevice, AMissingEmulatorSocketIsAClearError) {
    auto p = load("simulated.toml");
    auto dev = open_device(p, {"", "/tmp/kerf-no-such-dir/none.sock", ""});
    ASSERT_FALSE(dev);
    EXPECT_NE(dev.error().message().find("/tmp/kerf-no-such-dir/none.sock"), std::string::npos)
        << dev.error().message();
}

}  // namespace
}  // namespace kerf::firmware_host
