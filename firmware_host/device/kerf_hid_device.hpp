// KerfHidDevice — a device speaking Kerf's HID protocol (PROTOCOL.md), over hidapi or the
// emulator socket. `open()` runs the start-up sequence (identity, mechanics, configuration);
// per tick it decodes input reports and encodes output reports in buffers it owns.
#pragma once

#include <array>
#include <memory>
#include <optional>

#include "config/base/result.hpp"
#include "firmware_host/device/device.hpp"
#include "firmware_host/protocol/kerf_hid_codec.hpp"
#include "firmware_host/transport/report_transport.hpp"
#include "firmware_host/transport/transport_error.hpp"

namespace kerf::firmware_host {

struct KerfHidOptions {
    std::uint16_t watchdog_ms = 10;  ///< device-side watchdog period to configure
    std::uint32_t feature_timeout_ms = 1000;
    std::uint16_t expected_vendor_id = 0;  ///< 0: accept any
    std::uint16_t expected_product_id = 0;
    std::uint32_t max_command_lag = 2;  ///< echo lag beyond this marks samples stale
};

class KerfHidDevice final : public Device {
public:
    /// Start-up sequence: get identity + mechanics, check them, set the configuration.
    static Result<std::unique_ptr<KerfHidDevice>, TransportError> open(
        std::unique_ptr<ReportTransport> transport, const KerfHidOptions& options);

    DeviceStatus try_read(DeviceSample& out, std::uint32_t timeout_us) noexcept override;
    DeviceStatus try_write(const DeviceCommand& command) noexcept override;
    const DeviceCounters& counters() const noexcept override { return counters_; }

    const IdentityReport& identity() const noexcept { return identity_; }
    const MechanicsReport& mechanics() const noexcept { return mechanics_; }
    /// Shutdown sequence: zero command without enable, then amplifiers off by feature report.
    LinkStatus shutdown(std::uint32_t timeout_ms) noexcept;

private:
    KerfHidDevice(std::unique_ptr<ReportTransport> transport,
                  const KerfHidOptions& options) noexcept;
    void to_sample(const InputReport& in, DeviceSample& out) noexcept;
    std::optional<TransportError> check_identity() const;

    std::unique_ptr<ReportTransport> transport_;
    KerfHidOptions options_;
    IdentityReport identity_;
    MechanicsReport mechanics_;
    DeviceCounters counters_;
    DeviceFlags flags_;
    std::uint16_t out_sequence_ = 0;
    std::uint16_t last_in_sequence_ = 0;
    bool have_input_ = false;
    std::uint64_t fresh_count_ = 0;
    std::array<std::byte, kReportSize> in_buf_{};
    std::array<std::byte, kReportSize> out_buf_{};
};

}  // namespace kerf::firmware_host
