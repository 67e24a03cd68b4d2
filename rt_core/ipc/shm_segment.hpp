// kerf::ipc::ShmSegment — one mapped session segment, and SegmentBuilder, the only way to get one:
// `create()` (the producer: replaces a stale segment of a dead producer, refuses a live one) or
// `open()` (a consumer or tool: verifies every header field, says which differ). Non-copyable,
// movable; unmaps on destruction; the creator also unlinks the name.
#pragma once

#include <cstdint>
#include <string>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/layout.hpp"

namespace kerf::ipc {

/// How alive the producer of a mapped segment looks to a reader.
enum class ProducerHealth : std::uint8_t {
    kAlive,    ///< state running, pid exists, heartbeat fresh
    kStale,    ///< pid exists but no heartbeat for longer than the limit (hung, stopped, stalled)
    kDead,     ///< pid gone (or a zombie): killed or crashed
    kStopped,  ///< producer shut down cleanly (state kStopped)
};
const char* to_string(ProducerHealth health) noexcept;

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
    /// True for the segment's creator (it unlinks the name when destroyed).
    bool owner() const noexcept { return owner_; }

private:
    friend class SegmentBuilder;
    ShmSegment(SegmentLayout* layout, std::string name, bool owner) noexcept;
    SegmentLayout* layout_ = nullptr;
    std::string name_;
    bool owner_ = false;
};

/// Builds a ShmSegment. Names are 1..64 of [A-Za-z0-9._-] (no slash), e.g. "kerf.demo".
class SegmentBuilder {
public:
    SegmentBuilder& name(std::string segment_name);
    /// Group read/write (0660) instead of owner-only (0600), for kiosks running as two users.
    SegmentBuilder& group_access(bool enabled);
    /// Directory for the session journal (default /dev/shm, next to the segment).
    SegmentBuilder& journal_dir(std::string directory);
    /// Heartbeat age above which an existing segment's producer counts as gone at create().
    SegmentBuilder& stale_after_ns(std::uint64_t age_ns);

    /// Producer: creates the segment, replacing a stale one; header filled, state kRunning.
    /// @pre no live producer owns `name`
    Result<ShmSegment, IpcError> create() const;
    /// Consumer/tool: maps an existing segment read-write and verifies its header.
    Result<ShmSegment, IpcError> open() const;

private:
    std::string name_;
    std::string journal_dir_ = "/dev/shm";
    std::uint64_t stale_after_ns_ = 1'000'000'000;
    bool group_access_ = false;
};

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
