#include "firmware_host/falcon/falcon_packet.hpp"

#include <gtest/gtest.h>

#include <array>

namespace kerf::firmware_host::falcon {
namespace {

using Packet = std::array<std::byte, kPacketSize>;

TEST(FalconPacket, CommandIsFramedWithLeastSignificantNibbleFirst) {
    FalconCommand cmd;
    cmd.motor = {0x1234, -1, 0};
    cmd.leds = 0x5;
    cmd.homing_mode = true;
    Packet p{};
    ASSERT_EQ(encode_command(cmd, p), FalconCodecStatus::kOk);
    const std::array<std::uint8_t, kPacketSize> expected = {
        '<',  0x45, 0x44, 0x43, 0x42, 0x50,       0x50, 0x50,
        0x50, 0x41, 0x41, 0x41, 0x41, 0x41 + 0xD, 0x41, '>'};
    for (std::size_t i = 0; i < kPacketSize; ++i) {
        EXPECT_EQ(std::to_integer<int>(p[i]), expected[i]) << "byte " << i;
    }
    FalconCommand back;
    ASSERT_EQ(decode_command(p, back), FalconCodecStatus::kOk);
    EXPECT_EQ(back, cmd);
}

TEST(FalconPacket, ReportRoundTripsExtremeValues) {
    FalconReport rep;
    rep.encoder = {-32768, 32767, -1};
    rep.homed = 0x7;
    rep.buttons = 0xF;
    Packet p{};
    ASSERT_EQ(encode_report(rep, p), FalconCodecStatus::kOk);
    FalconReport back;
    ASSERT_EQ(decode_report(p, back), FalconCodecStatus::kOk);
    EXPECT_EQ(back, rep);
    EXPECT_TRUE(back.all_homed());
}

TEST(FalconPacket, RejectsShortUnframedAndBadNibblePackets) {
    Packet p{};
    ASSERT_EQ(encode_report(FalconReport{}, p), FalconCodecStatus::kOk);
    FalconReport out;
    EXPECT_EQ(decode_report(std::span(p).first(15), out), FalconCodecStatus::kShort);
    Packet unframed = p;
    unframed[15] = std::byte{'<'};
    EXPECT_EQ(decode_report(unframed, out), FalconCodecStatus::kBadFrame);
    Packet bad = p;
    bad[5] = std::byte{0x40};
    EXPECT_EQ(decode_report(bad, out), FalconCodecStatus::kBadNibble);
    bad = p;
    bad[13] = std::byte{0x41 + 0x8};  // reserved homed bit
    EXPECT_EQ(decode_report(bad, out), FalconCodecStatus::kBadNibble);
}

TEST(FalconPacket, AnyByteWithTheHighBitSetIsRejected) {
    Packet good{};
    ASSERT_EQ(encode_report(FalconReport{{100, -200, 300}, 3, 1}, good), FalconCodecStatus::kOk);
    for (std::size_t i = 0; i < kPacketSize; ++i) {
        Packet bad = good;
        bad[i] ^= std::byte{0x80};
        FalconReport out;
        EXPECT_NE(decode_report(bad, out), FalconCodecStatus::kOk) << "byte " << i;
    }
}

}  // namespace
}  // namespace kerf::firmware_host::falcon
