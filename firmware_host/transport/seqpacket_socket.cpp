#include "firmware_host/transport/seqpacket_socket.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace kerf::firmware_host {
namespace {

// A failed system call: nothing there (ENOENT, ECONNREFUSED) is kNotConnected, the rest kSystem.
Err<TransportError> os_error(std::string_view action, std::string where, int err) {
    const bool absent = err == ENOENT || err == ECONNREFUSED;
    return Err{transport_error(absent ? TransportErrc::kNotConnected : TransportErrc::kSystem,
                               std::move(where), action, std::strerror(err))};
}

bool fill_address(const std::string& path, sockaddr_un& addr) noexcept {
    std::memset(&addr, 0, sizeof addr);
    addr.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof addr.sun_path) return false;
    std::memcpy(addr.sun_path, path.data(), path.size());
    return true;
}

LinkStatus from_errno(int err) noexcept {
    if (err == EAGAIN || err == EWOULDBLOCK) return LinkStatus::kBusy;
    if (err == EPIPE || err == ECONNRESET || err == ENOTCONN) return LinkStatus::kDisconnected;
    return LinkStatus::kError;
}

// Waits for `fd` to become readable; false on timeout or error.
bool wait_readable(int fd, std::uint32_t timeout_us) noexcept {
    pollfd p{fd, POLLIN, 0};
    const timespec ts{static_cast<time_t>(timeout_us / 1000000U),
                      static_cast<long>((timeout_us % 1000000U) * 1000U)};
    int r = 0;
    do {
        r = ppoll(&p, 1, &ts, nullptr);
    } while (r < 0 && errno == EINTR);
    return r > 0;
}

}  // namespace

Result<SeqpacketSocket, TransportError> SeqpacketSocket::connect(const std::string& path) {
    sockaddr_un addr{};
    if (!fill_address(path, addr)) {
        return Err{transport_error(TransportErrc::kBadPath, path, "connect to emulator socket",
                                   "path empty or too long")};
    }
    // Non-blocking: a listener that accepts nobody (the emulator's unplug fault) lets a blocking
    // connect() wait forever once its backlog is full, and kerf-rt's reconnector could then never
    // be stopped. A Unix socket connects at once or says EAGAIN (backlog full): not connected.
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) return os_error("create socket", path, errno);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int err = errno;
        ::close(fd);
        if (err == EAGAIN)
            return Err{transport_error(TransportErrc::kNotConnected, path,
                                       "connect to emulator socket",
                                       "it accepts no connection (backlog full)")};
        return os_error("connect to emulator socket", path, err);
    }
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags < 0 || ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0) {
        const int err = errno;
        ::close(fd);
        return os_error("connect to emulator socket", path, err);
    }
    return SeqpacketSocket(fd);
}

SeqpacketSocket::SeqpacketSocket(SeqpacketSocket&& other) noexcept : fd_(other.fd_) {
    other.fd_ = -1;
}

SeqpacketSocket& SeqpacketSocket::operator=(SeqpacketSocket&& other) noexcept {
    if (this != &other) {
        close();
        fd_ = other.fd_;
        other.fd_ = -1;
    }
    return *this;
}

SeqpacketSocket::~SeqpacketSocket() { close(); }

void SeqpacketSocket::close() noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

LinkStatus SeqpacketSocket::try_send(std::span<const std::byte> datagram) noexcept {
    if (fd_ < 0) return LinkStatus::kDisconnected;
    const auto n = ::send(fd_, datagram.data(), datagram.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n < 0) return from_errno(errno);
    return LinkStatus::kOk;
}

LinkStatus SeqpacketSocket::try_send_tagged(std::byte tag,
                                            std::span<const std::byte> payload) noexcept {
    if (fd_ < 0) return LinkStatus::kDisconnected;
    iovec iov[2] = {{&tag, 1}, {const_cast<std::byte*>(payload.data()), payload.size()}};
    msghdr msg{};
    msg.msg_iov = iov;
    msg.msg_iovlen = payload.empty() ? 1 : 2;
    const auto n = ::sendmsg(fd_, &msg, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n < 0) return from_errno(errno);
    return LinkStatus::kOk;
}

LinkStatus SeqpacketSocket::receive(std::span<std::byte> buffer, std::size_t& received,
                                    std::uint32_t timeout_us) noexcept {
    received = 0;
    if (fd_ < 0) return LinkStatus::kDisconnected;
    ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT | MSG_TRUNC);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK) && timeout_us > 0) {
        if (!wait_readable(fd_, timeout_us)) return LinkStatus::kTimeout;
        n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT | MSG_TRUNC);
    }
    if (n < 0) {
        const auto s = from_errno(errno);
        return s == LinkStatus::kBusy ? LinkStatus::kTimeout : s;
    }
    if (n == 0) return LinkStatus::kDisconnected;  // peer closed (we never send empty datagrams)
    if (static_cast<std::size_t>(n) > buffer.size()) return LinkStatus::kOverflow;
    received = static_cast<std::size_t>(n);
    return LinkStatus::kOk;
}

Result<SeqpacketListener, TransportError> SeqpacketListener::listen(const std::string& path) {
    sockaddr_un addr{};
    if (!fill_address(path, addr)) {
        return Err{transport_error(TransportErrc::kBadPath, path, "listen on emulator socket",
                                   "path empty or too long")};
    }
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            return Err{transport_error(TransportErrc::kBadPath, path, "listen on emulator socket",
                                       "a file that is not a socket is in the way")};
        }
        // A socket with a live listener belongs to a running process: never take it over. Only
        // a stale one (connect refused: its emulator died) is replaced.
        const int probe = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
        if (probe < 0) return os_error("create socket", path, errno);
        const int rc = ::connect(probe, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
        const int err = rc == 0 ? 0 : errno;
        ::close(probe);
        if (err != ECONNREFUSED) {
            return Err{transport_error(
                TransportErrc::kBadPath, path, "listen on emulator socket",
                err == 0 || err == EAGAIN || err == EINPROGRESS || err == EPROTOTYPE
                    ? "another process is listening on this socket (a running kerf-hapsim?); "
                      "refused to take it over: stop that process or choose another path"
                    : std::string("cannot tell whether another process listens on it (") +
                          std::strerror(err) + "); refused")};
        }
        ::unlink(path.c_str());  // stale socket from an emulator that died
    }
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    if (fd < 0) return os_error("create socket", path, errno);
    if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(fd, 4) != 0) {
        const int err = errno;
        ::close(fd);
        return os_error("listen on emulator socket", path, err);
    }
    return SeqpacketListener(fd, path);
}

SeqpacketListener::SeqpacketListener(SeqpacketListener&& other) noexcept
    : fd_(other.fd_), path_(std::move(other.path_)) {
    other.fd_ = -1;
}

SeqpacketListener::~SeqpacketListener() {
    if (fd_ >= 0) {
        ::close(fd_);
        ::unlink(path_.c_str());
    }
}

SeqpacketSocket SeqpacketListener::accept(std::uint32_t timeout_ms) noexcept {
    if (!wait_readable(fd_, timeout_ms * 1000U)) return SeqpacketSocket(-1);
    return SeqpacketSocket(::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC));
}

Result<std::pair<SeqpacketSocket, SeqpacketSocket>, TransportError> seqpacket_pair() {
    int fds[2] = {-1, -1};
    if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds) != 0) {
        return os_error("socketpair", "AF_UNIX SOCK_SEQPACKET", errno);
    }
    return std::pair<SeqpacketSocket, SeqpacketSocket>{SeqpacketSocket(fds[0]),
                                                       SeqpacketSocket(fds[1])};
}

}  // namespace kerf::firmware_host
