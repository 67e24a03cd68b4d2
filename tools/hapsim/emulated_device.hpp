// The device side of one wire protocol inside kerf-hapsim: it reacts to host datagrams (tag
// byte + USB transfer / HID report, PROTOCOL.md §7) and to the real-time clock, stepping the
// shared Simulation, and queues its replies. Both protocols implement it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "tools/hapsim/simulation.hpp"

namespace kerf::hapsim {

/// Replies queued by a protocol side, one datagram each (tag byte included).
struct Outbox {
    std::vector<std::vector<std::byte>> datagrams;
    void push(std::byte tag, std::span<const std::byte> payload);
};

class EmulatedDevice {
public:
    virtual ~EmulatedDevice() = default;
    /// A datagram from the host; in lockstep mode a periodic packet steps the simulation once.
    virtual void on_datagram(std::span<const std::byte> datagram, Outbox& out) = 0;
    /// Real-time mode: one device period elapsed.
    virtual void on_period(Outbox& out) = 0;
    /// The host went away (or the emulator unplugged): forces off, state back to power-up.
    virtual void on_disconnect() = 0;
};

}  // namespace kerf::hapsim
