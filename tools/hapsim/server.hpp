// The emulator's event loop: accepts the host on the Unix socket, feeds datagrams to the
// protocol side, applies transport faults (drop, delay, corrupt, short, unplug) to device
// replies, runs the real-time clock when not in lockstep, and takes commands on stdin.
#pragma once

#include <time.h>

#include <chrono>
#include <deque>
#include <string>
#include <vector>

#include "firmware_host/transport/seqpacket_socket.hpp"
#include "tools/hapsim/emulated_device.hpp"

namespace kerf::hapsim {

struct ServerOptions {
    bool lockstep = true;
    std::chrono::microseconds period{1000};
    bool commands = false;  ///< read `fault ...` / `quit` lines from stdin, ack on stdout
};

class Server {
public:
    Server(firmware_host::SeqpacketListener listener, EmulatedDevice& device, Simulation& sim,
           const ServerOptions& options);
    /// Runs until `quit`, stdin EOF (with commands) or SIGINT/SIGTERM. Returns the exit code.
    int run();

private:
    using Clock = std::chrono::steady_clock;
    void handle_command(const std::string& line);
    void read_stdin();
    void read_connection();
    void flush(Outbox& out);
    void send_due();
    void disconnect();
    timespec poll_timeout() const;

    firmware_host::SeqpacketListener listener_;
    firmware_host::SeqpacketSocket conn_{-1};
    EmulatedDevice& device_;
    Simulation& sim_;
    ServerOptions options_;
    bool quit_ = false;
    bool stdin_open_ = true;
    std::string stdin_buf_;
    Clock::time_point next_period_{};
    std::deque<std::pair<Clock::time_point, std::vector<std::byte>>> delayed_;
};

}  // namespace kerf::hapsim
