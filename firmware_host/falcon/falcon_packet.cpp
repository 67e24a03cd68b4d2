#include "firmware_host/falcon/falcon_packet.hpp"

namespace kerf::firmware_host::falcon {
namespace {

constexpr std::byte kOpen{'<'};
constexpr std::byte kClose{'>'};

std::byte nibble(unsigned v) noexcept {
    return std::byte{static_cast<std::uint8_t>((v & 0xFU) + kNibbleBase)};
}

// One nibble byte back to 0..15, or -1 when outside 0x41..0x50.
int unnibble(std::byte b) noexcept {
    const int v = std::to_integer<int>(b) - kNibbleBase;
    return (v < 0 || v > 15) ? -1 : v;
}

void put16(std::span<std::byte> out, std::size_t at, std::int16_t value) noexcept {
    const auto u = static_cast<std::uint16_t>(value);
    for (unsigned i = 0; i < 4; ++i) out[at + i] = nibble(u >> (4 * i));
}

// Reads four nibbles at `at`; false when one is malformed.
bool get16(std::span<const std::byte> in, std::size_t at, std::int16_t& value) noexcept {
    unsigned u = 0;
    for (unsigned i = 0; i < 4; ++i) {
        const int n = unnibble(in[at + i]);
        if (n < 0) return false;
        u |= static_cast<unsigned>(n) << (4 * i);
    }
    value = static_cast<std::int16_t>(static_cast<std::uint16_t>(u));
    return true;
}

FalconCodecStatus check_frame(std::span<const std::byte> in) noexcept {
    if (in.size() < kPacketSize) return FalconCodecStatus::kShort;
    if (in[0] != kOpen || in[kPacketSize - 1] != kClose) return FalconCodecStatus::kBadFrame;
    return FalconCodecStatus::kOk;
}

}  // namespace

std::string_view to_string(FalconCodecStatus status) noexcept {
    switch (status) {
        case FalconCodecStatus::kOk:
            return "ok";
        case FalconCodecStatus::kShort:
            return "short packet (fewer than 16 bytes)";
        case FalconCodecStatus::kBadFrame:
            return "packet not framed by '<' ... '>'";
        case FalconCodecStatus::kBadNibble:
            return "nibble byte outside 0x41..0x50 or reserved bit set";
    }
    return "unknown falcon codec status";
}

FalconCodecStatus encode_command(const FalconCommand& cmd, std::span<std::byte> out) noexcept {
    if (out.size() < kPacketSize) return FalconCodecStatus::kShort;
    out[0] = kOpen;
    for (std::size_t axis = 0; axis < 3; ++axis) put16(out, 1 + 4 * axis, cmd.motor[axis]);
    out[13] = nibble((cmd.leds & 0x7U) | (cmd.homing_mode ? 0x8U : 0U));
    out[14] = nibble(0);
    out[15] = kClose;
    return FalconCodecStatus::kOk;
}

FalconCodecStatus decode_command(std::span<const std::byte> in, FalconCommand& out) noexcept {
    if (auto s = check_frame(in); s != FalconCodecStatus::kOk) return s;
    FalconCommand v;
    for (std::size_t axis = 0; axis < 3; ++axis) {
        if (!get16(in, 1 + 4 * axis, v.motor[axis])) return FalconCodecStatus::kBadNibble;
    }
    const int control = unnibble(in[13]);
    if (control < 0 || unnibble(in[14]) != 0) return FalconCodecStatus::kBadNibble;
    v.leds = static_cast<std::uint8_t>(control & 0x7);
    v.homing_mode = (control & 0x8) != 0;
    out = v;
    return FalconCodecStatus::kOk;
}

FalconCodecStatus encode_report(const FalconReport& rep, std::span<std::byte> out) noexcept {
    if (out.size() < kPacketSize) return FalconCodecStatus::kShort;
    out[0] = kOpen;
    for (std::size_t axis = 0; axis < 3; ++axis) put16(out, 1 + 4 * axis, rep.encoder[axis]);
    out[13] = nibble(rep.homed & 0x7U);
    out[14] = nibble(rep.buttons & 0xFU);
    out[15] = kClose;
    return FalconCodecStatus::kOk;
}

FalconCodecStatus decode_report(std::span<const std::byte> in, FalconReport& out) noexcept {
    if (auto s = check_frame(in); s != FalconCodecStatus::kOk) return s;
    FalconReport v;
    for (std::size_t axis = 0; axis < 3; ++axis) {
        if (!get16(in, 1 + 4 * axis, v.encoder[axis])) return FalconCodecStatus::kBadNibble;
    }
    const int homed = unnibble(in[13]);
    const int buttons = unnibble(in[14]);
    if (homed < 0 || (homed & 0x8) != 0 || buttons < 0) return FalconCodecStatus::kBadNibble;
    v.homed = static_cast<std::uint8_t>(homed);
    v.buttons = static_cast<std::uint8_t>(buttons);
    out = v;
    return FalconCodecStatus::kOk;
}

}  // namespace kerf::firmware_host::falcon
