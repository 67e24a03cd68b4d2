// SocketReportTransport — Kerf HID reports over the emulator socket (PROTOCOL.md §7).
#pragma once

#include "firmware_host/transport/report_transport.hpp"
#include "firmware_host/transport/seqpacket_socket.hpp"

namespace kerf::firmware_host {

class SocketReportTransport final : public ReportTransport {
public:
    explicit SocketReportTransport(SeqpacketSocket socket) noexcept : socket_(std::move(socket)) {}

    LinkStatus try_write_report(std::span<const std::byte> report) noexcept override;
    LinkStatus read_report(std::span<std::byte> buffer, std::size_t& received,
                           std::uint32_t timeout_us) noexcept override;
    LinkStatus get_feature(std::uint8_t id, std::span<std::byte> buffer, std::size_t& received,
                           std::uint32_t timeout_ms) noexcept override;
    LinkStatus set_feature(std::span<const std::byte> report,
                           std::uint32_t timeout_ms) noexcept override;

private:
    // Waits for a datagram starting with `want`; other datagrams are dropped.
    LinkStatus await(std::byte want, std::span<std::byte> payload, std::size_t& received,
                     std::uint32_t timeout_us) noexcept;
    SeqpacketSocket socket_;
};

}  // namespace kerf::firmware_host
