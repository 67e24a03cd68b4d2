#include "rt_core/ipc/journal_writer.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "rt_core/ipc/journal_format.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {

inline constexpr std::uint32_t kBatch = 256;

struct JournalWriter::Queue {
    RingControl control{};
    EventRecord slots[kJournalQueueCapacity];
    SpscProducerEnd<EventRecord, kJournalQueueCapacity> producer;
    SpscConsumerEnd<EventRecord, kJournalQueueCapacity> consumer;
    EventRecord batch[kBatch];
    std::uint64_t dropped = 0;  // real-time thread only
};

namespace {

bool write_all(int fd, const void* data, std::size_t bytes) noexcept {
    const auto* p = static_cast<const char*>(data);
    while (bytes > 0) {
        const ssize_t n = ::write(fd, p, bytes);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        bytes -= std::size_t(n);
    }
    return true;
}

}  // namespace

Result<std::unique_ptr<JournalWriter>, IpcError> JournalWriter::create(
    SegmentLayout& segment, std::uint64_t flush_period_ns, mode_t mode, gid_t group) {
    const std::string path = journal_path_of(segment.header);
    if (path.empty())
        return Err{IpcError{IpcErrc::kJournal, "segment header", "journal path unset"}};
    const int fd =
        ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_APPEND | O_NOFOLLOW, mode);
    if (fd < 0) return Err{os_error("journal " + path, "open", errno)};
    if (fchmod(fd, mode) != 0 || (group != gid_t(-1) && fchown(fd, uid_t(-1), group) != 0)) {
        const int e = errno;
        ::close(fd);
        ::unlink(path.c_str());
        return Err{os_error("journal " + path, "chmod/chown", e)};
    }
    JournalFileHeader h{};
    h.magic = kJournalMagic;
    h.version = kJournalVersion;
    h.record_bytes = sizeof(EventRecord);
    h.session_id = segment.header.session_id;
    h.layout_hash = kLayoutHash;
    h.start_time_unix_ns = segment.header.start_time_unix_ns;
    if (!write_all(fd, &h, sizeof h)) {
        const int e = errno;
        ::close(fd);
        return Err{os_error("journal " + path, "write header", e)};
    }
    return std::unique_ptr<JournalWriter>(new JournalWriter(segment, fd, flush_period_ns));
}

JournalWriter::JournalWriter(SegmentLayout& segment, int fd, std::uint64_t flush_period_ns)
    : segment_(segment),
      fd_(fd),
      flush_period_ns_(flush_period_ns),
      queue_(std::make_unique<Queue>()) {
    queue_->producer = {&queue_->control, queue_->slots};
    queue_->consumer = {&queue_->control, queue_->slots};
    thread_ = std::thread([this] { run(); });
}

JournalWriter::~JournalWriter() { stop(); }

bool JournalWriter::try_enqueue(const EventRecord& record) noexcept {
    if (queue_->producer.try_push(record)) return true;
    segment_.journal_dropped.value.store(++queue_->dropped, std::memory_order_relaxed);
    return false;
}

bool JournalWriter::drain_once() noexcept {
    std::uint32_t n = 0;
    while (n < kBatch && queue_->consumer.try_pop(queue_->batch[n]) == PopResult::kOk) ++n;
    if (n == 0) return false;
    if (!write_all(fd_, queue_->batch, n * sizeof(EventRecord))) {
        write_errors_.fetch_add(1, std::memory_order_relaxed);
        return true;
    }
    segment_.journal_next_sequence.value.store(queue_->batch[n - 1].header.sequence + 1,
                                               std::memory_order_release);
    return true;
}

void JournalWriter::run() noexcept {
    std::uint64_t last_sync = monotonic_ns();
    bool dirty = false;
    while (!stop_.load(std::memory_order_acquire)) {
        const bool wrote = drain_once();
        dirty = dirty || wrote;
        if (!wrote) {
            timespec pause{0, 500'000};
            nanosleep(&pause, nullptr);
        }
        const auto now = monotonic_ns();
        if (dirty && now - last_sync >= flush_period_ns_) {
            if (fdatasync(fd_) != 0) write_errors_.fetch_add(1, std::memory_order_relaxed);
            last_sync = now;
            dirty = false;
        }
    }
    while (drain_once()) {
    }
    fdatasync(fd_);
}

void JournalWriter::stop() {
    if (fd_ < 0) return;
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    ::close(fd_);
    fd_ = -1;
}

int JournalWriter::reopen_read_only() const {
    const std::string path = journal_path_of(segment_.header);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) return -1;
    struct stat mine {
    }, theirs{};
    if (fstat(fd_, &mine) != 0 || fstat(fd, &theirs) != 0 || mine.st_ino != theirs.st_ino ||
        mine.st_dev != theirs.st_dev) {
        ::close(fd);
        errno = EXDEV;
        return -1;
    }
    return fd;
}

std::uint64_t JournalWriter::write_errors() const noexcept {
    return write_errors_.load(std::memory_order_relaxed);
}

}  // namespace kerf::ipc
