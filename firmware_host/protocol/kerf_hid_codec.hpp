// The pure Kerf HID codec: bytes in, struct out (or struct in, bytes out), every field checked.
// No I/O, no allocation, noexcept: callable from the 1 kHz loop and from a fuzzer.
//
//   InputReport in;
//   if (auto s = decode_input(bytes, in); s != CodecStatus::kOk) { count(s); zero_force(); }
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

#include "firmware_host/protocol/kerf_hid_reports.hpp"

namespace kerf::firmware_host {

/// Why a report was rejected.
enum class CodecStatus : std::uint8_t {
    kOk,
    kShort,            ///< fewer than 64 bytes
    kBadReportId,      ///< byte 0 is not the expected report id
    kBadChecksum,      ///< CRC-16 over bytes 0..61 differs from bytes 62..63
    kBadVersion,       ///< protocol version this codec does not speak
    kReservedNotZero,  ///< a reserved bit or byte is set
    kOutOfRange,       ///< a field outside its documented range
    kBadString,        ///< a string field is not printable ASCII followed by NUL padding
    kBufferTooSmall,   ///< encode: output span shorter than 64 bytes
};
std::string_view to_string(CodecStatus status) noexcept;

/// Decodes an input report. `out` is written only on kOk. Extra bytes past 64 are ignored.
CodecStatus decode_input(std::span<const std::byte> bytes, InputReport& out) noexcept;
/// Decodes an output report (the device side, and kerf-hapsim).
CodecStatus decode_output(std::span<const std::byte> bytes, OutputReport& out) noexcept;
/// Decodes the identity feature report.
CodecStatus decode_identity(std::span<const std::byte> bytes, IdentityReport& out) noexcept;
/// Decodes the mechanics feature report.
CodecStatus decode_mechanics(std::span<const std::byte> bytes, MechanicsReport& out) noexcept;
/// Decodes the configuration feature report.
CodecStatus decode_config(std::span<const std::byte> bytes, ConfigReport& out) noexcept;

/// Encodes into `out[0..63]` (id, fields, zero reserved bytes, CRC). @pre fields in range
/// (else kOutOfRange / kBadString and `out` is left unspecified).
CodecStatus encode_input(const InputReport& in, std::span<std::byte> out) noexcept;
CodecStatus encode_output(const OutputReport& in, std::span<std::byte> out) noexcept;
CodecStatus encode_identity(const IdentityReport& in, std::span<std::byte> out) noexcept;
CodecStatus encode_mechanics(const MechanicsReport& in, std::span<std::byte> out) noexcept;
CodecStatus encode_config(const ConfigReport& in, std::span<std::byte> out) noexcept;

/// The report id in byte 0, or 0 for an empty span.
std::uint8_t peek_report_id(std::span<const std::byte> bytes) noexcept;

}  // namespace kerf::firmware_host
