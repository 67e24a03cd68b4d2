// kerf::ipc::ShmSegment — one mapped session segment, and SegmentBuilder, the only way to get one:
// `create()` (the producer: a sealed memfd that can neither shrink nor grow, served over the
// session socket — see session_socket.hpp; a stale socket of a dead producer is replaced, a live
// one refused) or `open()` (a consumer or tool: receives the descriptors over the socket, checks
// seals, size, owner and mode, then verifies every header field and says which differ).
// Non-copyable, movable; unmaps on destruction; the creator also removes the session socket.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/layout.hpp"
#include "rt_core/ipc/session_socket.hpp"

namespace kerf::ipc {

/// How alive the producer of a mapped segment looks to a reader.
enum class ProducerHealth : std::uint8_t {
    kAlive,    ///< state running, pid exists, heartbeat fresh
    kStale,    ///< pid exists but no heartbeat for longer than the limit (hung, stopped, stalled)
    kDead,     ///< pid gone (or a zombie): killed or crashed
    kStopped,  ///< producer shut down cleanly (state kStopped)
};
std::string_view to_string(ProducerHealth health) noexcept;

/// Default heartbeat age after which a producer is reported kStale.
inline constexpr std::uint64_t kDefaultStaleAfter_ns = 40'000'000;

class ShmSegment {
public:
    ShmSegment(ShmSegment&& other) noexcept;
    ShmSegment& operator=(ShmSegment&& other) noexcept;
    ShmSegment(const ShmSegment&) = delete;
    ShmSegment& operator=(const ShmSegment&) = delete;
    ~ShmSegment();

    SegmentLayout& layout() noexcept { return *layout_; }
    const SegmentLayout& layout() const noexcept { return *layout_; }
    const std::string& name() const noexcept { return name_; }
    /// True for the segment's creator (it removes the session socket when destroyed).
    bool owner() const noexcept { return owner_; }
    /// Owner uid, permission bits (st_mode & 07777) and group of the segment.
    uid_t owner_uid() const noexcept { return owner_uid_; }
    mode_t mode() const noexcept { return mode_; }
    gid_t group_id() const noexcept { return group_id_; }
    /// Consumer side: the journal's read-only descriptor the producer served (-1 if none).
    int journal_fd() const noexcept { return journal_fd_; }
    /// Creator side: the session socket's path ("" for an opened segment).
    std::string socket_path() const;
    /// Creator side: serve `read_only_fd` (ownership taken) as the journal to later consumers.
    void serve_journal(int read_only_fd) noexcept;

private:
    friend class SegmentBuilder;
    ShmSegment(SegmentLayout* layout, std::string name, bool owner) noexcept;
    SegmentLayout* layout_ = nullptr;
    std::string name_;
    bool owner_ = false;
    uid_t owner_uid_ = 0;
    mode_t mode_ = 0;
    gid_t group_id_ = 0;
    int journal_fd_ = -1;
    std::unique_ptr<SessionServer> server_;
};

/// Builds a ShmSegment. Names are 1..64 of [A-Za-z0-9._-] (no slash), e.g. "kerf.demo".
class SegmentBuilder {
public:
    SegmentBuilder& name(std::string segment_name);
    /// Group read/write (0660) instead of owner-only (0600), for kiosks running as two users;
    /// the group is group() if set, else this process's effective group.
    SegmentBuilder& group_access(bool enabled);
    /// The kiosk group by name (implies group_access); a group that does not exist is an error.
    SegmentBuilder& group(std::string group_name);
    /// Folder of session folders (default default_runtime_dir()).
    SegmentBuilder& runtime_dir(std::string directory);
    /// Folder for the session journal (default: the session's own folder).
    SegmentBuilder& journal_dir(std::string directory);

    /// Producer: creates the sealed segment and serves it; header filled, state kStarting.
    /// @pre no live producer serves `name`
    Result<ShmSegment, IpcError> create() const;
    /// Consumer/tool: receives the segment from its producer, maps it read-write and verifies
    /// seals, size, owner (this user, root, or a group of ours with group access), mode (nothing
    /// for others) and header.
    Result<ShmSegment, IpcError> open() const;

private:
    std::string name_;
    std::string runtime_dir_;  // "" = default_runtime_dir()
    std::string journal_dir_;  // "" = the session folder
    std::string group_name_;
    bool group_access_ = false;
};

/// True if `name` is a valid session name (1..64 of [A-Za-z0-9._-], not "." or "..").
bool valid_session_name(const std::string& name);

/// Compares every header field with this build's layout; the message lists each difference.
Status<IpcError> check_header(const SegmentHeader& header, std::uint64_t mapped_bytes);

/// Liveness of the producer as seen now (reads state, pid, heartbeat; untrusted values ok).
ProducerHealth producer_health(const SegmentLayout& layout,
                               std::uint64_t stale_after_ns = kDefaultStaleAfter_ns) noexcept;

/// CLOCK_MONOTONIC in ns (the heartbeat clock).
std::uint64_t monotonic_ns() noexcept;

/// True if `pid` names a running (non-zombie) process.
bool process_alive(std::int32_t pid) noexcept;

/// Path of the session's journal as recorded in the header, or "" when not NUL-terminated/absolute.
std::string journal_path_of(const SegmentHeader& header);

}  // namespace kerf::ipc
