#include "firmware_host/transport/socket_usb_link.hpp"

#include <array>
#include <chrono>
#include <cstring>

#include "firmware_host/transport/socket_tags.hpp"

namespace kerf::firmware_host {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

LinkStatus SocketUsbLink::control_transfer(std::uint8_t request_type, std::uint8_t request,
                                           std::uint16_t value, std::uint16_t index,
                                           std::uint32_t timeout_ms) noexcept {
    const std::array<std::byte, 6> setup = {std::byte{request_type},
                                            std::byte{request},
                                            std::byte{static_cast<std::uint8_t>(value & 0xFF)},
                                            std::byte{static_cast<std::uint8_t>(value >> 8)},
                                            std::byte{static_cast<std::uint8_t>(index & 0xFF)},
                                            std::byte{static_cast<std::uint8_t>(index >> 8)}};
    if (auto s = socket_.try_send_tagged(tag::kControl, setup); s != LinkStatus::kOk) return s;
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
    std::array<std::byte, 600> reply{};
    for (;;) {  // bulk IN data queued before the reply is stale: the FTDI purges it too
        std::size_t n = 0;
        const auto s = socket_.receive(reply, n, us_until(deadline));
        if (s == LinkStatus::kOverflow) continue;
        if (s != LinkStatus::kOk) return s;
        if (n == 2 && reply[0] == tag::kControlReply) {
            return reply[1] == std::byte{1} ? LinkStatus::kOk : LinkStatus::kStall;
        }
        if (us_until(deadline) == 0) return LinkStatus::kTimeout;
    }
}

LinkStatus SocketUsbLink::bulk_write(std::span<const std::byte> data,
                                     std::uint32_t /*timeout_ms*/) noexcept {
    return socket_.try_send_tagged(tag::kOut, data);
}

LinkStatus SocketUsbLink::bulk_read(std::span<std::byte> buffer, std::size_t& received,
                                    std::uint32_t timeout_us) noexcept {
    received = 0;
    const auto deadline = Clock::now() + std::chrono::microseconds(timeout_us);
    std::array<std::byte, 600> datagram{};
    for (;;) {
        std::size_t n = 0;
        const auto s = socket_.receive(datagram, n, us_until(deadline));
        if (s != LinkStatus::kOk) return s;
        if (n >= 1 && datagram[0] == tag::kIn) {
            if (n - 1 > buffer.size()) return LinkStatus::kOverflow;
            std::memcpy(buffer.data(), datagram.data() + 1, n - 1);
            received = n - 1;
            return LinkStatus::kOk;
        }
        // A stray control reply: ignore it and keep waiting within the bound.
    }
}

}  // namespace kerf::firmware_host
