// kerf::ipc::Consumer — a process attached to a session segment (display, tuning tool, soak
// monitor, `kerf shm tail`). It holds one slot; events come from its ring and, when it attached
// late, restarted or fell behind (a sequence gap), from the journal first — so it delivers exactly
// the sequence an uninterrupted consumer saw:
//
//   journal [from .. first ring record)  ──then──  ring [first ring record ..)
//
// Everything read from the segment or the journal is untrusted: a bad index, record or header is
// rejected, counted and logged (rate-limited), never trusted, never a crash. Not real-time code.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/layout.hpp"
#include "rt_core/ipc/shm_segment.hpp"

namespace kerf::ipc {

/// Outcome of Consumer::try_next.
enum class Poll : std::uint8_t {
    kEvent,    ///< `out` holds the next event in sequence
    kNothing,  ///< nothing new yet (or the journal has not caught up yet)
};

/// Which slots a consumer may claim. The display and the soak monitor each own a reserved slot,
/// so stray tools (`kerf shm tail`, tuning) can hold every other slot and still never lock them
/// out.
enum class ConsumerRole : std::uint8_t {
    kDisplay,  ///< kerf-display: slot kDisplaySlot only
    kMonitor,  ///< soak monitor: slot kMonitorSlot only
    kTool,     ///< anything else (default): the remaining slots
};
std::string_view to_string(ConsumerRole role) noexcept;
inline constexpr std::uint32_t kDisplaySlot = 0;
inline constexpr std::uint32_t kMonitorSlot = 1;
inline constexpr std::uint32_t kFirstToolSlot = 2;  ///< tools share kFirstToolSlot..kSlotCount-1

/// Counters of one consumer since attach.
struct ConsumerStats {
    std::uint64_t delivered = 0;         ///< events handed to the application
    std::uint64_t from_journal = 0;      ///< ... of which read from the journal
    std::uint64_t ring_gaps = 0;         ///< sequence gaps seen in the ring (drops)
    std::uint64_t lost = 0;              ///< events in neither ring nor journal (skipped)
    std::uint64_t rejected_records = 0;  ///< records failing validation (ring or journal)
    std::uint64_t rejected_indices = 0;  ///< corrupt ring indices (resynced)
    std::uint64_t telemetry = 0;         ///< telemetry samples delivered
    std::uint64_t telemetry_gaps = 0;    ///< telemetry samples missed (dropped by producer)
};

class Consumer {
public:
    Consumer(Consumer&&) noexcept;
    Consumer& operator=(Consumer&&) noexcept;
    ~Consumer();  ///< releases the slot

    /// Next event in sequence order, from the journal or the ring.
    Poll try_next(EventRecord& out);
    /// Next telemetry sample (telemetry has no journal: gaps are counted, not filled).
    Poll try_next_telemetry(TelemetrySample& out);
    /// Latest state through the seqlock; validated (kBusy if it never got a clean copy).
    SeqlockRead try_read_state(LatestState& out);

    /// Producer liveness now (heartbeat age against the builder's limit, pid, state).
    ProducerHealth producer_health() const;

    std::uint64_t next_sequence() const noexcept;  ///< sequence the next event will have
    std::uint32_t slot() const noexcept;
    const ConsumerStats& stats() const noexcept;
    const SegmentLayout& layout() const noexcept;
    /// The mapped segment, writable: for the display's MeshMailboxWriter (the mailbox is the one
    /// part of the segment a consumer writes besides its slot).
    SegmentLayout& writable_layout() noexcept;

private:
    struct Impl;
    explicit Consumer(std::unique_ptr<Impl> impl) noexcept;
    friend class ConsumerBuilder;
    std::unique_ptr<Impl> impl_;
};

class ConsumerBuilder {
public:
    ConsumerBuilder& segment_name(std::string name);
    /// First sequence wanted: 0 (default) replays the whole session from the journal;
    /// kFromNow follows only events published after attach.
    ConsumerBuilder& from_sequence(std::uint64_t sequence);
    ConsumerBuilder& telemetry(bool wanted);                ///< also subscribe to telemetry
    ConsumerBuilder& stale_after_ns(std::uint64_t age_ns);  ///< heartbeat limit (default 40 ms)
    /// Which slots to claim (default kTool); kerf-display passes kDisplay.
    ConsumerBuilder& role(ConsumerRole consumer_role);

    /// Opens + verifies the segment, refuses a dead or stopped producer, claims a free slot
    /// (reclaiming one whose consumer died).
    Result<Consumer, IpcError> attach() const;

    static constexpr std::uint64_t kFromNow = ~std::uint64_t{0};

private:
    std::string name_;
    std::uint64_t from_ = 0;
    std::uint64_t stale_after_ns_ = kDefaultStaleAfter_ns;
    ConsumerRole role_ = ConsumerRole::kTool;
    bool telemetry_ = false;
};

/// Non-real-time: claims a slot of `layout` that `role` may use for process `pid`; returns its
/// index or an error naming the role and the holders.
Result<std::uint32_t, IpcError> claim_slot(SegmentLayout& layout, std::int32_t pid, bool telemetry,
                                           ConsumerRole role = ConsumerRole::kTool);
/// Releases a slot claimed by claim_slot (only if it still holds `claim_word`).
void release_slot(SegmentLayout& layout, std::uint32_t slot, std::uint64_t claim_word) noexcept;

/// Claim word layout: generation (30 bits) | holder pid (32 bits) | SlotState (2 bits).
inline constexpr std::uint64_t claim_word(std::uint64_t generation, std::int32_t pid, SlotState s) {
    return (generation << 34) | (std::uint64_t(std::uint32_t(pid)) << 2) | std::uint64_t(s);
}
inline constexpr std::int32_t claim_pid(std::uint64_t word) {
    return std::int32_t(std::uint32_t(word >> 2));
}
inline constexpr std::uint64_t kSlotHungAfter_ns = 10'000'000'000;

/// Slot liveness for reclaim: true if the holder's pid is gone or it has not polled for 10 s.
bool slot_holder_gone(const SlotControl& control) noexcept;

}  // namespace kerf::ipc
