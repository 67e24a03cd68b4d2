#include "rt_core/ipc/producer.hpp"

#include <cerrno>
#include <utility>

#include "rt_core/ipc/journal_writer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {

namespace {
constexpr std::uint64_t kStateMask = 3;
constexpr std::uint64_t kActive = static_cast<std::uint64_t>(SlotState::kActive);
}  // namespace

struct Producer::Impl {
    explicit Impl(ShmSegment s) : segment(std::move(s)) {}
    ShmSegment segment;
    std::unique_ptr<JournalWriter> journal;
    SpscProducerEnd<EventRecord, kEventCapacity> event_rings[kSlotCount];
    SpscProducerEnd<TelemetrySample, kTelemetryCapacity> telemetry_rings[kSlotCount];
    std::uint64_t claim_seen[kSlotCount] = {};  // claim word the rings were last reset for
    std::uint64_t next_sequence = 0;
    std::uint64_t next_telemetry = 0;
    std::uint64_t events_dropped = 0;
    std::uint64_t telemetry_dropped = 0;
    bool stopped = false;

    /// True if slot `i` has an active consumer; resets the rings when a new consumer claimed it.
    bool active(std::uint32_t i) noexcept {
        SlotControl& c = segment.layout().slots[i].control;
        const auto word = c.claim_word.load(std::memory_order_acquire);
        if ((word & kStateMask) != kActive) return false;
        if (word != claim_seen[i]) {
            claim_seen[i] = word;
            event_rings[i].reset_for_new_consumer();
            telemetry_rings[i].reset_for_new_consumer();
        }
        return true;
    }
};

Producer::Producer(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Producer::Producer(Producer&&) noexcept = default;
Producer& Producer::operator=(Producer&&) noexcept = default;
Producer::~Producer() {
    if (impl_) stop();
}

PublishOutcome Producer::publish_event(EventRecord& record) noexcept {
    Impl& m = *impl_;
    PublishOutcome out;
    out.sequence = m.next_sequence++;
    record.header.sequence = out.sequence;
    if (record.header.time_ns == 0) record.header.time_ns = monotonic_ns();
    stamp_checksum(record);
    out.journalled = m.journal->try_enqueue(record);
    for (std::uint32_t i = 0; i < kSlotCount; ++i) {
        if (!m.active(i)) continue;
        if (m.event_rings[i].try_push(record)) {
            ++out.delivered;
        } else {
            ++out.dropped;
        }
    }
    ProducerStatus& p = m.segment.layout().producer;
    if (out.dropped != 0) {
        m.events_dropped += out.dropped;
        p.events_dropped.store(m.events_dropped, std::memory_order_relaxed);
    }
    p.next_event_sequence.store(m.next_sequence, std::memory_order_release);
    return out;
}

void Producer::publish_telemetry(TelemetrySample& sample) noexcept {
    Impl& m = *impl_;
    sample.header.sequence = m.next_telemetry++;
    sample.header.type = EventType::kTelemetry;
    if (sample.header.time_ns == 0) sample.header.time_ns = monotonic_ns();
    stamp_checksum(sample);
    SegmentLayout& s = m.segment.layout();
    for (std::uint32_t i = 0; i < kSlotCount; ++i) {
        if (!m.active(i)) continue;
        const auto flags = s.slots[i].control.flags.load(std::memory_order_acquire);
        if ((flags & kSlotWantsTelemetry) == 0) continue;
        if (!m.telemetry_rings[i].try_push(sample)) {
            s.producer.telemetry_dropped.store(++m.telemetry_dropped, std::memory_order_relaxed);
        }
    }
}

void Producer::publish_state(const LatestState& state) noexcept {
    seqlock_write(impl_->segment.layout().state, state);
}

void Producer::heartbeat(std::uint64_t tick, std::uint64_t now_ns) noexcept {
    ProducerStatus& p = impl_->segment.layout().producer;
    p.heartbeat_tick.store(tick, std::memory_order_relaxed);
    p.heartbeat_ns.store(now_ns, std::memory_order_release);
}

void Producer::stop() {
    Impl& m = *impl_;
    if (m.stopped) return;
    m.stopped = true;
    m.journal->stop();
    m.segment.layout().header.state.store(static_cast<std::uint32_t>(SegmentState::kStopped),
                                          std::memory_order_release);
}

const SegmentLayout& Producer::layout() const noexcept { return impl_->segment.layout(); }
const std::string& Producer::segment_name() const noexcept { return impl_->segment.name(); }
std::string Producer::journal_path() const { return journal_path_of(layout().header); }
std::string Producer::socket_path() const { return impl_->segment.socket_path(); }

ProducerBuilder& ProducerBuilder::segment_name(std::string name) {
    name_ = std::move(name);
    return *this;
}
ProducerBuilder& ProducerBuilder::journal_dir(std::string directory) {
    journal_dir_ = std::move(directory);
    return *this;
}
ProducerBuilder& ProducerBuilder::group_access(bool enabled) {
    group_access_ = enabled;
    return *this;
}
ProducerBuilder& ProducerBuilder::group(std::string group_name) {
    group_name_ = std::move(group_name);
    return *this;
}
ProducerBuilder& ProducerBuilder::runtime_dir(std::string directory) {
    runtime_dir_ = std::move(directory);
    return *this;
}
ProducerBuilder& ProducerBuilder::journal_flush_period_ns(std::uint64_t period_ns) {
    flush_period_ns_ = period_ns;
    return *this;
}

Result<Producer, IpcError> ProducerBuilder::create() const {
    auto segment = SegmentBuilder()
                       .name(name_)
                       .runtime_dir(runtime_dir_)
                       .journal_dir(journal_dir_)
                       .group_access(group_access_)
                       .group(group_name_)
                       .create();
    if (!segment) return Err{std::move(segment).error()};
    // The journal follows the segment: owner-only, or readable by the kiosk group.
    const bool shared = (segment->mode() & 0060) != 0;
    auto impl = std::make_unique<Producer::Impl>(std::move(*segment));
    SegmentLayout& s = impl->segment.layout();
    for (std::uint32_t i = 0; i < kSlotCount; ++i) {
        impl->event_rings[i] = {&s.slots[i].event_ring, s.slots[i].events};
        impl->telemetry_rings[i] = {&s.slots[i].telemetry_ring, s.slots[i].telemetry};
    }
    auto journal = JournalWriter::create(s, flush_period_ns_, shared ? 0640 : 0600,
                                         shared ? impl->segment.group_id() : gid_t(-1));
    if (!journal) return Err{std::move(journal).error()};
    impl->journal = std::move(*journal);
    const int reader = impl->journal->reopen_read_only();
    if (reader < 0) {
        return Err{os_error("journal " + journal_path_of(s.header), "reopen to serve", errno)};
    }
    impl->segment.serve_journal(reader);
    s.producer.heartbeat_ns.store(monotonic_ns(), std::memory_order_release);
    s.header.state.store(static_cast<std::uint32_t>(SegmentState::kRunning),
                         std::memory_order_release);
    return Producer(std::move(impl));
}

}  // namespace kerf::ipc
