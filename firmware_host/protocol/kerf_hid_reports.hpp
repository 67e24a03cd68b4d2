// The decoded form of every Kerf HID report (PROTOCOL.md). Plain values in wire units: the codec
// (kerf_hid_codec.hpp) converts bytes <-> these structs and checks every range; conversion to
// SI happens in the device layer. All reports are 64 bytes: report id, payload, CRC-16.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace kerf::firmware_host {

inline constexpr std::size_t kReportSize = 64;       ///< every Kerf report, id byte included
inline constexpr std::uint8_t kProtocolVersion = 1;  ///< PROTOCOL.md version this codec speaks
inline constexpr std::int32_t kMaxCommandMilli = 1'000'000;  ///< |command| limit (1 kN, 1 kN·m)
inline constexpr std::size_t kStringSize = 16;               ///< vendor, model, serial fields

/// Report ids (byte 0 of every report).
enum class ReportId : std::uint8_t {
    kInput = 0x01,      ///< device -> host, interrupt IN, every period
    kOutput = 0x02,     ///< host -> device, interrupt OUT, every period
    kIdentity = 0x10,   ///< feature, get: who the device is
    kMechanics = 0x11,  ///< feature, get: kinematics, encoder, force limits, workspace
    kConfig = 0x20,     ///< feature, get/set: watchdog period, amplifier enable
};

/// Input-report status bits (PROTOCOL.md §3.1). Bits 7..15 are reserved and must be zero.
enum StatusBit : std::uint16_t {
    kStatusAmplifiersOn = 1U << 0,
    kStatusHomed = 1U << 1,
    kStatusOverTemperature = 1U << 2,
    kStatusEStop = 1U << 3,
    kStatusWatchdogTripped = 1U << 4,
    kStatusEncoderFault = 1U << 5,
    kStatusHoming = 1U << 6,
};
inline constexpr std::uint16_t kStatusDefinedMask = 0x007F;

/// Output-report flag bits (PROTOCOL.md §3.2). Bits 3..15 are reserved and must be zero.
enum CommandFlag : std::uint16_t {
    kFlagAmplifierEnable = 1U << 0,
    kFlagClearFault = 1U << 1,
    kFlagStartHoming = 1U << 2,
};
inline constexpr std::uint16_t kFlagDefinedMask = 0x0007;

/// Input report 0x01: one device sample.
struct InputReport {
    std::uint16_t sequence = 0;              ///< increments by one per report, wraps
    std::uint16_t echo_sequence = 0;         ///< sequence of the last valid output report received
    std::uint16_t status = 0;                ///< StatusBit set
    std::uint32_t device_time_us = 0;        ///< device clock, wraps
    std::array<std::int32_t, 3> position{};  ///< joint: encoder counts; Cartesian: micrometres
    std::array<std::int32_t, 3> velocity{};  ///< counts/s or micrometres/s
    std::uint16_t buttons = 0;               ///< bit i = button i pressed
    std::int16_t temperature_centi_c = 0;    ///< amplifier temperature, 0.01 degC, -4000..15000
    std::array<std::int16_t, 3> applied_centi = {};  ///< force (cN) or torque (cN·m) applied
    /// Tool orientation, unit quaternion (w, x, y, z) times 32767; all zero: not sensed (a device
    /// whose mechanics report does not announce orientation always sends zero). PROTOCOL.md 3.1.
    std::array<std::int16_t, 4> orientation_q15 = {};
    bool operator==(const InputReport&) const = default;
};

/// Output report 0x02: one host command.
struct OutputReport {
    std::uint16_t sequence = 0;                   ///< increments by one per report, wraps
    std::uint16_t flags = 0;                      ///< CommandFlag set
    std::array<std::int32_t, 3> command_milli{};  ///< mN (Cartesian) or mN·m (joint), |v| <= 1e6
    bool operator==(const OutputReport&) const = default;
};

/// Feature report 0x10: identity. Strings are printable ASCII, NUL-padded to 16 bytes.
struct IdentityReport {
    std::uint8_t protocol_version = kProtocolVersion;
    std::uint16_t firmware_version = 0;  ///< major << 8 | minor
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::array<char, kStringSize> vendor{};
    std::array<char, kStringSize> model{};
    std::array<char, kStringSize> serial{};
    bool operator==(const IdentityReport&) const = default;
};

/// Kinematic model codes in the mechanics report.
enum class WireKinematics : std::uint8_t { kCartesian = 0, kFalconDelta = 1 };

/// Feature report 0x11: mechanics.
struct MechanicsReport {
    std::uint8_t dof = 3;             ///< 1..6
    bool cartesian_reporting = true;  ///< false: joint space (host runs kinematics)
    WireKinematics kinematics = WireKinematics::kCartesian;
    std::uint32_t encoder_resolution = 0;  ///< joint: counts per rev; Cartesian: nm per count; > 0
    std::uint16_t peak_force_centi_n = 0;  ///< > 0
    std::uint16_t continuous_force_centi_n = 0;      ///< <= peak
    std::array<std::int16_t, 3> workspace_min_mm{};  ///< each < workspace_max_mm
    std::array<std::int16_t, 3> workspace_max_mm{};
    std::array<std::int32_t, 8> kinematic_params_um{};  ///< delta a,b,c,d,e,f,r,s; else zero
    bool senses_orientation = false;  ///< input reports carry the tool orientation (byte 5 bit 0)
    bool operator==(const MechanicsReport&) const = default;
};

/// Feature report 0x20: configuration.
struct ConfigReport {
    bool amplifier_enable = false;
    std::uint16_t watchdog_ms = 10;  ///< 1..1000
    bool operator==(const ConfigReport&) const = default;
};

}  // namespace kerf::firmware_host
