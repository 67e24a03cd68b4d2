// kerf::ipc::JournalReader — reads a session journal (untrusted: a file anyone could have edited)
// by sequence number, for consumers catching up and for replay. Not for the real-time thread.
#pragma once

#include <cstdint>
#include <string>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/journal_format.hpp"

namespace kerf::ipc {

/// Outcome of JournalReader::try_read.
enum class JournalRead : std::uint8_t {
    kOk,       ///< `out` holds the first record with sequence >= the one asked (> means lost)
    kNotYet,   ///< the file does not reach that far yet
    kCorrupt,  ///< the record there fails validation (counted; the caller skips it)
};

class JournalReader {
public:
    /// Opens `path` (regular, owned by this user or root, not world-writable; never follows a
    /// final link or blocks on a FIFO), checks its header; `expected_session_id` 0: any session.
    static Result<JournalReader, IpcError> open(const std::string& path,
                                                std::uint64_t expected_session_id);
    /// Takes `fd` (e.g. served by the producer; closed on failure too), requires a regular file
    /// and checks its header; `label` names it in messages.
    static Result<JournalReader, IpcError> adopt(int fd, const std::string& label,
                                                 std::uint64_t expected_session_id);
    JournalReader(JournalReader&& other) noexcept;
    JournalReader& operator=(JournalReader&&) = delete;
    JournalReader(const JournalReader&) = delete;
    ~JournalReader();

    /// Finds the first complete record with sequence >= `sequence`. `out` is validated.
    JournalRead try_read(std::uint64_t sequence, EventRecord& out);

    /// Complete records currently in the file.
    std::uint64_t record_count() const;

    const JournalFileHeader& header() const noexcept { return header_; }
    const std::string& path() const noexcept { return path_; }

private:
    JournalReader(int fd, std::string path, const JournalFileHeader& header) noexcept;
    bool read_at(std::uint64_t index, EventRecord& out) const;

    int fd_ = -1;
    std::string path_;
    JournalFileHeader header_{};
    std::uint64_t hint_index_ = 0;  ///< where the next sequential read probably is
};

}  // namespace kerf::ipc
