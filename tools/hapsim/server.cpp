#include "tools/hapsim/server.hpp"

#include <poll.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdio>
#include <sstream>

#include "firmware_host/transport/socket_tags.hpp"

namespace kerf::hapsim {
namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int) { g_stop = 1; }

}  // namespace

Server::Server(firmware_host::SeqpacketListener listener, EmulatedDevice& device, Simulation& sim,
               const ServerOptions& options)
    : listener_(std::move(listener)), device_(device), sim_(sim), options_(options) {}

void Server::handle_command(const std::string& line) {
    std::istringstream in(line);
    std::string verb, name, value;
    in >> verb >> name >> value;
    if (verb.empty()) return;
    std::string why;
    if (verb == "quit") {
        quit_ = true;
    } else if (verb == "fault" && !name.empty() && !value.empty()) {
        why = apply_fault(sim_.faults(), name, value);
    } else if (verb == "status") {
        std::printf("status steps=%llu connected=%d\n",
                    static_cast<unsigned long long>(sim_.steps()), conn_.valid() ? 1 : 0);
    } else {
        why = "unknown command '" + line + "' (fault <name> <value> | status | quit)";
    }
    if (why.empty()) {
        std::printf("ok %s\n", line.c_str());
    } else {
        std::printf("error %s\n", why.c_str());
    }
    std::fflush(stdout);
}

void Server::read_stdin() {
    std::array<char, 512> buf{};
    const auto n = ::read(STDIN_FILENO, buf.data(), buf.size());
    if (n <= 0) {
        stdin_open_ = false;
        quit_ = true;  // the controlling test went away
        return;
    }
    stdin_buf_.append(buf.data(), static_cast<std::size_t>(n));
    for (auto nl = stdin_buf_.find('\n'); nl != std::string::npos; nl = stdin_buf_.find('\n')) {
        handle_command(stdin_buf_.substr(0, nl));
        stdin_buf_.erase(0, nl + 1);
    }
}

void Server::disconnect() {
    conn_.close();
    delayed_.clear();
    device_.on_disconnect();
}

void Server::read_connection() {
    std::array<std::byte, 600> buf{};
    for (int i = 0; i < 64; ++i) {
        std::size_t n = 0;
        const auto s = conn_.receive(buf, n, 0);
        if (s == firmware_host::LinkStatus::kTimeout || s == firmware_host::LinkStatus::kOverflow) {
            if (s == firmware_host::LinkStatus::kTimeout) return;
            continue;
        }
        if (s != firmware_host::LinkStatus::kOk) {
            disconnect();
            return;
        }
        Outbox out;
        device_.on_datagram(std::span(buf).first(n), out);
        flush(out);
        if (!conn_.valid()) return;
    }
}

// Device replies pass through the transport faults; protocol replies (control, feature) do not.
void Server::flush(Outbox& out) {
    const auto& f = sim_.faults();
    for (auto& d : out.datagrams) {
        if (!d.empty() && d[0] == firmware_host::tag::kIn) {
            if (f.drop) continue;
            if (f.corrupt && d.size() > 2) d[1 + (d.size() - 1) / 2] ^= std::byte{0x80};
            if (f.short_packets && d.size() > 2) d.resize(1 + (d.size() - 1) / 2);
            if (f.delay_ms > 0) {
                delayed_.emplace_back(Clock::now() + std::chrono::milliseconds(f.delay_ms),
                                      std::move(d));
                continue;
            }
        }
        (void)conn_.try_send(d);
    }
    out.datagrams.clear();
}

void Server::send_due() {
    const auto now = Clock::now();
    while (!delayed_.empty() && delayed_.front().first <= now) {
        (void)conn_.try_send(delayed_.front().second);
        delayed_.pop_front();
    }
}

timespec Server::poll_timeout() const {
    // ppoll with nanoseconds: poll()'s whole milliseconds would round a 1 ms period up to 2 ms
    // and the catch-up would send reports in pairs (a host reading once a tick sees gaps).
    auto next = Clock::now() + std::chrono::milliseconds(100);
    if (!options_.lockstep && conn_.valid()) next = std::min(next, next_period_);
    if (!delayed_.empty()) next = std::min(next, delayed_.front().first);
    const auto ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(next - Clock::now()).count();
    if (ns <= 0) return timespec{0, 0};
    return timespec{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
}

int Server::run() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::signal(SIGPIPE, SIG_IGN);
    next_period_ = Clock::now();
    while (!quit_ && g_stop == 0) {
        std::array<pollfd, 3> fds{};
        nfds_t n = 0;
        const bool can_accept = !conn_.valid() && !sim_.faults().unplugged;
        fds[n++] = {can_accept ? listener_.fd() : -1, POLLIN, 0};
        fds[n++] = {conn_.valid() ? conn_.fd() : -1, POLLIN, 0};
        fds[n++] = {options_.commands && stdin_open_ ? STDIN_FILENO : -1, POLLIN, 0};
        const timespec timeout = poll_timeout();
        if (::ppoll(fds.data(), n, &timeout, nullptr) < 0 && errno != EINTR) return 1;
        if ((fds[2].revents & (POLLIN | POLLHUP)) != 0) read_stdin();
        if (sim_.faults().unplugged && conn_.valid()) disconnect();
        if ((fds[0].revents & POLLIN) != 0 && can_accept) {
            conn_ = listener_.accept(0);
            next_period_ = Clock::now();
        }
        if (conn_.valid() && (fds[1].revents & (POLLIN | POLLHUP | POLLERR)) != 0)
            read_connection();
        if (!options_.lockstep && conn_.valid() && Clock::now() >= next_period_) {
            Outbox out;
            device_.on_period(out);
            flush(out);
            next_period_ += options_.period;
            if (Clock::now() > next_period_ + 10 * options_.period) next_period_ = Clock::now();
        }
        if (conn_.valid()) send_due();
        for (const auto& w : sim_.warnings()) std::fprintf(stderr, "kerf-hapsim: %s\n", w.c_str());
        sim_.warnings().clear();
    }
    return 0;
}

}  // namespace kerf::hapsim
