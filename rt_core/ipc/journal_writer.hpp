// kerf::ipc::JournalWriter — appends every event to the session journal from its own thread.
// The real-time thread only calls try_enqueue() (a push into an in-process SPSC ring, preallocated
// at create); the writer thread drains it with write(2), publishes how far the file goes in the
// segment (journal_next_sequence) and fdatasync()s every flush period.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/layout.hpp"

namespace kerf::ipc {

inline constexpr std::uint32_t kJournalQueueCapacity = 1u << 16;  ///< events (65 s at 1 kHz)

class JournalWriter {
public:
    /// Creates the file named in the segment header (O_EXCL, O_NOFOLLOW) with `mode` (the
    /// segment's, less write for the group) and `group` (gid_t(-1): unchanged), and starts the
    /// writer thread.
    /// @pre `segment` outlives the writer
    static Result<std::unique_ptr<JournalWriter>, IpcError> create(SegmentLayout& segment,
                                                                   std::uint64_t flush_period_ns,
                                                                   mode_t mode = 0600,
                                                                   gid_t group = gid_t(-1));
    ~JournalWriter();  ///< stop()s

    /// Real-time side: hands one event to the writer thread. Never blocks, never allocates;
    /// false (and journal_dropped counted in the segment) if the queue is full.
    bool try_enqueue(const EventRecord& record) noexcept;

    /// Drains everything enqueued so far, fdatasyncs, joins the thread. Idempotent.
    void stop();

    /// A new read-only descriptor of the same file (checked: same inode), or -1 with errno.
    int reopen_read_only() const;

    /// Non-real-time: write errors seen by the thread so far (0 when healthy).
    std::uint64_t write_errors() const noexcept;

private:
    struct Queue;
    JournalWriter(SegmentLayout& segment, int fd, std::uint64_t flush_period_ns);
    void run() noexcept;
    bool drain_once() noexcept;

    SegmentLayout& segment_;
    int fd_;
    std::uint64_t flush_period_ns_;
    std::unique_ptr<Queue> queue_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> write_errors_{0};
    std::thread thread_;
};

}  // namespace kerf::ipc
