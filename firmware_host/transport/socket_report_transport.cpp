#include "firmware_host/transport/socket_report_transport.hpp"

#include <array>
#include <chrono>
#include <cstring>

#include "firmware_host/transport/socket_tags.hpp"

namespace kerf::firmware_host {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

LinkStatus SocketReportTransport::try_write_report(std::span<const std::byte> report) noexcept {
    return socket_.try_send_tagged(tag::kOut, report);
}

LinkStatus SocketReportTransport::await(std::byte want, std::span<std::byte> payload,
                                        std::size_t& received, std::uint32_t timeout_us) noexcept {
    received = 0;
    const auto deadline = Clock::now() + std::chrono::microseconds(timeout_us);
    std::array<std::byte, 256> datagram{};
    for (;;) {
        std::size_t n = 0;
        const auto s = socket_.receive(datagram, n, us_until(deadline));
        if (s == LinkStatus::kOverflow) continue;  // oversized datagram: not a report, dropped
        if (s != LinkStatus::kOk) return s;
        if (n >= 1 && datagram[0] == want) {
            const std::size_t len = n - 1;
            if (len > payload.size()) return LinkStatus::kOverflow;
            std::memcpy(payload.data(), datagram.data() + 1, len);
            received = len;
            return LinkStatus::kOk;
        }
    }
}

LinkStatus SocketReportTransport::read_report(std::span<std::byte> buffer, std::size_t& received,
                                              std::uint32_t timeout_us) noexcept {
    return await(tag::kIn, buffer, received, timeout_us);
}

LinkStatus SocketReportTransport::get_feature(std::uint8_t id, std::span<std::byte> buffer,
                                              std::size_t& received,
                                              std::uint32_t timeout_ms) noexcept {
    const std::array<std::byte, 1> request = {std::byte{id}};
    if (auto s = socket_.try_send_tagged(tag::kGetFeature, request); s != LinkStatus::kOk) return s;
    const auto s = await(tag::kFeature, buffer, received, timeout_ms * 1000U);
    if (s == LinkStatus::kOk && received == 0) return LinkStatus::kStall;
    return s;
}

LinkStatus SocketReportTransport::set_feature(std::span<const std::byte> report,
                                              std::uint32_t timeout_ms) noexcept {
    if (auto s = socket_.try_send_tagged(tag::kSetFeature, report); s != LinkStatus::kOk) return s;
    std::array<std::byte, 4> reply{};
    std::size_t n = 0;
    const auto s = await(tag::kSetReply, reply, n, timeout_ms * 1000U);
    if (s != LinkStatus::kOk) return s;
    return (n == 1 && reply[0] == std::byte{1}) ? LinkStatus::kOk : LinkStatus::kStall;
}

}  // namespace kerf::firmware_host
