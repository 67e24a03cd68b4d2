// The binary layout of a Kerf session segment (POSIX shared memory, /dev/shm/<name>). One struct,
// mapped at offset 0; every offset is pinned here and in tests/ipc/layout_test.cpp. Change any
// field, size or capacity => bump kLayoutVersion (the layout hash changes by itself).
//
//   offset 0        SegmentHeader     identity: magic, version, hash, session, pid, start, state
//   +256            ProducerStatus    heartbeat, next event sequence (producer, every tick)
//   +320/+384       journal counters  written by the producer's journal thread
//   +448            SeqlockCell       latest tool pose / force / contact / loop health
//   then            ConsumerSlot[4]   claim word + event ring + telemetry ring per consumer
//   then            MeshMailbox       display -> rt collision mesh, double-buffered
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "rt_core/ipc/mesh_layout.hpp"
#include "rt_core/ipc/records.hpp"
#include "rt_core/ipc/seqlock.hpp"
#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {

inline constexpr std::uint64_t kMagic = 0x314D48534652454Bull;  ///< "KERFSHM1" little-endian
inline constexpr std::uint32_t kLayoutVersion = 3;              ///< 3: 2^21-triangle mailbox
inline constexpr std::uint32_t kSlotCount = 4;                  ///< display, tuning, soak, spare
inline constexpr std::uint32_t kEventCapacity = 4096;           ///< events per slot ring
inline constexpr std::uint32_t kTelemetryCapacity = 2048;       ///< samples per slot ring (2 s)
inline constexpr std::size_t kJournalPathBytes = 128;

/// Segment life, in the header's state word.
enum class SegmentState : std::uint32_t { kStarting = 1, kRunning = 2, kStopped = 3 };
std::string_view to_string(SegmentState state) noexcept;

/// Written once by the producer before state becomes kRunning. 256 bytes.
struct SegmentHeader {
    std::uint64_t magic;                   ///< kMagic
    std::uint32_t layout_version;          ///< kLayoutVersion
    std::uint32_t header_bytes;            ///< sizeof(SegmentHeader)
    std::uint64_t layout_hash;             ///< kLayoutHash of the producer's build
    std::uint64_t segment_bytes;           ///< sizeof(SegmentLayout)
    std::uint64_t session_id;              ///< random per session (getrandom), never 0
    std::uint64_t start_time_unix_ns;      ///< CLOCK_REALTIME at creation, ns
    std::int32_t producer_pid;             ///< kerf-rt's pid
    std::uint32_t slot_count;              ///< kSlotCount
    std::uint32_t event_capacity;          ///< kEventCapacity
    std::uint32_t telemetry_capacity;      ///< kTelemetryCapacity
    std::atomic<std::uint32_t> state;      ///< SegmentState (release on change)
    std::uint32_t mesh_max_bodies;         ///< kMeshMaxBodies
    std::uint32_t mesh_max_vertices;       ///< kMeshMaxVertices
    std::uint32_t mesh_max_indices;        ///< kMeshMaxIndices
    char journal_path[kJournalPathBytes];  ///< absolute path of the event journal, NUL-terminated
    std::uint8_t reserved[48];             ///< 0
};

/// Producer liveness and progress; one line written by the real-time thread.
struct alignas(kCacheLine) ProducerStatus {
    std::atomic<std::uint64_t> heartbeat_tick;       ///< loop tick of the last heartbeat
    std::atomic<std::uint64_t> heartbeat_ns;         ///< CLOCK_MONOTONIC of the last heartbeat, ns
    std::atomic<std::uint64_t> next_event_sequence;  ///< events published so far (= next seq)
    std::atomic<std::uint64_t> telemetry_dropped;    ///< samples dropped over all slots
    std::atomic<std::uint64_t> events_dropped;  ///< ring drops over all slots (journal has them)
    std::atomic<std::uint64_t> reserved[3];
};

/// Slot claim word: (generation << 2) | SlotState. Generation increments on every claim.
enum class SlotState : std::uint32_t { kFree = 0, kClaiming = 1, kActive = 2 };
inline constexpr std::uint32_t kSlotWantsTelemetry = 1u;

/// Per-consumer control line, written by the consumer holding the slot.
struct alignas(kCacheLine) SlotControl {
    std::atomic<std::uint64_t> claim_word;      ///< (generation << 2) | SlotState
    std::atomic<std::uint64_t> heartbeat_ns;    ///< consumer's CLOCK_MONOTONIC at its last poll
    std::atomic<std::int32_t> consumer_pid;     ///< holder's pid, 0 when free
    std::atomic<std::uint32_t> flags;           ///< kSlotWantsTelemetry
    std::atomic<std::uint64_t> rejected_count;  ///< records/indices the consumer rejected
    std::atomic<std::uint64_t> delivered;       ///< events delivered to the application
    std::atomic<std::uint64_t> reserved[3];
};

struct ConsumerSlot {
    SlotControl control;
    RingControl event_ring;
    RingControl telemetry_ring;
    EventRecord events[kEventCapacity];
    TelemetrySample telemetry[kTelemetryCapacity];
};

/// The whole segment.
struct SegmentLayout {
    SegmentHeader header;
    ProducerStatus producer;
    PaddedCounter journal_next_sequence;  ///< every event with sequence < this is in the journal
    PaddedCounter journal_dropped;        ///< events the journal thread could not take (loss!)
    SeqlockCell<LatestState> state;
    ConsumerSlot slots[kSlotCount];
    MeshMailbox mailbox;
};

static_assert(sizeof(SegmentHeader) == 256 && offsetof(SegmentHeader, journal_path) == 80);
static_assert(sizeof(ProducerStatus) == 64 && sizeof(SlotControl) == 64);
static_assert(offsetof(SegmentLayout, producer) == 256);
static_assert(offsetof(SegmentLayout, journal_next_sequence) == 320);
static_assert(offsetof(SegmentLayout, state) == 448 && sizeof(SeqlockCell<LatestState>) == 192);
static_assert(offsetof(SegmentLayout, slots) == 640);
static_assert(sizeof(ConsumerSlot) == 64 + 512 + 128 * (kEventCapacity + kTelemetryCapacity));
static_assert(offsetof(SegmentLayout, mailbox) == 640 + kSlotCount * sizeof(ConsumerSlot));
static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

namespace detail {
constexpr std::uint64_t fnv(std::uint64_t h, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) h = (h ^ ((v >> (8 * i)) & 0xFF)) * 0x100000001B3ull;
    return h;
}
}  // namespace detail

/// Hash of every size, offset and capacity a reader depends on.
inline constexpr std::uint64_t kLayoutHash = [] {
    std::uint64_t h = 0xCBF29CE484222325ull;
    for (std::uint64_t v : {std::uint64_t{kLayoutVersion},
                            sizeof(SegmentLayout),
                            sizeof(SegmentHeader),
                            offsetof(SegmentLayout, slots),
                            offsetof(SegmentLayout, mailbox),
                            sizeof(ConsumerSlot),
                            sizeof(EventRecord),
                            sizeof(TelemetrySample),
                            sizeof(LatestState),
                            sizeof(MeshBuffer),
                            offsetof(EventRecord, cut),
                            offsetof(MeshBuffer, vertices_m),
                            offsetof(MeshBuffer, indices),
                            offsetof(MeshBuffer, materials),
                            offsetof(MeshBufferHeader, content_hash),
                            offsetof(TelemetrySample, safety_reasons),
                            std::uint64_t{kSlotCount},
                            std::uint64_t{kEventCapacity},
                            std::uint64_t{kTelemetryCapacity},
                            std::uint64_t{kMeshMaxVertices}}) {
        h = detail::fnv(h, v);
    }
    return h;
}();

}  // namespace kerf::ipc
