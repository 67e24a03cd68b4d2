// FTDI FT232 set-up for the Novint Falcon, done as vendor control requests over UsbLink
// (PROTOCOL.md §6), and the removal of the 2 modem-status bytes that start every 64-byte USB
// packet on bulk IN. Set-up runs at open time (bounded timeouts, not real-time); the stripping
// is pure and real-time safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host::falcon {

inline constexpr std::uint16_t kFalconVendorId = 0x0403;   ///< FTDI
inline constexpr std::uint16_t kFalconProductId = 0xCB48;  ///< Novint Falcon
inline constexpr std::uint8_t kBulkOutEndpoint = 0x02;
inline constexpr std::uint8_t kBulkInEndpoint = 0x81;
inline constexpr std::size_t kUsbPacketSize = 64;  ///< full-speed bulk max packet
inline constexpr std::size_t kFtdiStatusBytes = 2;

/// FTDI vendor requests (bmRequestType 0x40, wIndex 0).
namespace ftdi {
inline constexpr std::uint8_t kRequestType = 0x40;
inline constexpr std::uint8_t kReset = 0x00;         ///< wValue: 0 reset, 1 purge RX, 2 purge TX
inline constexpr std::uint8_t kModemControl = 0x01;  ///< DTR/RTS with mask in the high byte
inline constexpr std::uint8_t kFlowControl = 0x02;
inline constexpr std::uint8_t kBaudDivisor = 0x03;
inline constexpr std::uint8_t kDataFormat = 0x04;
inline constexpr std::uint8_t kLatencyTimer = 0x09;
inline constexpr std::uint16_t kPurgeRx = 1;
inline constexpr std::uint16_t kPurgeTx = 2;
inline constexpr std::uint16_t kDtrHigh = 0x0101;
inline constexpr std::uint16_t kDtrLow = 0x0100;
inline constexpr std::uint16_t kRtsLow = 0x0200;
inline constexpr std::uint16_t kBaud9600 = 0x4138;
inline constexpr std::uint16_t kBaudFirmwareLoad = 0x0015;
inline constexpr std::uint16_t kBaudNormal = 0x0002;
inline constexpr std::uint16_t kData8N1 = 0x0008;
}  // namespace ftdi

/// One control request, for tables and for the emulator's checks.
struct ControlRequest {
    std::uint8_t request = 0;
    std::uint16_t value = 0;
};

/// Copies the payload of a bulk IN transfer into `out`, dropping the 2 status bytes that start
/// each 64-byte packet. Returns the payload length (truncated to out.size()). Pure, noexcept.
std::size_t strip_ftdi_status(std::span<const std::byte> transfer,
                              std::span<std::byte> out) noexcept;

/// Sends `requests` in order; stops at the first failure and returns its status.
LinkStatus send_requests(UsbLink& link, std::span<const ControlRequest> requests,
                         std::uint32_t timeout_ms) noexcept;

/// The requests that put the FTDI into the boot loader's serial format (before the handshake).
std::span<const ControlRequest> firmware_mode_requests() noexcept;
/// The requests that follow a good handshake: DTR low, 0x15 divisor for the image transfer.
std::span<const ControlRequest> firmware_load_requests() noexcept;
/// The requests for normal 1 kHz operation: latency 1 ms, divisor 0x0002, purge RX/TX.
std::span<const ControlRequest> normal_mode_requests() noexcept;

}  // namespace kerf::firmware_host::falcon
