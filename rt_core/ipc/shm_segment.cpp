#include "rt_core/ipc/shm_segment.hpp"

#include <fcntl.h>
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

std::string shm_path(const std::string& name) { return "/" + name; }

bool valid_name(const std::string& name) {
    if (name.empty() || name.size() > 64) return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) return false;
    }
    return name != "." && name != "..";
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

// True when an existing segment may be replaced: garbage, stopped, producer dead or long silent.
bool existing_is_stale(int fd, std::uint64_t stale_after_ns, std::string& why_in_use) {
    struct stat st {};
    if (fstat(fd, &st) != 0 || st.st_size < static_cast<off_t>(sizeof(SegmentLayout))) return true;
    void* p = mmap(nullptr, sizeof(SegmentLayout), PROT_READ, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) return true;
    const auto* layout = static_cast<const SegmentLayout*>(p);
    bool stale = true;
    if (check_header(layout->header, std::uint64_t(st.st_size))) {
        const ProducerHealth h = producer_health(*layout, stale_after_ns);
        stale = h == ProducerHealth::kDead || h == ProducerHealth::kStopped ||
                h == ProducerHealth::kStale;
        why_in_use = "owned by live producer pid " + std::to_string(layout->header.producer_pid);
    }
    munmap(p, sizeof(SegmentLayout));
    return stale;
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

const char* to_string(ProducerHealth health) noexcept {
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

const char* to_string(SegmentState state) noexcept {
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
    return Err{make_error(IpcErrc::kBadHeader, "header: " + out)};
}

ShmSegment::ShmSegment(SegmentLayout* layout, std::string name, bool owner) noexcept
    : layout_(layout), name_(std::move(name)), owner_(owner) {}

ShmSegment::ShmSegment(ShmSegment&& other) noexcept
    : layout_(std::exchange(other.layout_, nullptr)),
      name_(std::move(other.name_)),
      owner_(std::exchange(other.owner_, false)) {}

ShmSegment& ShmSegment::operator=(ShmSegment&& other) noexcept {
    if (this != &other) {
        this->~ShmSegment();
        new (this) ShmSegment(std::move(other));
    }
    return *this;
}

ShmSegment::~ShmSegment() {
    if (layout_ == nullptr) return;
    if (owner_) shm_unlink(shm_path(name_).c_str());
    munmap(layout_, sizeof(SegmentLayout));
}

SegmentBuilder& SegmentBuilder::name(std::string segment_name) {
    name_ = std::move(segment_name);
    return *this;
}
SegmentBuilder& SegmentBuilder::group_access(bool enabled) {
    group_access_ = enabled;
    return *this;
}
SegmentBuilder& SegmentBuilder::journal_dir(std::string directory) {
    journal_dir_ = std::move(directory);
    return *this;
}
SegmentBuilder& SegmentBuilder::stale_after_ns(std::uint64_t age_ns) {
    stale_after_ns_ = age_ns;
    return *this;
}

Result<ShmSegment, IpcError> SegmentBuilder::create() const {
    if (!valid_name(name_)) {
        return Err{make_error(IpcErrc::kBadArgument,
                              "segment name '" + name_ + "': use 1-64 of [A-Za-z0-9._-]")};
    }
    const std::string where = "segment " + name_;
    if (journal_dir_.empty() || journal_dir_[0] != '/' || journal_dir_.size() > 80) {
        return Err{make_error(IpcErrc::kBadArgument, where + ": journal dir '" + journal_dir_ +
                                                         "' must be absolute, <= 80 chars")};
    }
    const int existing = shm_open(shm_path(name_).c_str(), O_RDONLY | O_CLOEXEC, 0);
    if (existing >= 0) {
        std::string why;
        const bool stale = existing_is_stale(existing, stale_after_ns_, why);
        close(existing);
        if (!stale) return Err{make_error(IpcErrc::kInUse, where + ": " + why)};
        shm_unlink(shm_path(name_).c_str());  // a dead producer's leftover: replace it
    }
    const mode_t mode = group_access_ ? 0660 : 0600;
    const int fd = shm_open(shm_path(name_).c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, mode);
    if (fd < 0) return Err{os_error(where + ": shm_open", errno)};
    fchmod(fd, mode);  // umask may have removed the group bits
    if (ftruncate(fd, sizeof(SegmentLayout)) != 0) {
        const int e = errno;
        close(fd);
        shm_unlink(shm_path(name_).c_str());
        return Err{os_error(where + ": ftruncate", e)};
    }
    void* p = mmap(nullptr, sizeof(SegmentLayout), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    const int e = errno;
    close(fd);
    if (p == MAP_FAILED) {
        shm_unlink(shm_path(name_).c_str());
        return Err{os_error(where + ": mmap", e)};
    }
    auto* layout = static_cast<SegmentLayout*>(p);  // zero-filled by ftruncate
    fill_header(layout->header, "");
    char journal[kJournalPathBytes];
    std::snprintf(journal, sizeof journal, "%s/%s-%016" PRIx64 ".kjournal", journal_dir_.c_str(),
                  name_.c_str(), layout->header.session_id);
    std::memcpy(layout->header.journal_path, journal, sizeof journal);
    layout->header.state.store(static_cast<std::uint32_t>(SegmentState::kStarting),
                               std::memory_order_release);
    return ShmSegment(layout, name_, true);
}

Result<ShmSegment, IpcError> SegmentBuilder::open() const {
    if (!valid_name(name_)) {
        return Err{make_error(IpcErrc::kBadArgument, "segment name '" + name_ + "' is invalid")};
    }
    const std::string where = "segment " + name_;
    const int fd = shm_open(shm_path(name_).c_str(), O_RDWR | O_CLOEXEC, 0);
    if (fd < 0) {
        const int e = errno;
        if (e == ENOENT) return Err{make_error(IpcErrc::kNotFound, where + ": no such segment")};
        return Err{os_error(where + ": shm_open", e)};
    }
    struct stat st {};
    if (fstat(fd, &st) != 0 || st.st_size < static_cast<off_t>(sizeof(SegmentHeader))) {
        close(fd);
        return Err{make_error(IpcErrc::kBadHeader, where + ": " + std::to_string(st.st_size) +
                                                       " bytes, expected " +
                                                       std::to_string(sizeof(SegmentLayout)))};
    }
    const std::size_t map_bytes = std::uint64_t(st.st_size) >= sizeof(SegmentLayout)
                                      ? sizeof(SegmentLayout)
                                      : sizeof(SegmentHeader);
    void* p = mmap(nullptr, map_bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    const int e = errno;
    close(fd);
    if (p == MAP_FAILED) return Err{os_error(where + ": mmap", e)};
    auto* layout = static_cast<SegmentLayout*>(p);
    auto checked = check_header(layout->header, std::uint64_t(st.st_size));
    if (!checked) {
        munmap(p, map_bytes);
        return Err{make_error(IpcErrc::kBadHeader, where + ": " + checked.error().message)};
    }
    return ShmSegment(layout, name_, false);
}

}  // namespace kerf::ipc
