#include "firmware_host/device/falcon_device.hpp"

#include <cmath>
#include <cstring>

#include "firmware_host/falcon/ftdi.hpp"

namespace kerf::firmware_host {
namespace {

constexpr int kMaxTransfersPerRead = 8;
constexpr std::uint32_t kSetupTimeoutMs = 1000;

}  // namespace

FalconDevice::FalconDevice(std::unique_ptr<UsbLink> link, const FalconOptions& options) noexcept
    : link_(std::move(link)), options_(options), kinematics_(options.geometry) {}

Result<std::unique_ptr<FalconDevice>, TransportError> FalconDevice::open(
    std::unique_ptr<UsbLink> link, const FalconOptions& options) {
    std::unique_ptr<FalconDevice> dev(new FalconDevice(std::move(link), options));
    if (!options.firmware_path.empty()) {
        auto image = falcon::read_firmware_image(options.firmware_path);
        if (!image)
            return Err{transport_error(TransportErrc::kFirmware, options.firmware_path,
                                       "read falcon firmware", image.error().what)};
        if (auto s = falcon::load_firmware(*dev->link_, *image, options.load); !s) {
            return Err{transport_error(TransportErrc::kFirmware, options.firmware_path,
                                       "load falcon firmware", s.error().what)};
        }
    } else if (auto s = falcon::send_requests(*dev->link_, falcon::normal_mode_requests(),
                                              kSetupTimeoutMs);
               s != LinkStatus::kOk) {
        return Err{transport_error(TransportErrc::kSystem, "ftdi", "set falcon normal mode",
                                   to_string(s))};
    }
    // Normal-mode check: one zero command must be answered by a well-formed packet.
    (void)dev->try_write(DeviceCommand{});
    DeviceSample sample;
    const auto s = dev->try_read(sample, options.probe_timeout_ms * 1000U);
    if (s != DeviceStatus::kOk) {
        return Err{transport_error(
            TransportErrc::kProtocol, "normal mode", "check falcon firmware",
            std::string(to_string(s)) + (options.firmware_path.empty()
                                             ? " (firmware not loaded? pass a firmware image)"
                                             : ""))};
    }
    return dev;
}

int FalconDevice::consume(std::span<const std::byte> payload, bool& malformed) noexcept {
    int decoded = 0;
    for (std::byte b : payload) {
        if (stream_len_ == stream_.size()) {  // garbage without frames: start over
            stream_len_ = 0;
            malformed = true;
        }
        if (stream_len_ == 0 && b != std::byte{'<'}) {
            malformed = true;
            continue;
        }
        stream_[stream_len_++] = b;
        if (stream_len_ < falcon::kPacketSize) continue;
        falcon::FalconReport rep;
        if (falcon::decode_report(std::span(stream_).first(falcon::kPacketSize), rep) ==
            falcon::FalconCodecStatus::kOk) {
            report_ = rep;
            ++decoded;
            stream_len_ = 0;
            continue;
        }
        malformed = true;  // resynchronise on the next '<' after the bad start
        std::size_t next = 1;
        while (next < stream_len_ && stream_[next] != std::byte{'<'}) ++next;
        std::memmove(stream_.data(), stream_.data() + next, stream_len_ - next);
        stream_len_ -= next;
    }
    return decoded;
}

bool FalconDevice::to_sample(DeviceSample& out) noexcept {
    Vec3 theta{};
    for (int i = 0; i < 3; ++i) theta[i] = kinematics_.angle_rad(report_.encoder[i]);
    Vec3 p{};
    if (kinematics_.forward(theta, position_, p) != falcon::KinematicsStatus::kOk) return false;
    out.count = ++fresh_count_;
    for (int i = 0; i < 3; ++i) {
        out.velocity_m_per_s[i] = have_position_ ? (p[i] - position_[i]) / options_.period_s : 0.0;
        out.position_m[i] = p[i];
    }
    theta_ = theta;
    position_ = p;
    have_position_ = true;
    out.buttons = report_.buttons;
    out.flags = DeviceFlags{};
    out.flags.homed = report_.all_homed();
    out.flags.amplifiers_on = enabled_;
    return true;
}

DeviceStatus FalconDevice::try_read(DeviceSample& out, std::uint32_t timeout_us) noexcept {
    int decoded = 0;
    bool malformed = false;
    for (int i = 0; i < kMaxTransfersPerRead; ++i) {
        std::size_t n = 0;
        const auto s = link_->bulk_read(transfer_, n, i == 0 ? timeout_us : 0U);
        if (s == LinkStatus::kTimeout) break;
        if (s == LinkStatus::kDisconnected) return DeviceStatus::kDisconnected;
        if (s != LinkStatus::kOk) return DeviceStatus::kError;
        const auto len = falcon::strip_ftdi_status(std::span(transfer_).first(n), payload_);
        decoded += consume(std::span(payload_).first(len), malformed);
        if (len == 0 && decoded > 0) break;
    }
    if (malformed) {
        ++counters_.malformed;
        return DeviceStatus::kMalformed;
    }
    if (decoded == 0) {
        ++counters_.timeouts;
        return DeviceStatus::kNoData;
    }
    if (!to_sample(out)) {
        ++counters_.malformed;
        return DeviceStatus::kMalformed;
    }
    ++counters_.samples;
    return DeviceStatus::kOk;
}

DeviceStatus FalconDevice::try_write(const DeviceCommand& command) noexcept {
    falcon::FalconCommand cmd;
    cmd.leds = command.leds;
    const bool homed = report_.all_homed();
    cmd.homing_mode = !homed;
    enabled_ = command.enable && homed && have_position_;
    if (enabled_) {
        Vec3 torque{};
        if (kinematics_.torques(theta_, position_, command.force_n, torque) ==
            falcon::KinematicsStatus::kOk) {
            bool clamped = false;
            cmd.motor = kinematics_.commands(torque, clamped);
            if (clamped) ++counters_.clamped_commands;
        }
    }
    (void)falcon::encode_command(cmd, out_buf_);
    const auto s = link_->bulk_write(out_buf_, 0);
    if (s == LinkStatus::kBusy) {
        ++counters_.write_busy;
        return DeviceStatus::kNoData;
    }
    if (s == LinkStatus::kDisconnected) return DeviceStatus::kDisconnected;
    return s == LinkStatus::kOk ? DeviceStatus::kOk : DeviceStatus::kError;
}

}  // namespace kerf::firmware_host
