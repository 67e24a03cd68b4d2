// kerf::files — reading inputs and writing outputs so that no bad path loses data, hangs or eats
// memory. Reads: regular files only (a FIFO, device, directory or a link to one is refused before
// a byte is read; opening never blocks), at most a stated number of bytes. Writes: each output is
// written to a temporary file in its own folder, synced, and renamed over the target only after
// every output of the set was written, so a multi-file result appears whole or not at all; an
// output that is one of the inputs (same file, whatever the path) is refused before anything is
// written.
//
//   auto bytes = files::read_regular_file(path, files::kDefaultMaxInputBytes);
//   files::AtomicFileSet out;
//   out.add("piece_1.stl", data1);  out.add("piece_2.stl", data2);
//   out.refuse_inputs({input});     // same inode: error, nothing written
//   out.commit();                   // all renamed, or none (temps removed)
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"

namespace kerf::files {

/// Why a read or write was refused or failed.
enum class FileErrc : std::uint8_t {
    kNotFound,    ///< no such file
    kNotRegular,  ///< a directory, FIFO, socket, device, or a link to one: refused
    kTooLarge,    ///< more bytes than the caller's cap
    kIsInput,     ///< an output that is one of the inputs, or named twice in one set
    kIo,          ///< open, stat, read, write, fsync or rename failed (errno text in what)
};
/// Stable snake_case name ("not_regular").
std::string_view to_string(FileErrc code) noexcept;

/// A file failure (kerf::Error): where is the path, what a sentence a user can act on.
using FileError = Error<FileErrc>;

/// Default cap on one input file: 2 GiB (a 20-million-triangle binary STL is 1 GB).
inline constexpr std::uint64_t kDefaultMaxInputBytes = 2ull << 30;

/// Reads the whole regular file at `path` (links followed to a regular file only). Refuses a
/// directory, FIFO, socket or device and a file larger than `max_bytes`, naming which.
Result<std::vector<std::byte>, FileError> read_regular_file(const std::filesystem::path& path,
                                                            std::uint64_t max_bytes);

/// A regular file open for reading in pieces (a large input parsed as it is read, without a
/// buffer of its size): open() makes read_regular_file's checks and gives its errors.
class RegularFile {
public:
    /// Opens `path` for reading if it is a regular file of at most `max_bytes`.
    static Result<RegularFile, FileError> open(const std::filesystem::path& path,
                                               std::uint64_t max_bytes);
    RegularFile(RegularFile&& other) noexcept;
    RegularFile& operator=(RegularFile&& other) noexcept;
    RegularFile(const RegularFile&) = delete;
    RegularFile& operator=(const RegularFile&) = delete;
    ~RegularFile();  ///< closes it

    /// Its size when opened, bytes (it may change while it is read).
    std::uint64_t size() const noexcept { return size_; }
    /// Reads on from where the last read stopped until `buffer` is full or the file ends: the
    /// bytes read (fewer than asked only at the end of the file).
    Result<std::size_t, FileError> read(std::span<std::byte> buffer);
    /// The whole file from its start, wherever reading stopped: what read_regular_file() gives.
    Result<std::vector<std::byte>, FileError> read_whole();

private:
    RegularFile(int fd, std::string path, std::uint64_t size, std::uint64_t max_bytes)
        : fd_(fd), path_(std::move(path)), size_(size), max_bytes_(max_bytes) {}
    FileError read_error(int e) const;

    int fd_ = -1;
    std::string path_;
    std::uint64_t size_ = 0;
    std::uint64_t max_bytes_ = 0;
};

/// True if `a` and `b` name the same existing file (device and inode), whatever their paths.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

/// A set of output files written all-or-nothing. Not thread-safe; one commit per set.
class AtomicFileSet {
public:
    AtomicFileSet() = default;
    AtomicFileSet(const AtomicFileSet&) = delete;
    AtomicFileSet& operator=(const AtomicFileSet&) = delete;
    ~AtomicFileSet();  ///< removes temporary files of a set that was not committed

    /// Adds one output and its full contents.
    void add(std::filesystem::path target, std::string contents);

    /// Files to remove once the set is in place (e.g. pieces of an earlier run beyond this one's
    /// count), so an old set never mixes with the new one. Missing files are fine.
    void remove_after_commit(std::filesystem::path stale);

    /// Error if any target is the same file as one of `inputs`, or two targets are the same.
    Status<FileError> refuse_inputs(const std::vector<std::filesystem::path>& inputs) const;

    /// Writes every temp file (mode 0644 less umask, O_EXCL, fsync; up to 64 written, their
    /// writeback started, before the first is waited for), then renames each over its target; on
    /// any failure before the renames, removes every temp and leaves targets as they were. A target
    /// that exists and is not a regular file (directory, FIFO, device) is refused.
    Status<FileError> commit();

private:
    struct Entry {
        std::filesystem::path target;
        std::string contents;
        std::filesystem::path temp;
    };
    void remove_temps() noexcept;
    std::vector<Entry> entries_;
    std::vector<std::filesystem::path> stale_;
};

/// Writes one file atomically (an AtomicFileSet of one).
Status<FileError> write_file_atomically(const std::filesystem::path& target,
                                        const std::string& contents);

}  // namespace kerf::files
