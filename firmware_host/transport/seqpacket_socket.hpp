// A connected Unix SOCK_SEQPACKET socket (one datagram = one USB transfer or HID report, with
// the tag byte of PROTOCOL.md §7) and the listener kerf-hapsim accepts on. Built by
// `connect()` / `listen()` returning a Result; the per-tick calls never block beyond their
// timeout and never allocate.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "config/base/result.hpp"
#include "firmware_host/transport/transport_error.hpp"
#include "firmware_host/transport/usb_link.hpp"

namespace kerf::firmware_host {

class SeqpacketSocket {
public:
    /// Connects to a listening socket at `path` (open-time, may allocate); never waits for a
    /// listener that accepts nobody (kNotConnected when its backlog is full).
    static Result<SeqpacketSocket, TransportError> connect(const std::string& path);
    /// Adopts a connected descriptor (accept(), socketpair()).
    explicit SeqpacketSocket(int fd) noexcept : fd_(fd) {}
    SeqpacketSocket(SeqpacketSocket&& other) noexcept;
    SeqpacketSocket& operator=(SeqpacketSocket&& other) noexcept;
    SeqpacketSocket(const SeqpacketSocket&) = delete;
    SeqpacketSocket& operator=(const SeqpacketSocket&) = delete;
    ~SeqpacketSocket();

    /// Sends one datagram without waiting: kOk, kBusy (buffer full), kDisconnected.
    LinkStatus try_send(std::span<const std::byte> datagram) noexcept;
    /// Sends `tag` followed by `payload` as one datagram (no allocation: scatter-gather).
    LinkStatus try_send_tagged(std::byte tag, std::span<const std::byte> payload) noexcept;
    /// Receives one datagram, waiting at most `timeout_us` (0: only what is queued).
    /// kTimeout when none; kOverflow when it did not fit (the datagram is consumed).
    LinkStatus receive(std::span<std::byte> buffer, std::size_t& received,
                       std::uint32_t timeout_us) noexcept;

    int fd() const noexcept { return fd_; }
    bool valid() const noexcept { return fd_ >= 0; }
    void close() noexcept;

private:
    int fd_ = -1;
};

/// Microseconds from now until `deadline` (0 once it has passed): the `timeout_us` to give
/// receive() so that several receives share one deadline. noexcept, no allocation.
inline std::uint32_t us_until(std::chrono::steady_clock::time_point deadline) noexcept {
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(
        deadline - std::chrono::steady_clock::now());
    return left.count() > 0 ? static_cast<std::uint32_t>(left.count()) : 0U;
}

class SeqpacketListener {
public:
    /// Binds and listens at `path`, replacing a stale socket file left by a dead emulator.
    static Result<SeqpacketListener, TransportError> listen(const std::string& path);
    SeqpacketListener(SeqpacketListener&& other) noexcept;
    SeqpacketListener& operator=(SeqpacketListener&&) = delete;
    SeqpacketListener(const SeqpacketListener&) = delete;
    ~SeqpacketListener();

    /// Accepts one connection within `timeout_ms`; an invalid socket on timeout.
    SeqpacketSocket accept(std::uint32_t timeout_ms) noexcept;
    int fd() const noexcept { return fd_; }

private:
    SeqpacketListener(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
    int fd_ = -1;
    std::string path_;
};

/// A connected pair (tests and the benchmark's floor).
Result<std::pair<SeqpacketSocket, SeqpacketSocket>, TransportError> seqpacket_pair();

}  // namespace kerf::firmware_host
