// Host <-> kerf-hapsim as real processes, Novint Falcon protocol: FTDI set-up, firmware load
// from a generated dummy image (Kerf never ships the real one), homing, motion, faults.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "firmware_host/device/falcon_device.hpp"
#include "firmware_host/open/open_device.hpp"
#include "firmware_host/transport/socket_usb_link.hpp"
#include "tests/firmware_host/fault_check.hpp"

namespace kerf::firmware_host {
namespace {

using test::DeviceLoop;
using test::HapsimProcess;

std::string dummy_firmware(std::size_t bytes) {
    const std::string path = test::temp_path("dummy-firmware.bin");
    std::mt19937 rng(11);
    std::ofstream f(path, std::ios::binary);
    for (std::size_t i = 0; i < bytes; ++i) f.put(static_cast<char>(rng() & 0xFF));
    return path;
}

Result<std::unique_ptr<FalconDevice>, TransportError> open_falcon(const HapsimProcess& sim,
                                                                  const std::string& firmware) {
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    if (!socket) return Err{socket.error()};
    FalconOptions options;
    options.firmware_path = firmware;
    options.load.transfer_timeout_ms = 200;
    options.load.handshake_tries = 3;
    return FalconDevice::open(std::make_unique<SocketUsbLink>(std::move(*socket)), options);
}

TEST(FalconIntegration, LoadsFirmwareHomesAndEngages) {
    HapsimProcess sim({"--protocol", "falcon"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_falcon(sim, dummy_firmware(1000));  // 17 chunks, the last one short
    ASSERT_TRUE(dev) << dev.error().message();
    DeviceLoop loop(**dev);
    loop.tick();
    EXPECT_FALSE(loop.sample.flags.homed);
    EXPECT_EQ(loop.force(), 0.0);  // no force before all three axes report homed
    test::engage(loop);
    EXPECT_TRUE((*dev)->last_report().all_homed());
}

TEST(FalconIntegration, RealTimeModeStreamsPacketsHomesAndEngages) {
    HapsimProcess sim({"--protocol", "falcon", "--firmware-loaded", "--realtime"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_falcon(sim, "");
    ASSERT_TRUE(dev) << dev.error().message();
    DeviceLoop loop(**dev);
    test::engage(loop);
}

TEST(FalconIntegration, TheFalconProfileConfiguresEmulatorAndHostAlike) {
    const std::string profile_path = std::string(KERF_SOURCE_DIR) + "/config/devices/falcon.toml";
    HapsimProcess sim({"--profile", profile_path, "--firmware-loaded"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    EXPECT_NE(sim.output().find("protocol=falcon"), std::string::npos) << sim.output();
    auto profile = config::load_device_profile(profile_path);
    ASSERT_TRUE(profile) << profile.error().message();
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    ASSERT_TRUE(socket);
    FalconOptions options;
    options.geometry = delta_geometry_from(*profile);
    auto dev = FalconDevice::open(std::make_unique<SocketUsbLink>(std::move(*socket)), options);
    ASSERT_TRUE(dev) << dev.error().message();
    DeviceLoop loop(**dev);
    test::engage(loop);
}

TEST(FalconIntegration, EchoMismatchIsRetriedAndTheLoadSucceeds) {
    HapsimProcess sim({"--protocol", "falcon"});
    ASSERT_TRUE(sim.ready());
    ASSERT_TRUE(sim.command("fault echo_mismatch 2"));  // two bad echoes, the third load is clean
    auto dev = open_falcon(sim, dummy_firmware(300));
    ASSERT_TRUE(dev) << dev.error().message();
}

TEST(FalconIntegration, FirmwareLoadFailureIsAClearError) {
    HapsimProcess sim({"--protocol", "falcon"});
    ASSERT_TRUE(sim.ready());
    ASSERT_TRUE(sim.command("fault firmware_fail on"));
    auto dev = open_falcon(sim, dummy_firmware(300));
    ASSERT_FALSE(dev);
    const auto m = dev.error().message();
    EXPECT_NE(m.find("echoed back different bytes"), std::string::npos) << m;
    EXPECT_NE(m.find("at image offset 0"), std::string::npos) << m;
    EXPECT_NE(m.find("after 3 load attempts"), std::string::npos) << m;
}

TEST(FalconIntegration, MissingFirmwareFileIsAClearError) {
    HapsimProcess sim({"--protocol", "falcon"});
    ASSERT_TRUE(sim.ready());
    auto dev = open_falcon(sim, "/nonexistent/novint.bin");
    ASSERT_FALSE(dev);
    EXPECT_EQ(dev.error().code, TransportErrc::kFirmware);
    EXPECT_EQ(dev.error().message(),
              "/nonexistent/novint.bin: read falcon firmware: cannot read the firmware image: no "
              "such file (firmware)");
}

TEST(FalconIntegration, OpeningWithoutFirmwareSaysSo) {
    HapsimProcess sim({"--protocol", "falcon"});
    ASSERT_TRUE(sim.ready());
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    ASSERT_TRUE(socket);
    FalconOptions options;
    options.probe_timeout_ms = 50;
    auto dev = FalconDevice::open(std::make_unique<SocketUsbLink>(std::move(*socket)), options);
    ASSERT_FALSE(dev);
    EXPECT_NE(dev.error().message().find("firmware not loaded"), std::string::npos)
        << dev.error().message();
}

// Scripted motion: every host position (forward kinematics of the quantised encoder counts)
// lies within half an encoder count of the emulator's true position, mapped through the Jacobian.
TEST(FalconIntegration, ScriptedMotionMatchesTheTruthWithinEncoderResolution) {
    const std::string script = test::temp_path("falcon-motion.csv");
    const std::string trace = test::temp_path("falcon-trace.csv");
    std::ofstream(script)
        << "move,0.02,0.0,0.12,1.0\nsweep,0.0,0.02,0.0,1.0,2.0\nmove,-0.02,0.01,0.1,1.0\n";
    HapsimProcess sim(
        {"--protocol", "falcon", "--firmware-loaded", "--script", script, "--trace", trace});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_falcon(sim, "");
    ASSERT_TRUE(dev) << dev.error().message();
    falcon::DeltaKinematics kin{falcon::DeltaGeometry{}};
    DeviceLoop loop(**dev);
    std::vector<Vec3> seen;
    std::vector<falcon::Mat3> jac;
    std::vector<bool> homed;
    for (int i = 0; i < 4000; ++i) {
        loop.tick_lockstep();  // sample i answers packet i, however late the emulator runs
        ASSERT_EQ(loop.status, DeviceStatus::kOk) << "tick " << i;
        seen.push_back(loop.sample.position_m);
        homed.push_back(loop.sample.flags.homed);
        falcon::Mat3 j{};
        ASSERT_EQ(kin.jacobian((*dev)->joint_angles(), loop.sample.position_m, j),
                  falcon::KinematicsStatus::kOk);
        jac.push_back(j);
    }
    RecordProperty("late_reads", static_cast<int>(loop.late_reads));  // stalls waited out
    ASSERT_EQ(sim.stop(), 0);
    std::ifstream f(trace);
    std::string line;
    std::getline(f, line);
    const double half_count = kin.angle_rad(1) - kin.angle_rad(0);
    int compared = 0;
    for (std::size_t i = 0; i + 1 < seen.size() && std::getline(f, line); ++i) {
        // Row i is the state after step i + 1; tick i - 1 read it (the open probe took step 1).
        // Before homing the encoders are relative (offset), so only homed samples are compared.
        if (i < 1 || !homed[i - 1]) continue;
        ++compared;
        double step, x, y, z;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream(line) >> step >> x >> y >> z;
        const auto& p = seen[i - 1];
        const auto& j = jac[i - 1];
        const Vec3 truth = {x, y, z};
        for (int r = 0; r < 3; ++r) {
            const double bound =
                0.5 * half_count * (std::abs(j[r][0]) + std::abs(j[r][1]) + std::abs(j[r][2]));
            ASSERT_LE(std::abs(p[r] - truth[r]), bound * 1.01 + 1e-9)
                << "tick " << i << " axis " << r;
        }
    }
    EXPECT_GT(compared, 3900);
}

struct FaultCase {
    const char* name;
    const char* on;
    bool reconnect;
};

class FalconFault : public ::testing::TestWithParam<FaultCase> {};

TEST_P(FalconFault, ZeroesForceWithinTwoTicksAndRecovers) {
    const auto& c = GetParam();
    HapsimProcess sim({"--protocol", "falcon", "--firmware-loaded"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_falcon(sim, "");
    ASSERT_TRUE(dev) << dev.error().message();
    DeviceLoop loop(**dev);
    std::unique_ptr<FalconDevice> dev2;
    std::unique_ptr<DeviceLoop> loop2;
    auto reopen = [&]() -> DeviceLoop* {
        auto d = open_falcon(sim, "");
        if (!d) {
            ADD_FAILURE() << d.error().message();
            return nullptr;
        }
        dev2 = std::move(*d);
        loop2 = std::make_unique<DeviceLoop>(*dev2);
        return loop2.get();
    };
    test::check_fault(sim, loop, c.name, c.on, "off",
                      c.reconnect ? std::function<DeviceLoop*()>(reopen) : nullptr);
}

INSTANTIATE_TEST_SUITE_P(TransportFaults, FalconFault,
                         ::testing::Values(FaultCase{"drop", "on", false},
                                           FaultCase{"delay", "50", false},
                                           FaultCase{"corrupt", "on", false},
                                           FaultCase{"short", "on", false},
                                           FaultCase{"unplug", "on", true}),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

}  // namespace
}  // namespace kerf::firmware_host
