// UsbLink — the small USB interface the Falcon code talks to: vendor control requests and bulk
// transfers on one FTDI interface. Implemented for real hardware by LibusbLink (libusb, transfers
// allocated once at open) and for the emulator by SocketUsbLink (kerf-hapsim over a Unix socket),
// so the Falcon host code above it runs unchanged against either.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace kerf::firmware_host {

/// Outcome of one transfer. Like hidapi's return codes, plain and few.
enum class LinkStatus : std::uint8_t {
    kOk,
    kTimeout,       ///< nothing completed within the timeout (bulk_read: no data yet)
    kBusy,          ///< the previous bulk OUT is still in flight
    kStall,         ///< the device refused a control request
    kDisconnected,  ///< the device is gone (unplugged, emulator closed the socket)
    kOverflow,      ///< the device sent more than the buffer holds
    kError,         ///< any other I/O error
};
std::string_view to_string(LinkStatus status) noexcept;

class UsbLink {
public:
    virtual ~UsbLink() = default;

    /// A vendor OUT control request without data stage, bounded by `timeout_ms`.
    virtual LinkStatus control_transfer(std::uint8_t request_type, std::uint8_t request,
                                        std::uint16_t value, std::uint16_t index,
                                        std::uint32_t timeout_ms) noexcept = 0;

    /// Queues `data` on bulk OUT (0x02); waits at most `timeout_ms` for it to complete
    /// (0: submit and return; a later call returns kBusy while it is in flight).
    /// @pre data.size() <= 64.
    virtual LinkStatus bulk_write(std::span<const std::byte> data,
                                  std::uint32_t timeout_ms) noexcept = 0;

    /// Takes one completed bulk IN (0x81) transfer into `buffer`, FTDI status bytes included
    /// (2 per 64-byte USB packet); waits at most `timeout_us` (0: only what already completed).
    /// `received` is the byte count on kOk.
    virtual LinkStatus bulk_read(std::span<std::byte> buffer, std::size_t& received,
                                 std::uint32_t timeout_us) noexcept = 0;
};

}  // namespace kerf::firmware_host
