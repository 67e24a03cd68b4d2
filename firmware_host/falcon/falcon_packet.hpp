// The Novint Falcon's normal-mode packets (PROTOCOL.md §6): 16 bytes framed '<' ... '>', each
// 16-bit value sent as four nibbles, least significant first, each nibble offset by 0x41 ('A').
// Pure, noexcept, no allocation.
//
//   host -> device: '<' motor0[4] motor1[4] motor2[4] control '0x41' '>'
//   device -> host: '<' enc0[4]   enc1[4]   enc2[4]   homed   buttons '>'
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace kerf::firmware_host::falcon {

inline constexpr std::size_t kPacketSize = 16;
inline constexpr std::uint8_t kNibbleBase = 0x41;

/// Host -> device: three motor commands, LEDs, homing mode.
struct FalconCommand {
    std::array<std::int16_t, 3> motor{};  ///< signed 16-bit motor commands (already clamped)
    std::uint8_t leds = 0;                ///< bit 0 green, bit 1 blue, bit 2 red
    bool homing_mode = false;             ///< motors drive the arms to their homing stops
    bool operator==(const FalconCommand&) const = default;
};

/// Device -> host: three encoder counts, per-axis homed flags, buttons.
struct FalconReport {
    std::array<std::int16_t, 3> encoder{};  ///< motor-shaft encoder counts, wrap at 16 bits
    std::uint8_t homed = 0;                 ///< bit i: axis i has seen its homing index
    std::uint8_t buttons = 0;               ///< bit i: grip button i pressed (4 buttons)
    bool all_homed() const noexcept { return (homed & 0x7U) == 0x7U; }
    bool operator==(const FalconReport&) const = default;
};

/// Why a packet was rejected.
enum class FalconCodecStatus : std::uint8_t {
    kOk,
    kShort,      ///< fewer than 16 bytes
    kBadFrame,   ///< byte 0 is not '<' or byte 15 is not '>'
    kBadNibble,  ///< a nibble byte outside 0x41..0x50, or a reserved bit set
};
std::string_view to_string(FalconCodecStatus status) noexcept;

/// Writes `cmd` into `out[0..15]`. @pre out.size() >= 16 (else kShort, nothing written).
FalconCodecStatus encode_command(const FalconCommand& cmd, std::span<std::byte> out) noexcept;
/// Parses a device packet; `out` is written only on kOk.
FalconCodecStatus decode_report(std::span<const std::byte> in, FalconReport& out) noexcept;

/// Device side (kerf-hapsim): the inverse pair.
FalconCodecStatus encode_report(const FalconReport& rep, std::span<std::byte> out) noexcept;
FalconCodecStatus decode_command(std::span<const std::byte> in, FalconCommand& out) noexcept;

}  // namespace kerf::firmware_host::falcon
