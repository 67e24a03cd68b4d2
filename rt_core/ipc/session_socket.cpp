#include "rt_core/ipc/session_socket.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace kerf::ipc {
namespace {

constexpr std::uint64_t kHelloMagic = 0x314F4C4C45484B4Bull;  // "KKHELLO1" little-endian
constexpr int kMaxFds = 2;

/// The one message a server sends: who it is and whether descriptors follow.
struct Hello {
    std::uint64_t magic = kHelloMagic;
    std::uint64_t session_id = 0;
    std::uint32_t refused = 0;   ///< 1: the peer's credentials were not allowed
    std::uint32_t fd_count = 0;  ///< descriptors attached (segment, then journal)
};

std::string octal(mode_t mode) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04o", unsigned(mode & 07777));
    return buf;
}

bool fill_address(sockaddr_un& addr, const std::string& path) {
    addr = {};
    addr.sun_family = AF_UNIX;
    if (path.size() >= sizeof addr.sun_path) return false;
    std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
    return true;
}

// Connects a stream socket to `path`; returns the fd or -errno.
int connect_to(const std::string& path) {
    sockaddr_un addr;
    if (!fill_address(addr, path)) return -ENAMETOOLONG;
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -errno;
    if (connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int e = errno;
        close(fd);
        return -e;
    }
    return fd;
}

bool peer_credentials(int fd, ucred& cred) {
    socklen_t len = sizeof cred;
    return getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0 && len == sizeof cred;
}

// Creates `path` as a folder (or accepts an existing one of ours) with exactly `mode` and group.
Status<IpcError> ensure_dir(const std::string& path, mode_t mode, gid_t group, bool set_group) {
    if (mkdir(path.c_str(), mode) != 0 && errno != EEXIST) {
        return Err{os_error("runtime folder " + path, "mkdir", errno)};
    }
    const int fd = open(path.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        return Err{
            IpcError{IpcErrc::kUntrusted, "runtime folder " + path,
                     std::string("not a folder (or a symbolic link): ") + std::strerror(errno)}};
    }
    struct stat st {};
    fstat(fd, &st);
    if (st.st_uid != geteuid()) {
        close(fd);
        return Err{IpcError{IpcErrc::kUntrusted, "runtime folder " + path,
                            "owned by uid " + std::to_string(st.st_uid) +
                                ", not by this user (uid " + std::to_string(geteuid()) + ")"}};
    }
    bool ok = fchmod(fd, mode) == 0;
    if (set_group) ok = ok && fchown(fd, uid_t(-1), group) == 0;
    const int e = errno;
    close(fd);
    if (!ok) return Err{os_error("runtime folder " + path, "chmod/chown", e)};
    return {};
}

std::vector<gid_t> groups_of(pid_t pid) {
    std::vector<gid_t> out;
    std::ifstream f("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind("Groups:", 0) != 0) continue;
        std::istringstream in(line.substr(7));
        long g = 0;
        while (in >> g) out.push_back(gid_t(g));
    }
    return out;
}

}  // namespace

std::string default_runtime_dir() {
    if (const char* d = std::getenv("KERF_RUNTIME_DIR"); d != nullptr && d[0] != '\0') return d;
    if (const char* x = std::getenv("XDG_RUNTIME_DIR"); x != nullptr && x[0] == '/') {
        return std::string(x) + "/kerf";
    }
    if (geteuid() == 0) return "/run/kerf";
    return "/tmp/kerf-" + std::to_string(geteuid());
}

std::string session_dir_of(const std::string& runtime_dir, const std::string& name) {
    return runtime_dir + "/" + name;
}

std::string session_socket_of(const std::string& runtime_dir, const std::string& name) {
    return session_dir_of(runtime_dir, name) + "/socket";
}

bool peer_allowed(const PeerPolicy& policy, pid_t pid, uid_t uid, gid_t gid) {
    if (uid == policy.owner_uid || uid == 0) return true;
    if (!policy.group_allowed) return false;
    if (gid == policy.group) return true;
    const auto groups = groups_of(pid);
    return std::find(groups.begin(), groups.end(), policy.group) != groups.end();
}

Result<std::unique_ptr<SessionServer>, IpcError> SessionServer::start(
    const std::string& runtime_dir, const std::string& name, int memfd, PeerPolicy policy,
    std::uint64_t session_id) {
    std::unique_ptr<SessionServer> s(new SessionServer());
    s->memfd_ = memfd;
    s->policy_ = policy;
    s->session_id_ = session_id;
    s->dir_path_ = session_dir_of(runtime_dir, name);
    s->socket_path_ = session_socket_of(runtime_dir, name);
    const std::string where = "session " + name;
    if (runtime_dir.empty() || runtime_dir[0] != '/') {
        return Err{IpcError{IpcErrc::kBadArgument, where,
                            "runtime folder '" + runtime_dir + "' must be absolute"}};
    }
    // The runtime folder only lists session names; each session's folder guards its socket.
    if (auto ok = ensure_dir(runtime_dir, 0755, 0, false); !ok) return Err{ok.error()};
    const mode_t dir_mode = policy.group_allowed ? 0750 : 0700;
    if (auto ok = ensure_dir(s->dir_path_, dir_mode, policy.group, policy.group_allowed); !ok) {
        return Err{ok.error()};
    }
    sockaddr_un addr;
    if (!fill_address(addr, s->socket_path_)) {
        return Err{IpcError{IpcErrc::kBadArgument, where,
                            "socket path " + s->socket_path_ + " is too long"}};
    }
    struct stat st {};
    if (lstat(s->socket_path_.c_str(), &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            return Err{IpcError{IpcErrc::kInUse, where,
                                s->socket_path_ + " exists and is not a socket; remove it"}};
        }
        const int probe = connect_to(s->socket_path_);
        if (probe >= 0) {
            ucred cred{};
            const bool known = peer_credentials(probe, cred);
            close(probe);
            return Err{
                IpcError{IpcErrc::kInUse, where,
                         "a live producer" +
                             (known ? " (pid " + std::to_string(cred.pid) + ")" : std::string()) +
                             " serves " + s->socket_path_}};
        }
        if (probe != -ECONNREFUSED) {
            return Err{os_error(where, "probing " + s->socket_path_, -probe)};
        }
        spdlog::info("kerf ipc: {}: removing the stale socket of a dead session", where);
        unlink(s->socket_path_.c_str());
    }
    s->listen_fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (s->listen_fd_ < 0) return Err{os_error(where, "socket", errno)};
    if (bind(s->listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int e = errno;
        if (e == EADDRINUSE) {
            return Err{
                IpcError{IpcErrc::kInUse, where, "another producer bound " + s->socket_path_}};
        }
        return Err{os_error(where, "bind " + s->socket_path_, e)};
    }
    s->bound_ = true;  // from here on the socket is ours to remove
    const mode_t socket_mode = policy.group_allowed ? 0660 : 0600;
    if (chmod(s->socket_path_.c_str(), socket_mode) != 0 ||
        (policy.group_allowed && chown(s->socket_path_.c_str(), uid_t(-1), policy.group) != 0) ||
        listen(s->listen_fd_, 16) != 0 || pipe2(s->wake_, O_CLOEXEC) != 0) {
        return Err{os_error(where, "socket setup", errno)};
    }
    SessionServer* raw = s.get();
    s->thread_ = std::thread([raw] { raw->run(); });
    return s;
}

SessionServer::~SessionServer() {
    if (thread_.joinable()) {
        const char stop = 1;
        (void)!write(wake_[1], &stop, 1);
        thread_.join();
    }
    if (bound_) {
        unlink(socket_path_.c_str());
        rmdir(dir_path_.c_str());  // only if empty: journals stay as the recording
    }
    for (int fd : {listen_fd_, memfd_, journal_fd_.load(), wake_[0], wake_[1]}) {
        if (fd >= 0) close(fd);
    }
}

void SessionServer::set_journal_fd(int fd) noexcept {
    const int old = journal_fd_.exchange(fd);
    if (old >= 0) close(old);
}

void SessionServer::run() noexcept {
    // Threads inherit the creator's policy: this one must never compete with a SCHED_FIFO loop.
    sched_param normal{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
    for (;;) {
        pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {wake_[0], POLLIN, 0}};
        if (poll(fds, 2, -1) < 0) {
            if (errno == EINTR) continue;
            return;
        }
        if (fds[1].revents != 0) return;
        if ((fds[0].revents & POLLIN) == 0) continue;
        const int client = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
        if (client < 0) continue;
        serve(client);
        close(client);
    }
}

void SessionServer::serve(int client) noexcept {
    Hello hello;
    hello.session_id = session_id_;
    ucred cred{};
    if (!peer_credentials(client, cred) || !peer_allowed(policy_, cred.pid, cred.uid, cred.gid)) {
        refused_.fetch_add(1);
        hello.refused = 1;
        (void)!send(client, &hello, sizeof hello, MSG_NOSIGNAL | MSG_DONTWAIT);
        return;
    }
    int fds[kMaxFds] = {memfd_, journal_fd_.load()};
    hello.fd_count = fds[1] >= 0 ? 2 : 1;
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * kMaxFds)] = {};
    iovec iov{&hello, sizeof hello};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = CMSG_SPACE(sizeof(int) * hello.fd_count);
    cmsghdr* c = CMSG_FIRSTHDR(&msg);
    c->cmsg_level = SOL_SOCKET;
    c->cmsg_type = SCM_RIGHTS;
    c->cmsg_len = CMSG_LEN(sizeof(int) * hello.fd_count);
    std::memcpy(CMSG_DATA(c), fds, sizeof(int) * hello.fd_count);
    if (sendmsg(client, &msg, MSG_NOSIGNAL | MSG_DONTWAIT) == static_cast<ssize_t>(sizeof hello)) {
        served_.fetch_add(1);
    }
}

Result<SessionFds, IpcError> fetch_session(const std::string& runtime_dir,
                                           const std::string& name) {
    const std::string where = "session " + name;
    const std::string dir = session_dir_of(runtime_dir, name);
    const std::string path = session_socket_of(runtime_dir, name);
    struct stat dst {};
    if (lstat(dir.c_str(), &dst) != 0) {
        if (errno == ENOENT) {
            return Err{
                IpcError{IpcErrc::kNotFound, where, "no such session (no folder " + dir + ")"}};
        }
        return Err{os_error(where, dir, errno)};
    }
    if (!S_ISDIR(dst.st_mode) || (dst.st_mode & 0002) != 0) {
        return Err{
            IpcError{IpcErrc::kUntrusted, where,
                     dir + " is not a private folder (mode " + octal(dst.st_mode) + "); refused"}};
    }
    struct stat sst {};
    if (lstat(path.c_str(), &sst) != 0) {
        if (errno == ENOENT) {
            return Err{IpcError{IpcErrc::kNotFound, where,
                                "no such session (no socket " + path + "; the session has ended)"}};
        }
        return Err{os_error(where, path, errno)};
    }
    if (!S_ISSOCK(sst.st_mode)) {
        return Err{IpcError{IpcErrc::kUntrusted, where, path + " is not a socket"}};
    }
    const int fd = connect_to(path);
    if (fd == -ECONNREFUSED) {
        return Err{IpcError{IpcErrc::kProducerGone, where,
                            "stale socket " + path + ": no process listens (its producer died)"}};
    }
    if (fd < 0) return Err{os_error(where, "connect " + path, -fd)};
    ucred cred{};
    if (!peer_credentials(fd, cred)) {
        close(fd);
        return Err{os_error(where, "SO_PEERCRED", errno)};
    }
    if (cred.uid != dst.st_uid || cred.uid != sst.st_uid) {
        close(fd);
        return Err{IpcError{IpcErrc::kUntrusted, where,
                            "served by uid " + std::to_string(cred.uid) +
                                " but the folder belongs to uid " + std::to_string(dst.st_uid) +
                                " and the socket to uid " + std::to_string(sst.st_uid)}};
    }
    timeval timeout{2, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    Hello hello{};
    hello.magic = 0;
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * 4)] = {};
    iovec iov{&hello, sizeof hello};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    ssize_t n = -1;
    do {
        n = recvmsg(fd, &msg, MSG_CMSG_CLOEXEC | MSG_WAITALL);
    } while (n < 0 && errno == EINTR);
    const int e = errno;
    close(fd);
    std::vector<int> received;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); n > 0 && c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
        if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_RIGHTS) continue;
        const std::size_t count = (c->cmsg_len - CMSG_LEN(0)) / sizeof(int);
        for (std::size_t i = 0; i < count; ++i) {
            int got = -1;
            std::memcpy(&got, CMSG_DATA(c) + i * sizeof(int), sizeof got);
            received.push_back(got);
        }
    }
    auto fail = [&](IpcError error) -> Result<SessionFds, IpcError> {
        for (int r : received) close(r);
        return Err{std::move(error)};
    };
    if (n < 0) return fail(os_error(where, "receiving from " + path, e));
    if (n != static_cast<ssize_t>(sizeof hello) || hello.magic != kHelloMagic) {
        return fail(IpcError{IpcErrc::kCorrupt, where,
                             path + " answered " + std::to_string(n) +
                                 " bytes that are not a Kerf session greeting"});
    }
    if (hello.refused != 0) {
        return fail(IpcError{IpcErrc::kUntrusted, where,
                             "the producer (pid " + std::to_string(cred.pid) +
                                 ") refused this user (uid " + std::to_string(geteuid()) + ")"});
    }
    if ((msg.msg_flags & MSG_CTRUNC) != 0 || received.empty() ||
        received.size() != hello.fd_count || received.size() > kMaxFds) {
        return fail(IpcError{IpcErrc::kCorrupt, where,
                             "expected " + std::to_string(hello.fd_count) +
                                 " descriptors, received " + std::to_string(received.size())});
    }
    SessionFds out;
    out.segment_fd = received[0];
    out.journal_fd = received.size() > 1 ? received[1] : -1;
    out.producer_pid = cred.pid;
    out.producer_uid = cred.uid;
    out.producer_gid = cred.gid;
    out.session_id = hello.session_id;
    return out;
}

std::vector<SessionEntry> list_session_dirs(const std::string& runtime_dir) {
    std::vector<SessionEntry> out;
    DIR* d = opendir(runtime_dir.c_str());
    if (d == nullptr) return out;
    while (dirent* e = readdir(d)) {
        const std::string n = e->d_name;
        if (n == "." || n == "..") continue;
        struct stat st {};
        if (lstat(session_dir_of(runtime_dir, n).c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
            continue;
        SessionEntry entry{n, false};
        entry.has_socket =
            lstat(session_socket_of(runtime_dir, n).c_str(), &st) == 0 && S_ISSOCK(st.st_mode);
        out.push_back(std::move(entry));
    }
    closedir(d);
    std::sort(out.begin(), out.end(),
              [](const SessionEntry& a, const SessionEntry& b) { return a.name < b.name; });
    return out;
}

bool remove_stale_socket(const std::string& runtime_dir, const std::string& name) {
    const std::string path = session_socket_of(runtime_dir, name);
    struct stat st {};
    if (lstat(path.c_str(), &st) != 0 || !S_ISSOCK(st.st_mode)) return false;
    if (st.st_uid != geteuid() && geteuid() != 0) return false;
    const int fd = connect_to(path);
    if (fd >= 0) {
        close(fd);
        return false;
    }
    if (fd != -ECONNREFUSED) return false;
    if (unlink(path.c_str()) != 0) return false;
    rmdir(session_dir_of(runtime_dir, name).c_str());  // only if empty
    return true;
}

}  // namespace kerf::ipc
