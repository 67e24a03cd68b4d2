// Every TOML file shipped in config/ loads, and carries the values other modules rely on.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "config/load_config.hpp"

namespace kerf::config {
namespace {

namespace fs = std::filesystem;

const fs::path kConfigDir = fs::path(KERF_SOURCE_DIR) / "config";

std::vector<fs::path> toml_files(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".toml") out.push_back(entry.path());
    return out;
}

TEST(ShippedConfig, EveryDeviceProfileLoads) {
    auto files = toml_files(kConfigDir / "devices");
    ASSERT_GE(files.size(), 3u);
    for (const auto& f : files) {
        auto p = load_device_profile(f);
        EXPECT_TRUE(p) << (p ? "" : p.error().message());
    }
}

TEST(ShippedConfig, EveryForceProfileLoadsAndValidates) {
    auto files = toml_files(kConfigDir / "force");
    ASSERT_GE(files.size(), 2u);
    for (const auto& f : files) {
        auto p = load_force_profile(f);
        ASSERT_TRUE(p) << p.error().message();
        EXPECT_TRUE(validate_force_profile(*p).empty()) << f;
        EXPECT_EQ(p->name, f.stem().string());
    }
}

TEST(ShippedConfig, EverySceneLoads) {
    auto files = toml_files(kConfigDir / "scenes");
    ASSERT_GE(files.size(), 2u);
    for (const auto& f : files) {
        auto s = load_scene(f);
        ASSERT_TRUE(s) << s.error().message();
        EXPECT_EQ(s->name, f.stem().string());
        EXPECT_FALSE(s->bodies.empty());
    }
}

TEST(ShippedConfig, KerfTomlLoadsWithEveryProfileItNames) {
    auto c = load_config(kConfigDir / "kerf.toml");
    ASSERT_TRUE(c) << c.error().message();
    EXPECT_EQ(c->main.realtime.period_ns, 1'000'000);
    EXPECT_EQ(c->main.realtime.policy, SchedPolicy::kFifo);
    EXPECT_EQ(c->main.display.mode, DisplayMode::kHeadless);
    EXPECT_EQ(c->device.kind, DeviceKind::kSimulated);
    EXPECT_EQ(c->scene.bodies.at(0).mesh.kind, MeshSourceKind::kBuiltinFoot);
    EXPECT_EQ(c->config_dir, kConfigDir.lexically_normal());
    EXPECT_TRUE(c->journal_dir.is_absolute());
}

TEST(ShippedConfig, FalconProfileCarriesTheLibnifalconFacts) {
    auto p = load_device_profile(kConfigDir / "devices" / "falcon.toml");
    ASSERT_TRUE(p) << p.error().message();
    EXPECT_EQ(p->kind, DeviceKind::kFalcon);
    EXPECT_EQ(p->ids.vendor_id, 0x0403);
    EXPECT_EQ(p->ids.product_id, 0xCB48);
    EXPECT_EQ(p->reporting_space, ReportingSpace::kJoint);
    EXPECT_EQ(p->kinematic_model, KinematicModel::kFalconDelta);
    EXPECT_DOUBLE_EQ(p->falcon_delta.a_m, 0.060);
    EXPECT_DOUBLE_EQ(p->falcon_delta.b_m, 0.1025);
    EXPECT_DOUBLE_EQ(p->falcon_delta.f_m, -0.025);
    EXPECT_EQ(p->encoder.counts_per_rev, 1280u);
    EXPECT_DOUBLE_EQ(p->limits.peak_force_n, 8.9);
    EXPECT_LE(p->limits.continuous_force_n, p->limits.peak_force_n);
    EXPECT_EQ(p->motor.command_limit, 32767);
}

}  // namespace
}  // namespace kerf::config
