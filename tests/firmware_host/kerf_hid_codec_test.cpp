#include "firmware_host/protocol/kerf_hid_codec.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>

#include "firmware_host/protocol/crc16.hpp"
#include "tests/firmware_host/test_bytes.hpp"

namespace kerf::firmware_host {
namespace {

using Report = std::array<std::byte, kReportSize>;

InputReport sample_input() {
    InputReport in;
    in.sequence = 0xFFFE;
    in.echo_sequence = 0x1234;
    in.status = kStatusAmplifiersOn | kStatusHomed;
    in.device_time_us = 0xDEADBEEF;
    in.position = {-150000, 0, 2147483647};
    in.velocity = {-1, 2, -2147483647 - 1};
    in.buttons = 0x0005;
    in.temperature_centi_c = 3550;
    in.applied_centi = {-800, 0, 800};
    return in;
}

void reseal(Report& r) {
    const auto crc = crc16_ccitt(std::span<const std::byte>(r.data(), kReportSize - 2));
    r[62] = std::byte{static_cast<std::uint8_t>(crc & 0xFF)};
    r[63] = std::byte{static_cast<std::uint8_t>(crc >> 8)};
}

TEST(Crc16, MatchesTheCcittFalseCheckValue) {
    const std::string digits = "123456789";
    const auto* p = reinterpret_cast<const std::byte*>(digits.data());
    EXPECT_EQ(crc16_ccitt(std::span<const std::byte>(p, digits.size())), 0x29B1);
}

TEST(KerfHidCodec, InputReportRoundTripsEveryField) {
    Report bytes{};
    ASSERT_EQ(encode_input(sample_input(), bytes), CodecStatus::kOk);
    InputReport out;
    ASSERT_EQ(decode_input(bytes, out), CodecStatus::kOk);
    EXPECT_EQ(out, sample_input());
}

TEST(KerfHidCodec, FieldsAreLittleEndianAtDocumentedOffsets) {
    Report b{};
    ASSERT_EQ(encode_input(sample_input(), b), CodecStatus::kOk);
    EXPECT_EQ(b[0], std::byte{0x01});
    EXPECT_EQ(b[1], std::byte{kProtocolVersion});
    EXPECT_EQ(b[2], std::byte{0xFE});
    EXPECT_EQ(b[3], std::byte{0xFF});
    EXPECT_EQ(b[8], std::byte{0xEF});
    EXPECT_EQ(b[11], std::byte{0xDE});
    EXPECT_EQ(b[12], std::byte{0x10});  // position[0] = -150000 = 0xFFFDB610 -> 10 B6 FD FF
    EXPECT_EQ(b[13], std::byte{0xB6});
    EXPECT_EQ(b[14], std::byte{0xFD});
    EXPECT_EQ(b[15], std::byte{0xFF});
}

TEST(KerfHidCodec, RejectsAShortReport) {
    Report bytes{};
    ASSERT_EQ(encode_input(sample_input(), bytes), CodecStatus::kOk);
    InputReport out;
    EXPECT_EQ(decode_input(std::span(bytes).first(63), out), CodecStatus::kShort);
    EXPECT_EQ(decode_input({}, out), CodecStatus::kShort);
}

TEST(KerfHidCodec, RejectsTheWrongReportId) {
    Report bytes{};
    ASSERT_EQ(encode_output(OutputReport{}, bytes), CodecStatus::kOk);
    InputReport out;
    EXPECT_EQ(decode_input(bytes, out), CodecStatus::kBadReportId);
}

TEST(KerfHidCodec, RejectsEverySingleBitFlipByChecksumOrId) {
    Report good{};
    ASSERT_EQ(encode_input(sample_input(), good), CodecStatus::kOk);
    for (std::size_t bit = 0; bit < kReportSize * 8; ++bit) {
        Report bad = good;
        bad[bit / 8] ^= std::byte{static_cast<std::uint8_t>(1U << (bit % 8))};
        InputReport out;
        const auto s = decode_input(bad, out);
        EXPECT_TRUE(s == CodecStatus::kBadChecksum || s == CodecStatus::kBadReportId) << bit;
    }
}

TEST(KerfHidCodec, RejectsAnUnknownProtocolVersion) {
    Report b{};
    ASSERT_EQ(encode_input(sample_input(), b), CodecStatus::kOk);
    b[1] = std::byte{2};
    reseal(b);
    InputReport out;
    EXPECT_EQ(decode_input(b, out), CodecStatus::kBadVersion);
}

TEST(KerfHidCodec, RejectsReservedStatusBitsAndBytes) {
    Report b{};
    ASSERT_EQ(encode_input(sample_input(), b), CodecStatus::kOk);
    b[7] = std::byte{0x80};
    reseal(b);
    InputReport out;
    EXPECT_EQ(decode_input(b, out), CodecStatus::kReservedNotZero);
    ASSERT_EQ(encode_input(sample_input(), b), CodecStatus::kOk);
    b[56] = std::byte{1};  // after the orientation field (46..53)
    reseal(b);
    EXPECT_EQ(decode_input(b, out), CodecStatus::kReservedNotZero);
}

TEST(KerfHidCodec, OrientationIsZeroOrAUnitQuaternionAndSitsAtBytes46To53) {
    InputReport in = sample_input();
    in.orientation_q15 = {0, 32767, 0, 0};  // 180 degrees about x
    Report b{};
    ASSERT_EQ(encode_input(in, b), CodecStatus::kOk);
    EXPECT_EQ(b[48], std::byte{0xFF});
    EXPECT_EQ(b[49], std::byte{0x7F});
    InputReport out;
    ASSERT_EQ(decode_input(b, out), CodecStatus::kOk);
    EXPECT_EQ(out, in);
    in.orientation_q15 = {16000, 0, 0, 0};  // |q| = 0.49: not a rotation
    EXPECT_EQ(encode_input(in, b), CodecStatus::kOutOfRange);
    b[46] = std::byte{0x80};  // w = 128 with x = 32767 -> still unit within 2 %: fine
    reseal(b);
    EXPECT_EQ(decode_input(b, out), CodecStatus::kOk);
    b[47] = std::byte{0x40};  // w = 16512: |q|^2 = 1.25
    reseal(b);
    EXPECT_EQ(decode_input(b, out), CodecStatus::kOutOfRange);
}

TEST(KerfHidCodec, MechanicsOrientationFlagIsBitZeroOfByte5AndTheRestIsReserved) {
    MechanicsReport m;
    m.encoder_resolution = 10000;
    m.peak_force_centi_n = 1000;
    m.continuous_force_centi_n = 500;
    m.workspace_min_mm = {-80, -80, -80};
    m.workspace_max_mm = {80, 80, 80};
    m.senses_orientation = true;
    Report b{};
    ASSERT_EQ(encode_mechanics(m, b), CodecStatus::kOk);
    EXPECT_EQ(b[5], std::byte{1});
    MechanicsReport out;
    ASSERT_EQ(decode_mechanics(b, out), CodecStatus::kOk);
    EXPECT_TRUE(out.senses_orientation);
    b[5] = std::byte{3};
    reseal(b);
    EXPECT_EQ(decode_mechanics(b, out), CodecStatus::kReservedNotZero);
}

TEST(KerfHidCodec, RejectsOutOfRangeTemperatureAndCommands) {
    InputReport hot = sample_input();
    hot.temperature_centi_c = 15001;
    Report b{};
    EXPECT_EQ(encode_input(hot, b), CodecStatus::kOutOfRange);
    OutputReport cmd;
    cmd.command_milli = {0, kMaxCommandMilli + 1, 0};
    EXPECT_EQ(encode_output(cmd, b), CodecStatus::kOutOfRange);
    cmd.command_milli = {0, kMaxCommandMilli, 0};
    ASSERT_EQ(encode_output(cmd, b), CodecStatus::kOk);
    b[10] = std::byte{0x41};  // command[1] low byte: 1'000'000 -> 1'000'001
    reseal(b);
    OutputReport out;
    EXPECT_EQ(decode_output(b, out), CodecStatus::kOutOfRange);
}

TEST(KerfHidCodec, DecodeLeavesTheOutputUntouchedOnFailure) {
    Report b{};
    ASSERT_EQ(encode_input(sample_input(), b), CodecStatus::kOk);
    b[20] ^= std::byte{1};
    InputReport out;
    out.sequence = 77;
    EXPECT_EQ(decode_input(b, out), CodecStatus::kBadChecksum);
    EXPECT_EQ(out.sequence, 77);
}

TEST(KerfHidCodec, FeatureReportsRoundTrip) {
    Report b{};
    IdentityReport id;
    id.firmware_version = 0x0102;
    id.vendor_id = 0x1209;
    id.product_id = 0x0001;
    id.vendor = test::fixed<kStringSize>("Kerf");
    id.model = test::fixed<kStringSize>("Reference 3DOF");
    id.serial = test::fixed<kStringSize>("KRF-0001");
    ASSERT_EQ(encode_identity(id, b), CodecStatus::kOk);
    IdentityReport id_out;
    ASSERT_EQ(decode_identity(b, id_out), CodecStatus::kOk);
    EXPECT_EQ(id_out, id);

    MechanicsReport m;
    m.encoder_resolution = 10000;
    m.peak_force_centi_n = 1000;
    m.continuous_force_centi_n = 500;
    m.workspace_min_mm = {-80, -80, -80};
    m.workspace_max_mm = {80, 80, 80};
    ASSERT_EQ(encode_mechanics(m, b), CodecStatus::kOk);
    MechanicsReport m_out;
    ASSERT_EQ(decode_mechanics(b, m_out), CodecStatus::kOk);
    EXPECT_EQ(m_out, m);

    ConfigReport c{true, 10};
    ASSERT_EQ(encode_config(c, b), CodecStatus::kOk);
    ConfigReport c_out;
    ASSERT_EQ(decode_config(b, c_out), CodecStatus::kOk);
    EXPECT_EQ(c_out, c);
}

TEST(KerfHidCodec, RejectsInconsistentMechanicsAndBadStrings) {
    Report b{};
    MechanicsReport m;
    m.encoder_resolution = 1;
    m.peak_force_centi_n = 100;
    m.continuous_force_centi_n = 200;  // continuous above peak
    m.workspace_max_mm = {1, 1, 1};
    EXPECT_EQ(encode_mechanics(m, b), CodecStatus::kOutOfRange);
    IdentityReport id;
    id.serial = test::fixed<kStringSize>("AB");
    id.serial[3] = 'C';  // text after NUL padding
    EXPECT_EQ(encode_identity(id, b), CodecStatus::kBadString);
    ConfigReport zero_watchdog{false, 0};
    EXPECT_EQ(encode_config(zero_watchdog, b), CodecStatus::kOutOfRange);
}

TEST(KerfHidCodec, EncodeRefusesABufferShorterThanAReport) {
    std::array<std::byte, 10> small{};
    EXPECT_EQ(encode_input(sample_input(), small), CodecStatus::kBufferTooSmall);
}

TEST(KerfHidCodec, RandomBytesNeverDecodeAsValidInput) {
    std::mt19937 rng(7);
    int accepted = 0;
    for (int i = 0; i < 20000; ++i) {
        Report b;
        for (auto& x : b) x = std::byte{static_cast<std::uint8_t>(rng())};
        b[0] = std::byte{0x01};
        InputReport out;
        if (decode_input(b, out) == CodecStatus::kOk) ++accepted;
    }
    EXPECT_EQ(accepted, 0);
}

TEST(KerfHidCodec, EveryStatusHasAName) {
    for (int s = 0; s <= static_cast<int>(CodecStatus::kBufferTooSmall); ++s) {
        EXPECT_NE(to_string(static_cast<CodecStatus>(s)), "unknown codec status");
    }
}

}  // namespace
}  // namespace kerf::firmware_host
