// Golden fixtures: recorded report bytes in tests/firmware_host/fixtures/*.bin. Each test decodes
// a fixture, checks the decoded values, and re-encodes them bit-exactly. The files double as the
// fuzzer's seed corpus. To regenerate after a deliberate protocol change (bump the version!):
//   KERF_WRITE_FIXTURES=1 build/bin/kerf_firmware_host_tests --gtest_filter='GoldenFixture*'
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <vector>

#include "firmware_host/falcon/falcon_packet.hpp"
#include "firmware_host/protocol/kerf_hid_codec.hpp"
#include "tests/firmware_host/test_bytes.hpp"

namespace kerf::firmware_host {
namespace {

using test::fixed;

bool writing() { return std::getenv("KERF_WRITE_FIXTURES") != nullptr; }

// Encodes `value`, writes the fixture when regenerating, then checks decode + bit-exact re-encode.
template <class T, class Encode, class Decode>
void check_fixture(const char* name, const T& value, Encode encode, Decode decode) {
    std::vector<std::byte> encoded(64);
    ASSERT_EQ(static_cast<int>(encode(value, encoded)), 0) << name;
    const auto path = test::fixture_dir() / name;
    if (writing()) test::write_bytes(path, encoded);
    const auto golden = test::read_bytes(path);
    ASSERT_FALSE(golden.empty()) << "missing fixture " << path;
    T decoded{};
    ASSERT_EQ(static_cast<int>(decode(golden, decoded)), 0) << name;
    EXPECT_EQ(decoded, value) << name;
    std::vector<std::byte> again(golden.size());
    ASSERT_EQ(static_cast<int>(encode(decoded, again)), 0);
    EXPECT_EQ(again, golden) << name << " did not re-encode bit-exactly";
}

TEST(GoldenFixture, InputReportOfAHomedMovingDevice) {
    InputReport in;
    in.sequence = 4242;
    in.echo_sequence = 4241;
    in.status = kStatusAmplifiersOn | kStatusHomed;
    in.device_time_us = 4242000;
    in.position = {12345, -23456, 34567};
    in.velocity = {-1000, 0, 1000};
    in.buttons = 1;
    in.temperature_centi_c = 3125;
    in.applied_centi = {150, -75, 0};
    check_fixture("kerf_input_homed_moving.bin", in, encode_input, decode_input);
}

TEST(GoldenFixture, InputReportWithEStopAndWatchdogTripped) {
    InputReport in;
    in.sequence = 65535;
    in.echo_sequence = 65530;
    in.status = kStatusHomed | kStatusEStop | kStatusWatchdogTripped;
    in.temperature_centi_c = -4000;
    check_fixture("kerf_input_estop.bin", in, encode_input, decode_input);
}

TEST(GoldenFixture, OutputReportCommandingForce) {
    OutputReport out;
    out.sequence = 4242;
    out.flags = kFlagAmplifierEnable;
    out.command_milli = {1500, -2500, 0};
    check_fixture("kerf_output_force.bin", out, encode_output, decode_output);
}

TEST(GoldenFixture, IdentityFeatureReport) {
    IdentityReport id;
    id.firmware_version = 0x0103;
    id.vendor_id = 0x1209;
    id.product_id = 0x0001;
    id.vendor = fixed<kStringSize>("Kerf");
    id.model = fixed<kStringSize>("Reference 3DOF");
    id.serial = fixed<kStringSize>("KRF-000042");
    check_fixture("kerf_feature_identity.bin", id, encode_identity, decode_identity);
}

TEST(GoldenFixture, MechanicsFeatureReportOfADeltaDevice) {
    MechanicsReport m;
    m.dof = 3;
    m.cartesian_reporting = false;
    m.kinematics = WireKinematics::kFalconDelta;
    m.encoder_resolution = 1280;
    m.peak_force_centi_n = 890;
    m.continuous_force_centi_n = 400;
    m.workspace_min_mm = {-60, -60, 75};
    m.workspace_max_mm = {60, 60, 175};
    m.kinematic_params_um = {60000, 102500, 14000, 11250, 11250, -25000, 37234, -27331};
    check_fixture("kerf_feature_mechanics.bin", m, encode_mechanics, decode_mechanics);
}

// The orientation extension (PROTOCOL.md 3.1, 4.2): byte 5 bit 0 of the mechanics report
// announces it; input bytes 46..53 carry the tool's unit quaternion times 32767. These two files
// were written by a script independent of the codec (Python struct + CRC-16/CCITT-FALSE).
TEST(GoldenFixture, MechanicsFeatureReportAnnouncingOrientation) {
    MechanicsReport m;
    m.dof = 3;
    m.cartesian_reporting = false;
    m.kinematics = WireKinematics::kFalconDelta;
    m.encoder_resolution = 1280;
    m.peak_force_centi_n = 890;
    m.continuous_force_centi_n = 400;
    m.workspace_min_mm = {-60, -60, 75};
    m.workspace_max_mm = {60, 60, 175};
    m.kinematic_params_um = {60000, 102500, 14000, 11250, 11250, -25000, 37234, -27331};
    m.senses_orientation = true;
    check_fixture("kerf_feature_mechanics_orientation.bin", m, encode_mechanics, decode_mechanics);
}

TEST(GoldenFixture, InputReportWithAToolOrientation) {
    InputReport in;
    in.sequence = 7;
    in.echo_sequence = 6;
    in.status = kStatusAmplifiersOn | kStatusHomed;
    in.device_time_us = 7000;
    in.position = {1000, -2000, 3000};
    in.buttons = 5;
    in.temperature_centi_c = 3100;
    in.orientation_q15 = {31650, 8481, 0, 0};  // 30 degrees about x
    check_fixture("kerf_input_orientation.bin", in, encode_input, decode_input);
}

TEST(GoldenFixture, ConfigFeatureReport) {
    check_fixture("kerf_feature_config.bin", ConfigReport{true, 10}, encode_config, decode_config);
}

TEST(GoldenFixture, FalconPacketsRoundTripBitExactly) {
    falcon::FalconReport rep{{1200, -340, 5}, 0x7, 0x2};
    std::array<std::byte, falcon::kPacketSize> bytes{};
    ASSERT_EQ(falcon::encode_report(rep, bytes), falcon::FalconCodecStatus::kOk);
    const auto path = test::fixture_dir() / "falcon_report_homed.bin";
    if (writing()) test::write_bytes(path, {bytes.begin(), bytes.end()});
    const auto golden = test::read_bytes(path);
    falcon::FalconReport decoded;
    ASSERT_EQ(falcon::decode_report(golden, decoded), falcon::FalconCodecStatus::kOk);
    EXPECT_EQ(decoded, rep);
    EXPECT_EQ(std::vector<std::byte>(bytes.begin(), bytes.end()), golden);
}

TEST(GoldenFixture, CorruptedFixtureIsRejected) {
    auto bytes = test::read_bytes(test::fixture_dir() / "kerf_input_homed_moving.bin");
    ASSERT_EQ(bytes.size(), kReportSize);
    bytes[13] ^= std::byte{0x04};
    InputReport in;
    EXPECT_EQ(decode_input(bytes, in), CodecStatus::kBadChecksum);
}

}  // namespace
}  // namespace kerf::firmware_host
