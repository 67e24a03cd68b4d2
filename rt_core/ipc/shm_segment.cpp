#include "rt_core/ipc/shm_segment.hpp"

#include <fcntl.h>
#include <grp.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <utility>

namespace kerf::ipc {
namespace {

bool valid_name(const std::string& name) { return valid_session_name(name); }

std::string octal(mode_t mode) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04o", unsigned(mode & 07777));
    return buf;
}

bool in_my_groups(gid_t gid) {
    if (gid == getegid()) return true;
    gid_t groups[256];
    const int n = getgroups(256, groups);
    for (int i = 0; i < n; ++i) {
        if (groups[i] == gid) return true;
    }
    return false;
}

// Trust rule at attach: the segment belongs to the producer that served it; nothing for others;
// the owner is this user or root, or the group is one of ours and the segment is group-shared.
Status<IpcError> check_trust(const std::string& where, const struct stat& st, uid_t producer_uid) {
    const std::string mode = "owner uid " + std::to_string(st.st_uid) + ", group " +
                             std::to_string(st.st_gid) + ", mode " + octal(st.st_mode);
    if (st.st_uid != producer_uid) {
        return Err{IpcError{IpcErrc::kUntrusted, where,
                            "segment (" + mode + ") was served by uid " +
                                std::to_string(producer_uid) + ", not its owner; refused"}};
    }
    if ((st.st_mode & 0007) != 0) {
        return Err{IpcError{IpcErrc::kUntrusted, where,
                            "segment (" + mode + ") is open to others; refused"}};
    }
    const bool mine = st.st_uid == geteuid() || st.st_uid == 0;
    const bool shared = (st.st_mode & 0060) == 0060 && in_my_groups(st.st_gid);
    if (!mine && !shared) {
        return Err{IpcError{IpcErrc::kUntrusted, where,
                            "segment (" + mode +
                                ") belongs to another user and is not shared with a group of "
                                "ours; refused"}};
    }
    return {};
}

std::string hex(std::uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "0x%" PRIx64, v);
    return buf;
}

std::uint64_t realtime_ns() {
    timespec ts{};
    clock_gettime(CLOCK_REALTIME, &ts);
    return std::uint64_t(ts.tv_sec) * 1'000'000'000u + std::uint64_t(ts.tv_nsec);
}

std::uint64_t random_session_id() {
    std::uint64_t id = 0;
    while (id == 0) {
        if (getrandom(&id, sizeof id, 0) != static_cast<ssize_t>(sizeof id)) {
            id = realtime_ns() ^ (std::uint64_t(getpid()) << 32);
        }
    }
    return id;
}

void fill_header(SegmentHeader& h, const std::string& journal_path) {
    h.magic = kMagic;
    h.layout_version = kLayoutVersion;
    h.header_bytes = sizeof(SegmentHeader);
    h.layout_hash = kLayoutHash;
    h.segment_bytes = sizeof(SegmentLayout);
    h.session_id = random_session_id();
    h.start_time_unix_ns = realtime_ns();
    h.producer_pid = getpid();
    h.slot_count = kSlotCount;
    h.event_capacity = kEventCapacity;
    h.telemetry_capacity = kTelemetryCapacity;
    h.mesh_max_bodies = kMeshMaxBodies;
    h.mesh_max_vertices = kMeshMaxVertices;
    h.mesh_max_indices = kMeshMaxIndices;
    std::snprintf(h.journal_path, sizeof h.journal_path, "%s", journal_path.c_str());
}

template <class T>
void diff(std::string& out, const char* field, T got, T want) {
    if (got == want) return;
    if (!out.empty()) out += "; ";
    out += std::string(field) + " " + std::to_string(got) + ", expected " + std::to_string(want);
}

}  // namespace

std::string_view to_string(ProducerHealth health) noexcept {
    switch (health) {
        case ProducerHealth::kAlive:
            return "alive";
        case ProducerHealth::kStale:
            return "stale";
        case ProducerHealth::kDead:
            return "dead";
        case ProducerHealth::kStopped:
            return "stopped";
    }
    return "unknown";
}

std::string_view to_string(SegmentState state) noexcept {
    switch (state) {
        case SegmentState::kStarting:
            return "starting";
        case SegmentState::kRunning:
            return "running";
        case SegmentState::kStopped:
            return "stopped";
    }
    return "unknown";
}

std::uint64_t monotonic_ns() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::uint64_t(ts.tv_sec) * 1'000'000'000u + std::uint64_t(ts.tv_nsec);
}

bool process_alive(std::int32_t pid) noexcept {
    if (pid <= 0) return false;
    if (kill(pid, 0) != 0 && errno != EPERM) return false;
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
    FILE* f = std::fopen(path, "re");
    if (f == nullptr) return true;  // no procfs: trust kill()
    char buf[512] = {};
    const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    const char* close_paren = std::strrchr(buf, ')');
    if (n == 0 || close_paren == nullptr || close_paren[1] == '\0') return true;
    const char state = close_paren[2];
    return state != 'Z' && state != 'X';
}

ProducerHealth producer_health(const SegmentLayout& layout, std::uint64_t stale_after_ns) noexcept {
    const auto state = layout.header.state.load(std::memory_order_acquire);
    if (state == static_cast<std::uint32_t>(SegmentState::kStopped))
        return ProducerHealth::kStopped;
    if (!process_alive(layout.header.producer_pid)) return ProducerHealth::kDead;
    const auto beat = layout.producer.heartbeat_ns.load(std::memory_order_acquire);
    const auto now = monotonic_ns();
    if (beat == 0) {  // not ticking yet: judge by the segment's age
        return ProducerHealth::kAlive;
    }
    return (now > beat && now - beat > stale_after_ns) ? ProducerHealth::kStale
                                                       : ProducerHealth::kAlive;
}

std::string journal_path_of(const SegmentHeader& header) {
    const void* nul = std::memchr(header.journal_path, '\0', sizeof header.journal_path);
    if (nul == nullptr || header.journal_path[0] != '/') return {};
    return std::string(header.journal_path);
}

Status<IpcError> check_header(const SegmentHeader& h, std::uint64_t mapped_bytes) {
    std::string out;
    if (h.magic != kMagic) out = "magic " + hex(h.magic) + ", expected " + hex(kMagic);
    diff(out, "layout version", h.layout_version, kLayoutVersion);
    diff(out, "header bytes", h.header_bytes, std::uint32_t(sizeof(SegmentHeader)));
    if (h.layout_hash != kLayoutHash) {
        if (!out.empty()) out += "; ";
        out += "layout hash " + hex(h.layout_hash) + ", expected " + hex(kLayoutHash);
    }
    diff(out, "segment bytes", h.segment_bytes, std::uint64_t(sizeof(SegmentLayout)));
    diff(out, "mapped bytes", mapped_bytes, std::uint64_t(sizeof(SegmentLayout)));
    diff(out, "slot count", h.slot_count, kSlotCount);
    diff(out, "event capacity", h.event_capacity, kEventCapacity);
    diff(out, "telemetry capacity", h.telemetry_capacity, kTelemetryCapacity);
    diff(out, "mesh max bodies", h.mesh_max_bodies, kMeshMaxBodies);
    diff(out, "mesh max vertices", h.mesh_max_vertices, kMeshMaxVertices);
    diff(out, "mesh max indices", h.mesh_max_indices, kMeshMaxIndices);
    if (h.session_id == 0) out += std::string(out.empty() ? "" : "; ") + "session id 0";
    if (h.producer_pid <= 0) {
        out +=
            std::string(out.empty() ? "" : "; ") + "producer pid " + std::to_string(h.producer_pid);
    }
    const auto state = h.state.load(std::memory_order_acquire);
    if (state < 1 || state > 3) {
        out += std::string(out.empty() ? "" : "; ") + "state " + std::to_string(state);
    }
    if (journal_path_of(h).empty()) out += std::string(out.empty() ? "" : "; ") + "journal path";
    if (out.empty()) return {};
    return Err{IpcError{IpcErrc::kBadHeader, "header", out}};
}

bool valid_session_name(const std::string& name) {
    if (name.empty() || name.size() > 64) return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) return false;
    }
    return name != "." && name != "..";
}

ShmSegment::ShmSegment(SegmentLayout* layout, std::string name, bool owner) noexcept
    : layout_(layout), name_(std::move(name)), owner_(owner) {}

ShmSegment::ShmSegment(ShmSegment&& other) noexcept
    : layout_(std::exchange(other.layout_, nullptr)),
      name_(std::move(other.name_)),
      owner_(std::exchange(other.owner_, false)),
      owner_uid_(other.owner_uid_),
      mode_(other.mode_),
      group_id_(other.group_id_),
      journal_fd_(std::exchange(other.journal_fd_, -1)),
      server_(std::move(other.server_)) {}

ShmSegment& ShmSegment::operator=(ShmSegment&& other) noexcept {
    if (this != &other) {
        this->~ShmSegment();
        new (this) ShmSegment(std::move(other));
    }
    return *this;
}

ShmSegment::~ShmSegment() {
    server_.reset();  // stops serving and removes the socket before the memory goes
    if (journal_fd_ >= 0) close(journal_fd_);
    if (layout_ != nullptr) munmap(layout_, sizeof(SegmentLayout));
}

std::string ShmSegment::socket_path() const { return server_ ? server_->socket_path() : ""; }

void ShmSegment::serve_journal(int read_only_fd) noexcept {
    if (server_) {
        server_->set_journal_fd(read_only_fd);
    } else if (read_only_fd >= 0) {
        close(read_only_fd);
    }
}

SegmentBuilder& SegmentBuilder::name(std::string segment_name) {
    name_ = std::move(segment_name);
    return *this;
}
SegmentBuilder& SegmentBuilder::group_access(bool enabled) {
    group_access_ = enabled;
    return *this;
}
SegmentBuilder& SegmentBuilder::group(std::string group_name) {
    group_name_ = std::move(group_name);
    group_access_ = group_access_ || !group_name_.empty();
    return *this;
}
SegmentBuilder& SegmentBuilder::runtime_dir(std::string directory) {
    runtime_dir_ = std::move(directory);
    return *this;
}
SegmentBuilder& SegmentBuilder::journal_dir(std::string directory) {
    journal_dir_ = std::move(directory);
    return *this;
}

Result<ShmSegment, IpcError> SegmentBuilder::create() const {
    if (!valid_name(name_)) {
        return Err{IpcError{IpcErrc::kBadArgument, "segment name '" + name_ + "'",
                            "use 1-64 of [A-Za-z0-9._-]"}};
    }
    const std::string where = "segment " + name_;
    const std::string runtime = runtime_dir_.empty() ? default_runtime_dir() : runtime_dir_;
    if (!journal_dir_.empty() && (journal_dir_[0] != '/' || journal_dir_.size() > 80)) {
        return Err{IpcError{IpcErrc::kBadArgument, where,
                            "journal dir '" + journal_dir_ + "' must be absolute, <= 80 chars"}};
    }
    PeerPolicy policy;
    policy.owner_uid = geteuid();
    policy.group_allowed = group_access_;
    policy.group = getegid();
    if (!group_name_.empty()) {
        const ::group* g = getgrnam(group_name_.c_str());
        if (g == nullptr) {
            return Err{IpcError{IpcErrc::kBadArgument, where,
                                "group '" + group_name_ + "' does not exist"}};
        }
        policy.group = g->gr_gid;
    }
    const mode_t mode = group_access_ ? 0660 : 0600;
    const int fd = memfd_create(("kerf:" + name_).c_str(), MFD_CLOEXEC | MFD_ALLOW_SEALING);
    if (fd < 0) return Err{os_error(where, "memfd_create", errno)};
    auto fail = [&](const char* what) -> Result<ShmSegment, IpcError> {
        const int e = errno;
        close(fd);
        return Err{os_error(where, what, e)};
    };
    if (fchmod(fd, mode) != 0) return fail("fchmod");
    if (group_access_ && fchown(fd, uid_t(-1), policy.group) != 0) return fail("fchown");
    if (ftruncate(fd, sizeof(SegmentLayout)) != 0) return fail("ftruncate");
    // From here on nobody, this process included, can change the size: no SIGBUS for anyone.
    if (fcntl(fd, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) != 0) {
        return fail("sealing");
    }
    void* p = mmap(nullptr, sizeof(SegmentLayout), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) return fail("mmap");
    auto* layout = static_cast<SegmentLayout*>(p);  // zero-filled
    fill_header(layout->header, "");
    const std::string dir = journal_dir_.empty() ? session_dir_of(runtime, name_) : journal_dir_;
    char journal[kJournalPathBytes + 32];
    if (journal_dir_.empty()) {
        std::snprintf(journal, sizeof journal, "%s/%016" PRIx64 ".kjournal", dir.c_str(),
                      layout->header.session_id);
    } else {
        std::snprintf(journal, sizeof journal, "%s/%s-%016" PRIx64 ".kjournal", dir.c_str(),
                      name_.c_str(), layout->header.session_id);
    }
    if (std::strlen(journal) >= kJournalPathBytes) {
        munmap(p, sizeof(SegmentLayout));
        close(fd);
        return Err{IpcError{IpcErrc::kBadArgument, where,
                            std::string("journal path ") + journal + " is longer than " +
                                std::to_string(kJournalPathBytes - 1) + " bytes"}};
    }
    std::memcpy(layout->header.journal_path, journal, kJournalPathBytes);
    layout->header.state.store(static_cast<std::uint32_t>(SegmentState::kStarting),
                               std::memory_order_release);
    auto server = SessionServer::start(runtime, name_, fd, policy, layout->header.session_id);
    if (!server) {  // the descriptor went with the failed server
        munmap(p, sizeof(SegmentLayout));
        return Err{std::move(server).error()};
    }
    ShmSegment segment(layout, name_, true);
    segment.owner_uid_ = geteuid();
    segment.mode_ = mode;
    segment.group_id_ = group_access_ ? policy.group : getegid();
    segment.server_ = std::move(*server);
    return segment;
}

Result<ShmSegment, IpcError> SegmentBuilder::open() const {
    if (!valid_name(name_)) {
        return Err{IpcError{IpcErrc::kBadArgument, "segment name '" + name_ + "'", "invalid"}};
    }
    const std::string where = "segment " + name_;
    const std::string runtime = runtime_dir_.empty() ? default_runtime_dir() : runtime_dir_;
    auto fds = fetch_session(runtime, name_);
    if (!fds) return Err{std::move(fds).error()};
    const int fd = fds->segment_fd;
    auto fail = [&](IpcError error) -> Result<ShmSegment, IpcError> {
        close(fd);
        if (fds->journal_fd >= 0) close(fds->journal_fd);
        return Err{std::move(error)};
    };
    struct stat st {};
    if (fstat(fd, &st) != 0) return fail(os_error(where, "fstat", errno));
    if (!S_ISREG(st.st_mode) || std::uint64_t(st.st_size) != sizeof(SegmentLayout)) {
        return fail(IpcError{IpcErrc::kBadHeader, where,
                             std::to_string(st.st_size) + " bytes, expected " +
                                 std::to_string(sizeof(SegmentLayout))});
    }
    const int seals = fcntl(fd, F_GET_SEALS);
    if (seals < 0 || (seals & (F_SEAL_SHRINK | F_SEAL_GROW)) != (F_SEAL_SHRINK | F_SEAL_GROW)) {
        return fail(IpcError{IpcErrc::kUntrusted, where,
                             "segment is not sealed against resizing; refused"});
    }
    if (auto trusted = check_trust(where, st, fds->producer_uid); !trusted) {
        return fail(trusted.error());
    }
    void* p = mmap(nullptr, sizeof(SegmentLayout), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) return fail(os_error(where, "mmap", errno));
    close(fd);
    auto* layout = static_cast<SegmentLayout*>(p);
    auto checked = check_header(layout->header, std::uint64_t(st.st_size));
    std::string why;
    if (!checked) {
        why = checked.error().where + ": " + checked.error().what;
    } else if (layout->header.producer_pid != fds->producer_pid) {
        why = "header says producer pid " + std::to_string(layout->header.producer_pid) +
              " but pid " + std::to_string(fds->producer_pid) + " serves the session";
    } else if (layout->header.session_id != fds->session_id) {
        why = "header session id differs from the one its producer announced";
    }
    if (!why.empty()) {
        munmap(p, sizeof(SegmentLayout));
        if (fds->journal_fd >= 0) close(fds->journal_fd);
        return Err{IpcError{IpcErrc::kBadHeader, where, why}};
    }
    ShmSegment segment(layout, name_, false);
    segment.owner_uid_ = st.st_uid;
    segment.mode_ = st.st_mode & 07777;
    segment.group_id_ = st.st_gid;
    segment.journal_fd_ = fds->journal_fd;
    return segment;
}

}  // namespace kerf::ipc
