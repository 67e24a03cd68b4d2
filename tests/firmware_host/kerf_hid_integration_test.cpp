// Host <-> kerf-hapsim as real processes, Kerf HID protocol over the Unix socket.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "firmware_host/device/kerf_hid_device.hpp"
#include "firmware_host/open/open_device.hpp"
#include "firmware_host/transport/socket_report_transport.hpp"
#include "tests/firmware_host/device_loop.hpp"
#include "tests/firmware_host/fault_check.hpp"
#include "tests/firmware_host/hapsim_process.hpp"

namespace kerf::firmware_host {
namespace {

using test::DeviceLoop;
using test::HapsimProcess;

std::unique_ptr<KerfHidDevice> open_kerf(const HapsimProcess& sim, std::uint16_t watchdog_ms = 10) {
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    if (!socket) {
        ADD_FAILURE() << socket.error().message();
        return nullptr;
    }
    KerfHidOptions options;
    options.expected_vendor_id = 0x1209;
    options.expected_product_id = 0x0001;
    options.watchdog_ms = watchdog_ms;
    auto dev =
        KerfHidDevice::open(std::make_unique<SocketReportTransport>(std::move(*socket)), options);
    if (!dev) {
        ADD_FAILURE() << dev.error().message();
        return nullptr;
    }
    return std::move(*dev);
}

// Runs until homed and the force loop is engaged and delivering `force_n` upward.
// (test::engage: count-and-survive, a late read on a loaded machine only delays it).
void home_and_engage(DeviceLoop& loop, double force_n = 2.0) { test::engage(loop, force_n); }

TEST(KerfHidIntegration, OpensReadsIdentityHomesAndEngages) {
    HapsimProcess sim({"--protocol", "kerf", "--serial", "KRF-TEST-7"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_kerf(sim);
    ASSERT_NE(dev, nullptr);
    EXPECT_EQ(std::string(dev->identity().serial.data()), "KRF-TEST-7");
    EXPECT_EQ(dev->mechanics().peak_force_centi_n, 1000);
    DeviceLoop loop(*dev);
    loop.tick();
    EXPECT_FALSE(loop.sample.flags.homed);  // no force before homing
    EXPECT_EQ(loop.force(), 0.0);
    home_and_engage(loop);
    EXPECT_TRUE(loop.sample.flags.amplifiers_on);
    EXPECT_EQ(dev->shutdown(1000), LinkStatus::kOk);
}

TEST(KerfHidIntegration, OpenFailsClearlyWhenTheProfileIdsDoNotMatch) {
    HapsimProcess sim({"--protocol", "kerf"});
    ASSERT_TRUE(sim.ready());
    auto socket = SeqpacketSocket::connect(sim.socket_path());
    ASSERT_TRUE(socket);
    KerfHidOptions options;
    options.expected_vendor_id = 0x0403;
    auto dev =
        KerfHidDevice::open(std::make_unique<SocketReportTransport>(std::move(*socket)), options);
    ASSERT_FALSE(dev);
    EXPECT_NE(dev.error().message().find("1209:0001"), std::string::npos) << dev.error().message();
}

TEST(KerfHidIntegration, ConnectingToAMissingEmulatorIsAClearError) {
    auto socket = SeqpacketSocket::connect(test::temp_path("nobody-listens.sock"));
    ASSERT_FALSE(socket);
    EXPECT_NE(socket.error().message().find("No such file"), std::string::npos)
        << socket.error().message();
}

struct TraceRow {
    double x, y, z;
};

std::vector<TraceRow> read_trace(const std::string& path) {
    std::vector<TraceRow> rows;
    std::ifstream f(path);
    std::string line;
    std::getline(f, line);  // header
    while (std::getline(f, line)) {
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream in(line);
        unsigned long long step;
        TraceRow r{};
        in >> step >> r.x >> r.y >> r.z;
        rows.push_back(r);
    }
    return rows;
}

// 10,000 lockstep ticks of scripted motion: every position the host decodes equals the
// emulator's true position within the encoder resolution (10 um quantum: half of it).
TEST(KerfHidIntegration, TenThousandTicksOfScriptedMotionMatchTheTruthWithinResolution) {
    const std::string script = test::temp_path("motion.csv");
    const std::string trace = test::temp_path("trace.csv");
    std::ofstream(script) << "move,0.02,0.0,0.01,2.0\nhold,0.5\nsweep,0.0,0.03,0.0,1.0,3.0\n"
                             "button,0,down\nmove,-0.03,-0.02,0.02,2.0\nbutton,0,up\nhold,0.5\n"
                             "sweep,0.01,0.01,0.01,2.0,2.5\n";
    HapsimProcess sim({"--protocol", "kerf", "--script", script, "--trace", trace});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_kerf(sim);
    ASSERT_NE(dev, nullptr);
    DeviceLoop loop(*dev);
    std::vector<std::pair<std::uint32_t, Vec3>> seen;
    seen.reserve(10000);
    bool pressed = false;
    for (int i = 0; i < 10000; ++i) {
        loop.tick_lockstep();  // sample i answers packet i, however late the emulator runs
        ASSERT_EQ(loop.status, DeviceStatus::kOk) << "tick " << i;
        seen.emplace_back(loop.sample.device_sequence, loop.sample.position_m);
        pressed = pressed || (loop.sample.buttons & 1U) != 0;
    }
    RecordProperty("late_reads", static_cast<int>(loop.late_reads));  // stalls waited out
    EXPECT_TRUE(pressed);
    ASSERT_EQ(sim.stop(), 0);
    const auto truth = read_trace(trace);
    ASSERT_GE(truth.size(), 10000U);
    double worst = 0, travelled = 0;
    for (std::size_t i = 0; i < seen.size(); ++i) {
        const auto& t = truth[i];  // the reply to host packet i is the state after step i + 1
        const Vec3& p = seen[i].second;
        worst = std::max({worst, std::abs(p[0] - t.x), std::abs(p[1] - t.y), std::abs(p[2] - t.z)});
        if (i > 0) travelled += std::abs(t.x - truth[i - 1].x) + std::abs(t.y - truth[i - 1].y);
    }
    EXPECT_LE(worst, 0.5e-5 + 1e-9);
    EXPECT_GT(travelled, 0.1);  // the hand really moved the device (metres of path)
}

TEST(KerfHidIntegration, OpenDeviceOpensTheSimulatedProfileThroughTheEmulator) {
    const std::string profile_path =
        std::string(KERF_SOURCE_DIR) + "/config/devices/simulated.toml";
    HapsimProcess sim({"--profile", profile_path, "--lockstep"});  // configured by the same file
    ASSERT_TRUE(sim.ready());
    auto profile = config::load_device_profile(std::string(KERF_SOURCE_DIR) +
                                               "/config/devices/simulated.toml");
    ASSERT_TRUE(profile) << profile.error().message();
    auto dev = open_device(*profile, {"", sim.socket_path(), ""});
    ASSERT_TRUE(dev) << dev.error().message();
    const auto& kerf = dynamic_cast<const KerfHidDevice&>(**dev);
    EXPECT_EQ(std::string(kerf.identity().serial.data()), profile->ids.serial);
    EXPECT_EQ(kerf.mechanics().peak_force_centi_n, std::lround(profile->limits.peak_force_n * 100));
    DeviceLoop loop(**dev);
    test::engage(loop);
}

// Real-time mode: the emulated device streams reports every millisecond on the wall clock and
// its watchdog trips when the host falls silent; the host sees the bit, commands zero, clears
// the latched fault and re-engages. (25 ms watchdog: loaded CI machines stall for 10 ms.)
TEST(KerfHidIntegration, RealTimeDeviceWatchdogTripsWhenTheHostFallsSilentAndRecovers) {
    HapsimProcess sim({"--protocol", "kerf", "--realtime"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_kerf(sim, 25);
    ASSERT_NE(dev, nullptr);
    DeviceLoop loop(*dev);
    test::engage(loop);
    ::usleep(100000);  // the host stalls for 100 ms: four watchdog periods
    bool tripped = false;
    for (int i = 0; i < 5 && !tripped; ++i) {
        loop.tick(5000);
        tripped = loop.sample.flags.watchdog_tripped;
    }
    ASSERT_TRUE(tripped);
    EXPECT_EQ(loop.force(), 0.0);
    test::engage(loop);  // clear-fault with a zero command, then ramp-in again
    EXPECT_FALSE(loop.sample.flags.watchdog_tripped);
}

struct FaultCase {
    const char* name;
    const char* on;
    const char* off;
    bool reconnect;
};

class KerfHidFault : public ::testing::TestWithParam<FaultCase> {};

// Every injected fault takes the host to zero force within 2 ticks; it recovers when cleared.
TEST_P(KerfHidFault, ZeroesForceWithinTwoTicksAndRecovers) {
    const auto& c = GetParam();
    HapsimProcess sim({"--protocol", "kerf"});
    ASSERT_TRUE(sim.ready()) << sim.output();
    auto dev = open_kerf(sim);
    ASSERT_NE(dev, nullptr);
    DeviceLoop loop(*dev);
    std::unique_ptr<KerfHidDevice> dev2;
    std::unique_ptr<DeviceLoop> loop2;
    auto reopen = [&]() -> DeviceLoop* {
        dev2 = open_kerf(sim);
        if (!dev2) return nullptr;
        loop2 = std::make_unique<DeviceLoop>(*dev2);
        return loop2.get();
    };
    test::check_fault(sim, loop, c.name, c.on, c.off,
                      c.reconnect ? std::function<DeviceLoop*()>(reopen) : nullptr);
}

INSTANTIATE_TEST_SUITE_P(AllFaults, KerfHidFault,
                         ::testing::Values(FaultCase{"drop", "on", "off", false},
                                           FaultCase{"delay", "50", "off", false},
                                           FaultCase{"corrupt", "on", "off", false},
                                           FaultCase{"short", "on", "off", false},
                                           FaultCase{"unplug", "on", "off", true},
                                           FaultCase{"stuck_encoder", "on", "off", false},
                                           FaultCase{"estop", "on", "off", false},
                                           FaultCase{"watchdog_trip", "on", "off", false}),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

}  // namespace
}  // namespace kerf::firmware_host
