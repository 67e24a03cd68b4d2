#include "rt_core/ipc/journal_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <utility>

#include "rt_core/ipc/layout.hpp"
#include "rt_core/ipc/record_check.hpp"

namespace kerf::ipc {

Result<JournalReader, IpcError> JournalReader::open(const std::string& path,
                                                    std::uint64_t expected_session_id) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) {
        const int e = errno;
        if (e == ENOENT) return Err{IpcError{IpcErrc::kNotFound, "journal " + path, "missing"}};
        if (e == ELOOP) {
            return Err{
                IpcError{IpcErrc::kJournal, "journal " + path, "is a symbolic link; refused"}};
        }
        return Err{os_error("journal " + path, "open", e)};
    }
    // A journal found by path is trusted only if this user (or root) wrote it: a file another
    // user planted, or one anyone may rewrite, is refused before a byte is read.
    struct stat st {};
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
        std::string why;
        if (st.st_uid != geteuid() && st.st_uid != 0) {
            why = "owned by uid " + std::to_string(st.st_uid) + ", not by this user (uid " +
                  std::to_string(geteuid()) + ") or root; refused";
        } else if ((st.st_mode & S_IWOTH) != 0) {
            char mode[8];
            std::snprintf(mode, sizeof mode, "%03o", unsigned(st.st_mode & 0777));
            why = std::string("writable by every user (mode ") + mode + "); refused";
        }
        if (!why.empty()) {
            ::close(fd);
            return Err{IpcError{IpcErrc::kJournal, "journal " + path, why}};
        }
    }
    return adopt(fd, path, expected_session_id);
}

Result<JournalReader, IpcError> JournalReader::adopt(int fd, const std::string& path,
                                                     std::uint64_t expected_session_id) {
    struct stat st {};
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0) ::close(fd);
        return Err{IpcError{IpcErrc::kJournal, "journal " + path, "not a regular file; refused"}};
    }
    JournalFileHeader h{};
    const ssize_t n = ::pread(fd, &h, sizeof h, 0);
    std::string why;
    if (n != static_cast<ssize_t>(sizeof h)) {
        why = "header: file shorter than 64 bytes";
    } else if (h.magic != kJournalMagic) {
        why = "header: magic is not KERFJRN1";
    } else if (h.version != kJournalVersion) {
        why = "header: version " + std::to_string(h.version) + ", expected " +
              std::to_string(kJournalVersion);
    } else if (h.record_bytes != sizeof(EventRecord)) {
        why = "header: record bytes " + std::to_string(h.record_bytes) + ", expected 128";
    } else if (h.layout_hash != kLayoutHash) {
        why = "header: layout hash differs from this build's";
    } else if (expected_session_id != 0 && h.session_id != expected_session_id) {
        why = "header: session id differs from the segment's";
    }
    if (!why.empty()) {
        ::close(fd);
        return Err{IpcError{IpcErrc::kJournal, "journal " + path, why}};
    }
    return JournalReader(fd, path, h);
}

JournalReader::JournalReader(int fd, std::string path, const JournalFileHeader& header) noexcept
    : fd_(fd), path_(std::move(path)), header_(header) {}

JournalReader::JournalReader(JournalReader&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      header_(other.header_),
      hint_index_(other.hint_index_) {}

JournalReader::~JournalReader() {
    if (fd_ >= 0) ::close(fd_);
}

std::uint64_t JournalReader::record_count() const {
    struct stat st {};
    if (fstat(fd_, &st) != 0 || st.st_size < static_cast<off_t>(sizeof(JournalFileHeader)))
        return 0;
    return (std::uint64_t(st.st_size) - sizeof(JournalFileHeader)) / sizeof(EventRecord);
}

bool JournalReader::read_at(std::uint64_t index, EventRecord& out) const {
    const auto offset = sizeof(JournalFileHeader) + index * sizeof(EventRecord);
    return ::pread(fd_, &out, sizeof out, static_cast<off_t>(offset)) ==
           static_cast<ssize_t>(sizeof out);
}

JournalRead JournalReader::try_read(std::uint64_t sequence, EventRecord& out) {
    const std::uint64_t count = record_count();
    // Fast path: contiguous sequences put record s at index s (or the hint is right).
    for (std::uint64_t guess : {hint_index_, sequence}) {
        if (guess < count && read_at(guess, out) && out.header.sequence == sequence) {
            hint_index_ = guess + 1;
            return validate_event(out) == RecordFault::kNone ? JournalRead::kOk
                                                             : JournalRead::kCorrupt;
        }
    }
    // Slow path (journal drops or a foreign file): binary search on increasing sequences.
    std::uint64_t lo = 0, hi = count;
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (!read_at(mid, out)) return JournalRead::kNotYet;
        if (out.header.sequence < sequence)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo >= count || !read_at(lo, out)) return JournalRead::kNotYet;
    hint_index_ = lo + 1;
    return validate_event(out) == RecordFault::kNone ? JournalRead::kOk : JournalRead::kCorrupt;
}

}  // namespace kerf::ipc
