// SocketUsbLink — UsbLink over the emulator socket: control requests, bulk OUT and bulk IN (with
// the FTDI status bytes) as tagged datagrams, so the Falcon host code runs unchanged against
// kerf-hapsim. No allocation after construction.
#pragma once

#include "firmware_host/transport/seqpacket_socket.hpp"
#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host {

class SocketUsbLink final : public UsbLink {
public:
    explicit SocketUsbLink(SeqpacketSocket socket) noexcept : socket_(std::move(socket)) {}

    LinkStatus control_transfer(std::uint8_t request_type, std::uint8_t request,
                                std::uint16_t value, std::uint16_t index,
                                std::uint32_t timeout_ms) noexcept override;
    LinkStatus bulk_write(std::span<const std::byte> data,
                          std::uint32_t timeout_ms) noexcept override;
    LinkStatus bulk_read(std::span<std::byte> buffer, std::size_t& received,
                         std::uint32_t timeout_us) noexcept override;

private:
    SeqpacketSocket socket_;
};

}  // namespace kerf::firmware_host
