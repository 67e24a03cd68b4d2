// ReportTransport — how a Kerf-protocol device's 64-byte reports travel: HID over hidapi
// (HidapiTransport) or the emulator socket (SocketReportTransport). The per-tick calls
// (try_write_report, read_report) are noexcept, bounded and allocation-free; feature
// reports are open-time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host {

class ReportTransport {
public:
    virtual ~ReportTransport() = default;

    /// Sends one output report (report id in byte 0) without waiting beyond the OS write.
    virtual LinkStatus try_write_report(std::span<const std::byte> report) noexcept = 0;
    /// Receives one input report within `timeout_us` (0: non-blocking). kTimeout when none.
    virtual LinkStatus read_report(std::span<std::byte> buffer, std::size_t& received,
                                   std::uint32_t timeout_us) noexcept = 0;
    /// Gets feature report `id` into `buffer` (byte 0 = id).
    virtual LinkStatus get_feature(std::uint8_t id, std::span<std::byte> buffer,
                                   std::size_t& received, std::uint32_t timeout_ms) noexcept = 0;
    /// Sets a feature report (byte 0 = id); kStall when the device refuses it.
    virtual LinkStatus set_feature(std::span<const std::byte> report,
                                   std::uint32_t timeout_ms) noexcept = 0;
};

}  // namespace kerf::firmware_host
