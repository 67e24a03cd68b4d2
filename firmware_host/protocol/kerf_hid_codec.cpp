#include "firmware_host/protocol/kerf_hid_codec.hpp"

#include <cstring>

#include "firmware_host/protocol/crc16.hpp"

namespace kerf::firmware_host {
namespace {

constexpr std::size_t kCrcOffset = kReportSize - 2;

// Little-endian field access over a checked 64-byte report.
class Reader {
public:
    explicit Reader(std::span<const std::byte> b) noexcept : b_(b) {}
    std::uint8_t u8(std::size_t at) const noexcept { return std::to_integer<std::uint8_t>(b_[at]); }
    std::uint16_t u16(std::size_t at) const noexcept {
        return static_cast<std::uint16_t>(u8(at) | (u8(at + 1) << 8));
    }
    std::int16_t i16(std::size_t at) const noexcept { return static_cast<std::int16_t>(u16(at)); }
    std::uint32_t u32(std::size_t at) const noexcept {
        return static_cast<std::uint32_t>(u16(at)) |
               (static_cast<std::uint32_t>(u16(at + 2)) << 16);
    }
    std::int32_t i32(std::size_t at) const noexcept { return static_cast<std::int32_t>(u32(at)); }
    bool zero(std::size_t from, std::size_t to) const noexcept {
        for (std::size_t i = from; i < to; ++i) {
            if (b_[i] != std::byte{0}) return false;
        }
        return true;
    }

private:
    std::span<const std::byte> b_;
};

class Writer {
public:
    explicit Writer(std::span<std::byte> b) noexcept : b_(b) {
        std::memset(b_.data(), 0, kReportSize);
    }
    void u8(std::size_t at, std::uint8_t v) noexcept { b_[at] = std::byte{v}; }
    void u16(std::size_t at, std::uint16_t v) noexcept {
        u8(at, static_cast<std::uint8_t>(v & 0xFF));
        u8(at + 1, static_cast<std::uint8_t>(v >> 8));
    }
    void i16(std::size_t at, std::int16_t v) noexcept { u16(at, static_cast<std::uint16_t>(v)); }
    void u32(std::size_t at, std::uint32_t v) noexcept {
        u16(at, static_cast<std::uint16_t>(v & 0xFFFF));
        u16(at + 2, static_cast<std::uint16_t>(v >> 16));
    }
    void i32(std::size_t at, std::int32_t v) noexcept { u32(at, static_cast<std::uint32_t>(v)); }
    void header(ReportId id) noexcept {
        u8(0, static_cast<std::uint8_t>(id));
        u8(1, kProtocolVersion);
    }
    void seal() noexcept {
        u16(kCrcOffset, crc16_ccitt(std::span<const std::byte>(b_.data(), kCrcOffset)));
    }

private:
    std::span<std::byte> b_;
};

// Size, id, checksum and version: the checks every report shares, in that order.
CodecStatus check_frame(std::span<const std::byte> b, ReportId id) noexcept {
    if (b.size() < kReportSize) return CodecStatus::kShort;
    const Reader r(b);
    if (r.u8(0) != static_cast<std::uint8_t>(id)) return CodecStatus::kBadReportId;
    if (crc16_ccitt(b.first(kCrcOffset)) != r.u16(kCrcOffset)) return CodecStatus::kBadChecksum;
    if (r.u8(1) != kProtocolVersion) return CodecStatus::kBadVersion;
    return CodecStatus::kOk;
}

bool valid_string(const std::array<char, kStringSize>& s) noexcept {
    bool padding = false;
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (u == 0) {
            padding = true;
        } else if (padding || u < 0x20 || u > 0x7E) {
            return false;
        }
    }
    return true;
}

void read_string(const Reader& r, std::size_t at, std::array<char, kStringSize>& s) noexcept {
    for (std::size_t i = 0; i < kStringSize; ++i) s[i] = static_cast<char>(r.u8(at + i));
}

void write_string(Writer& w, std::size_t at, const std::array<char, kStringSize>& s) noexcept {
    for (std::size_t i = 0; i < kStringSize; ++i) w.u8(at + i, static_cast<std::uint8_t>(s[i]));
}

bool command_in_range(std::int32_t v) noexcept {
    return v >= -kMaxCommandMilli && v <= kMaxCommandMilli;
}

bool temperature_in_range(std::int16_t t) noexcept { return t >= -4000 && t <= 15000; }

/// All zero (not sensed), or a unit quaternion within 2 % (|q|^2 in [0.96, 1.04] x 32767^2).
bool orientation_in_range(const std::array<std::int16_t, 4>& q) noexcept {
    std::int64_t n2 = 0;
    for (std::int16_t c : q) n2 += std::int64_t{c} * c;
    constexpr std::int64_t kOne = 32767LL * 32767LL;
    return n2 == 0 || (n2 >= kOne * 96 / 100 && n2 <= kOne * 104 / 100);
}

bool mechanics_in_range(const MechanicsReport& m) noexcept {
    if (m.dof < 1 || m.dof > 6) return false;
    if (static_cast<std::uint8_t>(m.kinematics) > 1) return false;
    if (m.encoder_resolution == 0 || m.peak_force_centi_n == 0) return false;
    if (m.continuous_force_centi_n > m.peak_force_centi_n) return false;
    for (std::size_t i = 0; i < 3; ++i) {
        if (m.workspace_min_mm[i] >= m.workspace_max_mm[i]) return false;
    }
    return true;
}

}  // namespace

std::string_view to_string(CodecStatus status) noexcept {
    switch (status) {
        case CodecStatus::kOk:
            return "ok";
        case CodecStatus::kShort:
            return "short report (fewer than 64 bytes)";
        case CodecStatus::kBadReportId:
            return "unexpected report id";
        case CodecStatus::kBadChecksum:
            return "CRC-16 mismatch";
        case CodecStatus::kBadVersion:
            return "unsupported protocol version";
        case CodecStatus::kReservedNotZero:
            return "reserved bits or bytes not zero";
        case CodecStatus::kOutOfRange:
            return "field out of range";
        case CodecStatus::kBadString:
            return "string field not printable ASCII + NUL padding";
        case CodecStatus::kBufferTooSmall:
            return "output buffer shorter than 64 bytes";
    }
    return "unknown codec status";
}

std::uint8_t peek_report_id(std::span<const std::byte> bytes) noexcept {
    return bytes.empty() ? 0 : std::to_integer<std::uint8_t>(bytes[0]);
}

CodecStatus decode_input(std::span<const std::byte> bytes, InputReport& out) noexcept {
    if (auto s = check_frame(bytes, ReportId::kInput); s != CodecStatus::kOk) return s;
    const Reader r(bytes);
    InputReport v;
    v.sequence = r.u16(2);
    v.echo_sequence = r.u16(4);
    v.status = r.u16(6);
    v.device_time_us = r.u32(8);
    for (std::size_t i = 0; i < 3; ++i) {
        v.position[i] = r.i32(12 + 4 * i);
        v.velocity[i] = r.i32(24 + 4 * i);
        v.applied_centi[i] = r.i16(40 + 2 * i);
    }
    v.buttons = r.u16(36);
    v.temperature_centi_c = r.i16(38);
    for (std::size_t i = 0; i < 4; ++i) v.orientation_q15[i] = r.i16(46 + 2 * i);
    if ((v.status & ~kStatusDefinedMask) != 0 || !r.zero(54, kCrcOffset)) {
        return CodecStatus::kReservedNotZero;
    }
    if (!temperature_in_range(v.temperature_centi_c)) return CodecStatus::kOutOfRange;
    if (!orientation_in_range(v.orientation_q15)) return CodecStatus::kOutOfRange;
    out = v;
    return CodecStatus::kOk;
}

CodecStatus decode_output(std::span<const std::byte> bytes, OutputReport& out) noexcept {
    if (auto s = check_frame(bytes, ReportId::kOutput); s != CodecStatus::kOk) return s;
    const Reader r(bytes);
    OutputReport v;
    v.sequence = r.u16(2);
    v.flags = r.u16(4);
    for (std::size_t i = 0; i < 3; ++i) v.command_milli[i] = r.i32(6 + 4 * i);
    if ((v.flags & ~kFlagDefinedMask) != 0 || !r.zero(18, kCrcOffset)) {
        return CodecStatus::kReservedNotZero;
    }
    for (auto c : v.command_milli) {
        if (!command_in_range(c)) return CodecStatus::kOutOfRange;
    }
    out = v;
    return CodecStatus::kOk;
}

CodecStatus decode_identity(std::span<const std::byte> bytes, IdentityReport& out) noexcept {
    if (auto s = check_frame(bytes, ReportId::kIdentity); s != CodecStatus::kOk) return s;
    const Reader r(bytes);
    IdentityReport v;
    v.protocol_version = r.u8(1);
    v.firmware_version = r.u16(2);
    v.vendor_id = r.u16(4);
    v.product_id = r.u16(6);
    read_string(r, 8, v.vendor);
    read_string(r, 24, v.model);
    read_string(r, 40, v.serial);
    if (!r.zero(56, kCrcOffset)) return CodecStatus::kReservedNotZero;
    if (!valid_string(v.vendor) || !valid_string(v.model) || !valid_string(v.serial)) {
        return CodecStatus::kBadString;
    }
    out = v;
    return CodecStatus::kOk;
}

CodecStatus decode_mechanics(std::span<const std::byte> bytes, MechanicsReport& out) noexcept {
    if (auto s = check_frame(bytes, ReportId::kMechanics); s != CodecStatus::kOk) return s;
    const Reader r(bytes);
    if ((r.u8(5) & 0xFE) != 0 || !r.zero(22, 24) || !r.zero(60, kCrcOffset)) {
        return CodecStatus::kReservedNotZero;
    }
    if (r.u8(3) > 1) return CodecStatus::kOutOfRange;
    MechanicsReport v;
    v.dof = r.u8(2);
    v.cartesian_reporting = r.u8(3) == 1;
    v.kinematics = static_cast<WireKinematics>(r.u8(4));
    v.senses_orientation = (r.u8(5) & 1u) != 0;
    v.peak_force_centi_n = r.u16(6);
    v.continuous_force_centi_n = r.u16(8);
    for (std::size_t i = 0; i < 3; ++i) {
        v.workspace_min_mm[i] = r.i16(10 + 2 * i);
        v.workspace_max_mm[i] = r.i16(16 + 2 * i);
    }
    v.encoder_resolution = r.u32(24);
    for (std::size_t i = 0; i < 8; ++i) v.kinematic_params_um[i] = r.i32(28 + 4 * i);
    if (!mechanics_in_range(v)) return CodecStatus::kOutOfRange;
    out = v;
    return CodecStatus::kOk;
}

CodecStatus decode_config(std::span<const std::byte> bytes, ConfigReport& out) noexcept {
    if (auto s = check_frame(bytes, ReportId::kConfig); s != CodecStatus::kOk) return s;
    const Reader r(bytes);
    if ((r.u8(2) & 0xFE) != 0 || !r.zero(3, 4) || !r.zero(6, kCrcOffset)) {
        return CodecStatus::kReservedNotZero;
    }
    ConfigReport v;
    v.amplifier_enable = (r.u8(2) & 1U) != 0;
    v.watchdog_ms = r.u16(4);
    if (v.watchdog_ms < 1 || v.watchdog_ms > 1000) return CodecStatus::kOutOfRange;
    out = v;
    return CodecStatus::kOk;
}

CodecStatus encode_input(const InputReport& in, std::span<std::byte> out) noexcept {
    if (out.size() < kReportSize) return CodecStatus::kBufferTooSmall;
    if ((in.status & ~kStatusDefinedMask) != 0) return CodecStatus::kReservedNotZero;
    if (!temperature_in_range(in.temperature_centi_c)) return CodecStatus::kOutOfRange;
    if (!orientation_in_range(in.orientation_q15)) return CodecStatus::kOutOfRange;
    Writer w(out);
    w.header(ReportId::kInput);
    w.u16(2, in.sequence);
    w.u16(4, in.echo_sequence);
    w.u16(6, in.status);
    w.u32(8, in.device_time_us);
    for (std::size_t i = 0; i < 3; ++i) {
        w.i32(12 + 4 * i, in.position[i]);
        w.i32(24 + 4 * i, in.velocity[i]);
        w.i16(40 + 2 * i, in.applied_centi[i]);
    }
    w.u16(36, in.buttons);
    w.i16(38, in.temperature_centi_c);
    for (std::size_t i = 0; i < 4; ++i) w.i16(46 + 2 * i, in.orientation_q15[i]);
    w.seal();
    return CodecStatus::kOk;
}

CodecStatus encode_output(const OutputReport& in, std::span<std::byte> out) noexcept {
    if (out.size() < kReportSize) return CodecStatus::kBufferTooSmall;
    if ((in.flags & ~kFlagDefinedMask) != 0) return CodecStatus::kReservedNotZero;
    for (auto c : in.command_milli) {
        if (!command_in_range(c)) return CodecStatus::kOutOfRange;
    }
    Writer w(out);
    w.header(ReportId::kOutput);
    w.u16(2, in.sequence);
    w.u16(4, in.flags);
    for (std::size_t i = 0; i < 3; ++i) w.i32(6 + 4 * i, in.command_milli[i]);
    w.seal();
    return CodecStatus::kOk;
}

CodecStatus encode_identity(const IdentityReport& in, std::span<std::byte> out) noexcept {
    if (out.size() < kReportSize) return CodecStatus::kBufferTooSmall;
    if (in.protocol_version != kProtocolVersion) return CodecStatus::kBadVersion;
    if (!valid_string(in.vendor) || !valid_string(in.model) || !valid_string(in.serial)) {
        return CodecStatus::kBadString;
    }
    Writer w(out);
    w.header(ReportId::kIdentity);
    w.u16(2, in.firmware_version);
    w.u16(4, in.vendor_id);
    w.u16(6, in.product_id);
    write_string(w, 8, in.vendor);
    write_string(w, 24, in.model);
    write_string(w, 40, in.serial);
    w.seal();
    return CodecStatus::kOk;
}

CodecStatus encode_mechanics(const MechanicsReport& in, std::span<std::byte> out) noexcept {
    if (out.size() < kReportSize) return CodecStatus::kBufferTooSmall;
    if (!mechanics_in_range(in)) return CodecStatus::kOutOfRange;
    Writer w(out);
    w.header(ReportId::kMechanics);
    w.u8(2, in.dof);
    w.u8(3, in.cartesian_reporting ? 1 : 0);
    w.u8(4, static_cast<std::uint8_t>(in.kinematics));
    w.u8(5, in.senses_orientation ? 1 : 0);
    w.u16(6, in.peak_force_centi_n);
    w.u16(8, in.continuous_force_centi_n);
    for (std::size_t i = 0; i < 3; ++i) {
        w.i16(10 + 2 * i, in.workspace_min_mm[i]);
        w.i16(16 + 2 * i, in.workspace_max_mm[i]);
    }
    w.u32(24, in.encoder_resolution);
    for (std::size_t i = 0; i < 8; ++i) w.i32(28 + 4 * i, in.kinematic_params_um[i]);
    w.seal();
    return CodecStatus::kOk;
}

CodecStatus encode_config(const ConfigReport& in, std::span<std::byte> out) noexcept {
    if (out.size() < kReportSize) return CodecStatus::kBufferTooSmall;
    if (in.watchdog_ms < 1 || in.watchdog_ms > 1000) return CodecStatus::kOutOfRange;
    Writer w(out);
    w.header(ReportId::kConfig);
    w.u8(2, in.amplifier_enable ? 1 : 0);
    w.u16(4, in.watchdog_ms);
    w.seal();
    return CodecStatus::kOk;
}

}  // namespace kerf::firmware_host
