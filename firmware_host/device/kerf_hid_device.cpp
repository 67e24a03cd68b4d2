#include "firmware_host/device/kerf_hid_device.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

namespace kerf::firmware_host {
namespace {

constexpr int kMaxReportsPerRead = 16;  // bounded drain of queued reports

std::string hex_ids(std::uint16_t vid, std::uint16_t pid) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%04x:%04x", vid, pid);
    return buf;
}

std::int32_t to_milli(double v) noexcept {
    if (!std::isfinite(v)) return 0;
    const double m = std::round(v * 1000.0);
    if (m > kMaxCommandMilli) return kMaxCommandMilli;
    if (m < -kMaxCommandMilli) return -kMaxCommandMilli;
    return static_cast<std::int32_t>(m);
}

}  // namespace

std::string_view to_string(DeviceStatus status) noexcept {
    switch (status) {
        case DeviceStatus::kOk:
            return "ok";
        case DeviceStatus::kNoData:
            return "no new sample";
        case DeviceStatus::kMalformed:
            return "malformed data from the device";
        case DeviceStatus::kDisconnected:
            return "device disconnected";
        case DeviceStatus::kError:
            return "transport error";
    }
    return "unknown device status";
}

KerfHidDevice::KerfHidDevice(std::unique_ptr<ReportTransport> transport,
                             const KerfHidOptions& options) noexcept
    : transport_(std::move(transport)), options_(options) {}

namespace {

TransportError open_error(std::string_view action, std::string_view why,
                          TransportErrc code = TransportErrc::kProtocol) {
    return transport_error(code, "kerf hid device", action, why);
}

// Gets feature report `id` and decodes it into `out`; the error names the report.
template <class T, class Decode>
std::optional<TransportError> get_decoded(ReportTransport& t, ReportId id, const char* name,
                                          std::uint32_t timeout_ms, Decode decode, T& out) {
    std::array<std::byte, kReportSize> buf{};
    std::size_t n = 0;
    if (auto s = t.get_feature(static_cast<std::uint8_t>(id), buf, n, timeout_ms);
        s != LinkStatus::kOk) {
        return open_error(std::string("get ") + name, to_string(s), TransportErrc::kSystem);
    }
    if (auto c = decode(std::span<const std::byte>(buf).first(n), out); c != CodecStatus::kOk) {
        return open_error(std::string("decode ") + name, to_string(c));
    }
    return std::nullopt;
}

}  // namespace

std::optional<TransportError> KerfHidDevice::check_identity() const {
    const auto& id = identity_;
    if ((options_.expected_vendor_id != 0 && id.vendor_id != options_.expected_vendor_id) ||
        (options_.expected_product_id != 0 && id.product_id != options_.expected_product_id)) {
        return open_error("check identity",
                          "device reports " + hex_ids(id.vendor_id, id.product_id) +
                              ", profile expects " +
                              hex_ids(options_.expected_vendor_id, options_.expected_product_id));
    }
    if (!mechanics_.cartesian_reporting) {
        return open_error("check mechanics", "joint-space Kerf HID devices are not supported yet");
    }
    return std::nullopt;
}

Result<std::unique_ptr<KerfHidDevice>, TransportError> KerfHidDevice::open(
    std::unique_ptr<ReportTransport> transport, const KerfHidOptions& options) {
    std::unique_ptr<KerfHidDevice> dev(new KerfHidDevice(std::move(transport), options));
    auto& t = *dev->transport_;
    const auto timeout = options.feature_timeout_ms;
    if (auto e = get_decoded(t, ReportId::kIdentity, "identity report 0x10", timeout,
                             decode_identity, dev->identity_)) {
        return Err{*e};
    }
    if (auto e = get_decoded(t, ReportId::kMechanics, "mechanics report 0x11", timeout,
                             decode_mechanics, dev->mechanics_)) {
        return Err{*e};
    }
    if (auto e = dev->check_identity()) return Err{*e};
    std::array<std::byte, kReportSize> buf{};
    if (encode_config(ConfigReport{true, options.watchdog_ms}, buf) != CodecStatus::kOk) {
        return Err{open_error("encode configuration report 0x20", "watchdog_ms outside 1..1000",
                              TransportErrc::kConfig)};
    }
    if (auto s = t.set_feature(buf, timeout); s != LinkStatus::kOk) {
        return Err{
            open_error("set configuration report 0x20", to_string(s), TransportErrc::kSystem)};
    }
    return dev;
}

void KerfHidDevice::to_sample(const InputReport& in, DeviceSample& out) noexcept {
    out.count = ++fresh_count_;
    out.device_sequence = in.sequence;
    for (int i = 0; i < 3; ++i) {
        out.position_m[i] = in.position[i] * 1e-6;
        out.velocity_m_per_s[i] = in.velocity[i] * 1e-6;
    }
    out.buttons = in.buttons;
    const auto& q = in.orientation_q15;
    out.has_orientation = mechanics_.senses_orientation && (q[0] | q[1] | q[2] | q[3]) != 0;
    if (out.has_orientation) {
        const double n = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] +
                                   double(q[3]) * q[3]);
        for (int i = 0; i < 4; ++i) out.orientation_wxyz[i] = q[i] / n;
    }
    flags_.amplifiers_on = (in.status & kStatusAmplifiersOn) != 0;
    flags_.homed = (in.status & kStatusHomed) != 0;
    flags_.over_temperature = (in.status & kStatusOverTemperature) != 0;
    flags_.estop = (in.status & kStatusEStop) != 0;
    flags_.watchdog_tripped = (in.status & kStatusWatchdogTripped) != 0;
    flags_.encoder_fault = (in.status & kStatusEncoderFault) != 0;
    out.flags = flags_;
    out.command_lag = static_cast<std::uint16_t>(out_sequence_ - in.echo_sequence);
}

DeviceStatus KerfHidDevice::try_read(DeviceSample& out, std::uint32_t timeout_us) noexcept {
    InputReport newest;
    bool got = false;
    bool malformed = false;
    for (int i = 0; i < kMaxReportsPerRead; ++i) {
        std::size_t n = 0;
        const auto s = transport_->read_report(in_buf_, n, i == 0 ? timeout_us : 0U);
        if (s == LinkStatus::kTimeout) break;
        if (s == LinkStatus::kDisconnected) return DeviceStatus::kDisconnected;
        if (s != LinkStatus::kOk) {
            malformed = malformed || s == LinkStatus::kOverflow;
            if (s != LinkStatus::kOverflow) return DeviceStatus::kError;
            continue;
        }
        InputReport in;
        if (decode_input(std::span(in_buf_).first(n), in) != CodecStatus::kOk) {
            ++counters_.malformed;
            malformed = true;
            continue;
        }
        newest = in;
        got = true;
    }
    if (malformed) return DeviceStatus::kMalformed;  // any bad report this tick: not trusted
    if (!got || (have_input_ && newest.sequence == last_in_sequence_)) {
        ++counters_.timeouts;
        return DeviceStatus::kNoData;
    }
    have_input_ = true;
    last_in_sequence_ = newest.sequence;
    to_sample(newest, out);
    ++counters_.samples;
    if (out.command_lag > options_.max_command_lag) return DeviceStatus::kNoData;
    return DeviceStatus::kOk;
}

DeviceStatus KerfHidDevice::try_write(const DeviceCommand& command) noexcept {
    OutputReport rep;
    rep.sequence = ++out_sequence_;
    const bool zero = to_milli(command.force_n[0]) == 0 && to_milli(command.force_n[1]) == 0 &&
                      to_milli(command.force_n[2]) == 0;
    if (!flags_.homed) rep.flags |= kFlagStartHoming;
    if (flags_.any_fault() && zero) rep.flags |= kFlagClearFault;
    const bool drive = command.enable && flags_.homed && !flags_.any_fault();
    if (drive) {
        rep.flags |= kFlagAmplifierEnable;
        for (int i = 0; i < 3; ++i) rep.command_milli[i] = to_milli(command.force_n[i]);
    }
    if (encode_output(rep, out_buf_) != CodecStatus::kOk) return DeviceStatus::kError;
    const auto s = transport_->try_write_report(out_buf_);
    if (s == LinkStatus::kBusy) {
        ++counters_.write_busy;
        return DeviceStatus::kNoData;
    }
    if (s == LinkStatus::kDisconnected) return DeviceStatus::kDisconnected;
    return s == LinkStatus::kOk ? DeviceStatus::kOk : DeviceStatus::kError;
}

LinkStatus KerfHidDevice::shutdown(std::uint32_t timeout_ms) noexcept {
    (void)try_write(DeviceCommand{});
    std::array<std::byte, kReportSize> buf{};
    if (encode_config(ConfigReport{false, options_.watchdog_ms}, buf) != CodecStatus::kOk) {
        return LinkStatus::kError;
    }
    return transport_->set_feature(buf, timeout_ms);
}

}  // namespace kerf::firmware_host
