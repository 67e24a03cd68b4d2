// Device profiles: per-kind rules (joint vs Cartesian fields, emulator only when simulated) and
// each kind of bad input.
#include "config/device_profile.hpp"

#include <gtest/gtest.h>

#include "tests/config/config_test_support.hpp"

namespace kerf::config {
namespace {

using test::edit;
using test::error_of;
using test::line_of;
using test::shipped;

const std::string kFalcon = shipped("devices/falcon.toml");
const std::string kSimulated = shipped("devices/simulated.toml");
const std::string kHid = shipped("devices/kerf_hid_reference.toml");

ConfigError parse_error(const std::string& text) {
    return error_of(parse_device_profile(text, "devices/test.toml"));
}

TEST(DeviceProfileParse, CartesianDevicesHaveNoJointFields) {
    auto p = parse_device_profile(kHid, "hid");
    ASSERT_TRUE(p) << p.error().message();
    EXPECT_EQ(p->kind, DeviceKind::kKerfHid);
    EXPECT_EQ(p->kinematic_model, KinematicModel::kCartesian);
    EXPECT_DOUBLE_EQ(p->encoder.resolution_m, 1e-5);
    EXPECT_EQ(p->encoder.counts_per_rev, 0u);
    EXPECT_EQ(p->motor.command_limit, 0);
}

TEST(DeviceProfileParse, SimulatedDeviceCarriesItsEmulatorSettings) {
    auto p = parse_device_profile(kSimulated, "sim");
    ASSERT_TRUE(p) << p.error().message();
    EXPECT_EQ(p->emulator.protocol, DeviceKind::kKerfHid);
    EXPECT_EQ(p->emulator.socket_path, "${runtime}/kerf-hapsim.sock");
    EXPECT_FALSE(p->emulator.lockstep);
    EXPECT_EQ(p->ids.serial, "HAPSIM-0001");
}

TEST(DeviceProfileParse, UnknownKindListsTheAcceptedKinds) {
    auto text = edit(kFalcon, "kind = \"falcon\"", "kind = \"falcom\"");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_EQ(e.key, "kind");
    EXPECT_EQ(e.line, line_of(text, "kind ="));
    EXPECT_EQ(e.expected, "one of \"falcon\", \"kerf_hid\", \"simulated\"");
}

TEST(DeviceProfileParse, ASerialLongerThan16OrNotPrintableAsciiIsRefusedNotTruncated) {
    for (const char* serial : {"HAPSIM-0001-TOO-LONG", "HAPSIM-\u00e9"}) {
        auto text = edit(kSimulated, "serial = \"HAPSIM-0001\"",
                         std::string("serial = \"") + serial + "\"");
        auto e = parse_error(text);
        EXPECT_EQ(e.code, ConfigErrc::kBadValue) << serial;
        EXPECT_EQ(e.key, "ids.serial") << serial;
        EXPECT_EQ(e.expected, "at most 16 printable ASCII characters");
    }
}

TEST(DeviceProfileParse, VendorIdBeyondSixteenBitsIsOutOfRange) {
    auto e = parse_error(edit(kFalcon, "vendor_id = 0x0403", "vendor_id = 0x10403"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "ids.vendor_id");
    EXPECT_EQ(e.value, "66563");
    EXPECT_EQ(e.expected, "an integer, 1 <= value <= 65535");
}

TEST(DeviceProfileParse, ContinuousForceAbovePeakIsRejected) {
    auto e = parse_error(edit(kFalcon, "continuous_force_n = 4.0", "continuous_force_n = 9.5"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "limits.continuous_force_n");
    EXPECT_NE(e.expected.find("limits.peak_force_n (8.9 N)"), std::string::npos) << e.expected;
}

TEST(DeviceProfileParse, WorkspaceMinAboveMaxIsRejected) {
    auto text = edit(kFalcon, "min_m = [-0.06, -0.06, 0.075]", "min_m = [-0.06, 0.07, 0.075]");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "workspace.max_m");
    EXPECT_NE(e.note.find("axis y"), std::string::npos);
}

TEST(DeviceProfileParse, WorkspaceWithTwoComponentsIsOutOfRange) {
    auto e = parse_error(edit(kFalcon, "max_m = [0.06, 0.06, 0.175]", "max_m = [0.06, 0.06]"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "workspace.max_m");
    EXPECT_NE(e.note.find("has 2 elements"), std::string::npos);
}

TEST(DeviceProfileParse, NonNumberInsideAListNamesTheElement) {
    auto e = parse_error(edit(kFalcon, "[105.0, -15.0, -135.0]", "[105.0, \"x\", -135.0]"));
    EXPECT_EQ(e.code, ConfigErrc::kWrongType);
    EXPECT_EQ(e.key, "kinematics.leg_angles_deg[1]");
    EXPECT_EQ(e.value, "\"x\"");
}

TEST(DeviceProfileParse, NanLinkLengthIsNotFinite) {
    auto e = parse_error(edit(kFalcon, "a_m = 0.060", "a_m = nan"));
    EXPECT_EQ(e.code, ConfigErrc::kNonFinite);
    EXPECT_EQ(e.key, "kinematics.a_m");
}

TEST(DeviceProfileParse, LinkLengthInMillimetresIsABadUnit) {
    auto e = parse_error(edit(kFalcon, "b_m = 0.1025", "b_mm = 102.5"));
    EXPECT_EQ(e.code, ConfigErrc::kBadUnit);
    EXPECT_EQ(e.key, "kinematics.b_mm");
    EXPECT_NE(e.note.find("'b_m'"), std::string::npos);
}

TEST(DeviceProfileParse, JointSpaceDeviceWithoutMotorTableIsMissingIt) {
    auto text = edit(kFalcon, "[motor]", "[unused]");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kUnknownKey);  // the renamed table, reported first
    EXPECT_EQ(e.key, "unused");
    EXPECT_EQ(e.more_problems, 1u);  // and the missing [motor]
}

TEST(DeviceProfileParse, CartesianResolutionOnAJointDeviceIsABadValue) {
    auto e = parse_error(edit(kFalcon, "counts_per_rev = 1280",
                              "counts_per_rev = 1280\n"
                              "resolution_m = 1e-5"));
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_EQ(e.key, "encoder.resolution_m");
    EXPECT_NE(e.note.find("reporting_space = \"cartesian\""), std::string::npos);
}

TEST(DeviceProfileParse, EmulatorTableOnARealDeviceIsABadValue) {
    auto e = parse_error(kFalcon + "\n[emulator]\nprotocol = \"falcon\"\n");
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_EQ(e.key, "emulator");
    EXPECT_NE(e.note.find("kind = \"simulated\""), std::string::npos);
}

TEST(DeviceProfileParse, JointReportingWithCartesianModelIsInconsistent) {
    auto e =
        parse_error(edit(kHid, "reporting_space = \"cartesian\"", "reporting_space = \"joint\""));
    EXPECT_EQ(e.code, ConfigErrc::kBadValue);
    EXPECT_EQ(e.key, "kinematics.model");
}

TEST(DeviceProfileParse, SimulatedDeviceNeedsItsSocketPath) {
    auto e = parse_error(edit(kSimulated, "socket_path = \"${runtime}/kerf-hapsim.sock\"", ""));
    EXPECT_EQ(e.code, ConfigErrc::kMissingKey);
    EXPECT_EQ(e.key, "emulator.socket_path");
    EXPECT_EQ(e.line, line_of(kSimulated, "[emulator]"));
}

// Issue 9, item 13: an unknown ${var} in socket_path is an error at its line (it used to end as
// "--socket is required" in kerf-hapsim).
TEST(DeviceProfileParse, UnknownVariableInTheSocketPathIsABadReferenceAtItsLine) {
    const std::string text =
        edit(kSimulated, "${runtime}/kerf-hapsim.sock", "${home}/kerf-hapsim.sock");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kBadReference);
    EXPECT_EQ(e.key, "emulator.socket_path");
    EXPECT_EQ(e.line, line_of(text, "socket_path ="));
    EXPECT_NE(e.message().find("cannot expand ${home}"), std::string::npos) << e.message();
}

// Issue 9, item 13: an empty profile says what is missing, not "falcon_delta needs dof = 3".
TEST(DeviceProfileParse, AnEmptyProfileReportsAMissingKeyAndThatTheFileIsEmpty) {
    for (const char* text : {"", "# only a comment\n"}) {
        auto e = parse_error(text);
        EXPECT_EQ(e.code, ConfigErrc::kMissingKey) << e.message();
        EXPECT_EQ(e.message().find("falcon_delta"), std::string::npos) << e.message();
        EXPECT_NE(e.message().find("holds no settings"), std::string::npos) << e.message();
    }
}

TEST(DeviceProfileParse, WatchdogOfZeroIsOutOfRange) {
    auto e = parse_error(edit(kFalcon, "watchdog_ms = 20", "watchdog_ms = 0"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "limits.watchdog_ms");
}

TEST(DeviceProfileEnums, NamesRoundTripThroughTheFiles) {
    EXPECT_EQ(to_string(DeviceKind::kKerfHid), "kerf_hid");
    EXPECT_EQ(to_string(ReportingSpace::kJoint), "joint");
    EXPECT_EQ(to_string(KinematicModel::kFalconDelta), "falcon_delta");
}

}  // namespace
}  // namespace kerf::config

namespace kerf::config {
namespace {

TEST(DeviceProfileList, LoadsEveryShippedProfileSortedByName) {
    auto list = load_device_profiles(test::kConfigDir / "devices");
    ASSERT_TRUE(list) << list.error().message();
    ASSERT_EQ(list->size(), 3u);
    EXPECT_EQ((*list)[0].profile_name, "falcon");
    EXPECT_EQ((*list)[0].profile.ids.product_id, 0xCB48);
    EXPECT_EQ((*list)[1].profile_name, "kerf_hid_reference");
    EXPECT_EQ((*list)[2].profile_name, "simulated");
}

TEST(DeviceProfileList, EveryDeviceChoiceNamesAShippedProfileOfItsKind) {
    // kerf-rt --device and kerf run --record's copy both go through device_profile_stem().
    const struct {
        const char* device;
        const char* stem;
        DeviceKind kind;
    } cases[] = {{"simulated", "simulated", DeviceKind::kSimulated},
                 {"falcon", "falcon", DeviceKind::kFalcon},
                 {"hid", "kerf_hid_reference", DeviceKind::kKerfHid},
                 {"hid:A1B2", "kerf_hid_reference", DeviceKind::kKerfHid}};
    for (const auto& c : cases) {
        EXPECT_EQ(device_profile_stem(c.device), c.stem) << c.device;
        const auto file = test::kConfigDir / "devices" / (std::string(c.stem) + ".toml");
        auto p = load_device_profile(file);
        ASSERT_TRUE(p) << p.error().message();
        EXPECT_EQ(p->kind, c.kind) << c.device;
    }
}

TEST(DeviceProfileList, MissingFolderIsAnIoError) {
    auto e = test::error_of(load_device_profiles("/nonexistent/devices"));
    EXPECT_EQ(e.code, ConfigErrc::kIo);
    EXPECT_EQ(e.source, "/nonexistent/devices");
}

}  // namespace
}  // namespace kerf::config
