// FalconDevice — the Novint Falcon over a UsbLink (libusb on hardware, the emulator socket in
// tests). `open()` loads the user's firmware image (or checks that firmware answers), puts the
// FTDI in normal mode; per tick it reassembles 16-byte packets from the bulk IN stream, runs
// forward kinematics, and turns forces into clamped motor commands. No force until all three
// axes report homed: until then every command is zero with homing mode on.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "config/base/result.hpp"
#include "firmware_host/device/device.hpp"
#include "firmware_host/falcon/delta_kinematics.hpp"
#include "firmware_host/falcon/falcon_packet.hpp"
#include "firmware_host/falcon/firmware_loader.hpp"
#include "firmware_host/transport/transport_error.hpp"
#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host {

struct FalconOptions {
    falcon::DeltaGeometry geometry;
    std::string firmware_path;  ///< empty: firmware must already be loaded (checked)
    falcon::FirmwareLoadOptions load;
    std::uint32_t probe_timeout_ms = 500;  ///< how long the normal-mode check waits
    double period_s = 0.001;               ///< loop period, for the differenced velocity
};

class FalconDevice final : public Device {
public:
    static Result<std::unique_ptr<FalconDevice>, TransportError> open(std::unique_ptr<UsbLink> link,
                                                                      const FalconOptions& options);

    DeviceStatus try_read(DeviceSample& out, std::uint32_t timeout_us) noexcept override;
    DeviceStatus try_write(const DeviceCommand& command) noexcept override;
    const DeviceCounters& counters() const noexcept override { return counters_; }

    /// The last decoded packet (encoder counts, homed flags, buttons).
    const falcon::FalconReport& last_report() const noexcept { return report_; }
    /// Arm angles of the last sample (rad).
    const Vec3& joint_angles() const noexcept { return theta_; }

private:
    FalconDevice(std::unique_ptr<UsbLink> link, const FalconOptions& options) noexcept;
    // Appends payload to the stream buffer and decodes complete packets; newest wins.
    // Returns the number decoded; sets `malformed` when bad frames were dropped.
    int consume(std::span<const std::byte> payload, bool& malformed) noexcept;
    bool to_sample(DeviceSample& out) noexcept;

    std::unique_ptr<UsbLink> link_;
    FalconOptions options_;
    falcon::DeltaKinematics kinematics_;
    DeviceCounters counters_;
    falcon::FalconReport report_;
    Vec3 theta_{};
    Vec3 position_{0.0, 0.0, 0.11};
    bool have_position_ = false;
    bool enabled_ = false;
    std::uint64_t fresh_count_ = 0;
    std::array<std::byte, 512> transfer_{};
    std::array<std::byte, 512> payload_{};
    std::array<std::byte, 64> stream_{};
    std::size_t stream_len_ = 0;
    std::array<std::byte, falcon::kPacketSize> out_buf_{};
};

}  // namespace kerf::firmware_host
