#include "config/file_io/file_io.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <utility>

namespace kerf::files {

std::string_view to_string(FileErrc code) noexcept {
    switch (code) {
        case FileErrc::kNotFound:
            return "not_found";
        case FileErrc::kNotRegular:
            return "not_regular";
        case FileErrc::kTooLarge:
            return "too_large";
        case FileErrc::kIsInput:
            return "is_input";
        case FileErrc::kIo:
            return "io";
    }
    return "unknown";
}
namespace {

std::string kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    return "not a regular file";
}

std::string errno_text(int e) { return std::strerror(e); }

bool write_all(int fd, const char* data, std::size_t bytes) {
    while (bytes > 0) {
        const ssize_t n = ::write(fd, data, bytes);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        bytes -= std::size_t(n);
    }
    return true;
}

std::filesystem::path temp_name_for(const std::filesystem::path& target) {
    std::uint64_t r = 0;
    if (getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) r = std::uint64_t(getpid());
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp-%016" PRIx64, r);
    std::filesystem::path dir = target.parent_path();
    if (dir.empty()) dir = ".";
    return dir / ("." + target.filename().string() + suffix);
}

}  // namespace

Result<RegularFile, FileError> RegularFile::open(const std::filesystem::path& path,
                                                 std::uint64_t max_bytes) {
    std::string p = path.string();
    // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below anyway.
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        const int e = errno;
        if (e == ENOENT) return Err{FileError{FileErrc::kNotFound, p, "no such file"}};
        return Err{FileError{FileErrc::kIo, p, "cannot open: " + errno_text(e)}};
    }
    struct stat st {};
    if (fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        return Err{FileError{FileErrc::kIo, p, "cannot stat: " + errno_text(e)}};
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        return Err{FileError{FileErrc::kNotRegular, p,
                             "is " + kind_of(st.st_mode) + ", not a regular file; refused"}};
    }
    if (std::uint64_t(st.st_size) > max_bytes) {
        ::close(fd);
        return Err{FileError{FileErrc::kTooLarge, p,
                             "is " + std::to_string(st.st_size) + " bytes, more than the " +
                                 std::to_string(max_bytes) + "-byte limit for an input"}};
    }
    return RegularFile(fd, std::move(p), std::uint64_t(st.st_size), max_bytes);
}

RegularFile::RegularFile(RegularFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      size_(other.size_),
      max_bytes_(other.max_bytes_) {}

RegularFile& RegularFile::operator=(RegularFile&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        path_ = std::move(other.path_);
        size_ = other.size_;
        max_bytes_ = other.max_bytes_;
    }
    return *this;
}

RegularFile::~RegularFile() {
    if (fd_ >= 0) ::close(fd_);
}

FileError RegularFile::read_error(int e) const {
    return FileError{FileErrc::kIo, path_, "read failed: " + errno_text(e)};
}

Result<std::size_t, FileError> RegularFile::read(std::span<std::byte> buffer) {
    std::size_t got = 0;
    while (got < buffer.size()) {
        const ssize_t n = ::read(fd_, buffer.data() + got, buffer.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return Err{read_error(errno)};
        if (n == 0) break;
        got += std::size_t(n);
    }
    return got;
}

Result<std::vector<std::byte>, FileError> RegularFile::read_whole() {
    if (::lseek(fd_, 0, SEEK_SET) != 0) return Err{read_error(errno)};
    std::vector<std::byte> bytes(static_cast<std::size_t>(size_));
    std::size_t got = 0;
    for (;;) {
        if (got == bytes.size()) {
            // The file may have grown since fstat: one byte tells, before the buffer grows (the
            // common case, a file read whole at its stat size, then neither copies nor zero-fills
            // a second buffer twice its size). Beyond the cap: refused; else read on, within it.
            std::byte probe{};
            ssize_t more = ::read(fd_, &probe, 1);
            while (more < 0 && errno == EINTR) more = ::read(fd_, &probe, 1);
            if (bytes.size() >= max_bytes_) {
                if (more > 0) {
                    return Err{FileError{FileErrc::kTooLarge, path_,
                                         "grew past the " + std::to_string(max_bytes_) +
                                             "-byte limit while being read"}};
                }
                return bytes;
            }
            if (more < 0) return Err{read_error(errno)};
            if (more == 0) break;
            bytes.resize(std::min<std::uint64_t>(max_bytes_, bytes.size() * 2 + 4096));
            bytes[got++] = probe;
            continue;
        }
        const ssize_t n = ::read(fd_, bytes.data() + got, bytes.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return Err{read_error(errno)};
        if (n == 0) break;
        got += std::size_t(n);
    }
    bytes.resize(got);
    return bytes;
}

Result<std::vector<std::byte>, FileError> read_regular_file(const std::filesystem::path& path,
                                                            std::uint64_t max_bytes) {
    auto file = RegularFile::open(path, max_bytes);
    if (!file) return Err{std::move(file).error()};
    return file->read_whole();
}

bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
    struct stat sa {
    }, sb{};
    if (stat(a.c_str(), &sa) != 0 || stat(b.c_str(), &sb) != 0) return false;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

AtomicFileSet::~AtomicFileSet() { remove_temps(); }

void AtomicFileSet::add(std::filesystem::path target, std::string contents) {
    entries_.push_back({std::move(target), std::move(contents), {}});
}

void AtomicFileSet::remove_after_commit(std::filesystem::path stale) {
    stale_.push_back(std::move(stale));
}

Status<FileError> AtomicFileSet::refuse_inputs(
    const std::vector<std::filesystem::path>& inputs) const {
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        const auto& t = entries_[i].target;
        for (const auto& in : inputs) {
            if (same_file(t, in)) {
                return Err{FileError{FileErrc::kIsInput, t.string(),
                                     "is the input " + in.string() +
                                         "; refusing to overwrite it (choose another "
                                         "output name)"}};
            }
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (t == entries_[j].target || same_file(t, entries_[j].target)) {
                return Err{
                    FileError{FileErrc::kIsInput, t.string(), "is named twice in one output set"}};
            }
        }
    }
    return {};
}

void AtomicFileSet::remove_temps() noexcept {
    for (auto& e : entries_) {
        if (!e.temp.empty()) ::unlink(e.temp.c_str());
        e.temp.clear();
    }
}

Status<FileError> AtomicFileSet::commit() {
    for (const auto& e : entries_) {
        struct stat st {};
        if (lstat(e.target.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) {
            return Err{FileError{FileErrc::kNotRegular, e.target.string(),
                                 "exists and is " + kind_of(st.st_mode) + "; nothing written"}};
        }
        if (lstat(e.target.c_str(), &st) == 0 && S_ISLNK(st.st_mode) &&
            (stat(e.target.c_str(), &st) != 0 || !S_ISREG(st.st_mode))) {
            return Err{FileError{FileErrc::kNotRegular, e.target.string(),
                                 "is a link to something that is not a regular file; nothing "
                                 "written"}};
        }
    }
    // Every temp is written and its writeback started before any is waited for, so the disk
    // works on all of them at once instead of one fsync after another (20 pieces: 20 waits in
    // a row). At most kOpenAtOnce descriptors are held: the set is written in batches.
    constexpr std::size_t kOpenAtOnce = 64;
    std::vector<int> open_fds;
    auto fail = [&](const Entry& e, const std::string& what, int err) -> Status<FileError> {
        for (const int fd : open_fds) ::close(fd);
        open_fds.clear();
        remove_temps();
        return Err{FileError{FileErrc::kIo, e.target.string(),
                             what + errno_text(err) + "; nothing written"}};
    };
    for (std::size_t first = 0; first < entries_.size(); first += kOpenAtOnce) {
        const std::size_t end = std::min(entries_.size(), first + kOpenAtOnce);
        for (std::size_t i = first; i < end; ++i) {
            Entry& e = entries_[i];
            e.temp = temp_name_for(e.target);
            const int fd =
                ::open(e.temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
            if (fd < 0) {
                const int err = errno;
                e.temp.clear();
                return fail(e, "cannot create a temporary file next to it: ", err);
            }
            open_fds.push_back(fd);
            if (!write_all(fd, e.contents.data(), e.contents.size())) {
                const int err = errno;
                return fail(e, "write failed: ", err);
            }
            // Only a hint (not every file system has it): fsync below is what makes it durable.
            (void)::sync_file_range(fd, 0, 0, SYNC_FILE_RANGE_WRITE);
        }
        for (std::size_t i = first; i < end; ++i) {
            const int fd = open_fds[i - first];
            if (fsync(fd) != 0) {
                const int err = errno;
                return fail(entries_[i], "write failed: ", err);
            }
        }
        for (const int fd : open_fds) ::close(fd);
        open_fds.clear();
    }
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        Entry& e = entries_[i];
        if (std::rename(e.temp.c_str(), e.target.c_str()) != 0) {
            const int err = errno;
            remove_temps();
            return Err{FileError{FileErrc::kIo, e.target.string(),
                                 "rename failed: " + errno_text(err) + " (" + std::to_string(i) +
                                     " of " + std::to_string(entries_.size()) +
                                     " files were already in place)"}};
        }
        e.temp.clear();
    }
    for (const auto& s : stale_) {
        bool keep = false;
        for (const auto& e : entries_) keep = keep || e.target == s;
        if (!keep) ::unlink(s.c_str());
    }
    return {};
}

Status<FileError> write_file_atomically(const std::filesystem::path& target,
                                        const std::string& contents) {
    AtomicFileSet set;
    set.add(target, contents);
    return set.commit();
}

}  // namespace kerf::files
