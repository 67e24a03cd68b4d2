#include "rt_core/ipc/consumer.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <optional>
#include <utility>

#include "rt_core/ipc/journal_reader.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {
namespace {

constexpr std::uint64_t kStateMask = 3;
constexpr int kMaxPopsPerPoll = 64;

bool log_now(std::uint64_t count) { return (count & (count - 1)) == 0; }  // 1, 2, 4, 8, ...

}  // namespace

bool slot_holder_gone(const SlotControl& control) noexcept {
    const auto word = control.claim_word.load(std::memory_order_acquire);
    if ((word & kStateMask) == std::uint64_t(SlotState::kFree)) return true;
    if (!process_alive(claim_pid(word))) return true;
    const auto beat = control.heartbeat_ns.load(std::memory_order_acquire);
    const auto now = monotonic_ns();
    return now > beat && now - beat > kSlotHungAfter_ns;
}

std::string_view to_string(ConsumerRole role) noexcept {
    switch (role) {
        case ConsumerRole::kDisplay:
            return "display";
        case ConsumerRole::kMonitor:
            return "monitor";
        case ConsumerRole::kTool:
            return "tool";
    }
    return "unknown";
}

Result<std::uint32_t, IpcError> claim_slot(SegmentLayout& layout, std::int32_t pid, bool telemetry,
                                           ConsumerRole role) {
    const std::uint32_t first = role == ConsumerRole::kDisplay   ? kDisplaySlot
                                : role == ConsumerRole::kMonitor ? kMonitorSlot
                                                                 : kFirstToolSlot;
    const std::uint32_t last = role == ConsumerRole::kTool ? kSlotCount : first + 1;
    for (std::uint32_t i = first; i < last; ++i) {
        ConsumerSlot& slot = layout.slots[i];
        SlotControl& c = slot.control;
        auto word = c.claim_word.load(std::memory_order_acquire);
        if (!slot_holder_gone(c)) continue;
        const std::uint64_t generation = (word >> 34) + 1;
        const auto claiming = claim_word(generation, pid, SlotState::kClaiming);
        if (!c.claim_word.compare_exchange_strong(word, claiming, std::memory_order_acq_rel,
                                                  std::memory_order_acquire)) {
            continue;
        }
        c.heartbeat_ns.store(monotonic_ns(), std::memory_order_release);
        c.consumer_pid.store(pid, std::memory_order_relaxed);
        c.flags.store(telemetry ? kSlotWantsTelemetry : 0u, std::memory_order_release);
        c.rejected_count.store(0, std::memory_order_relaxed);
        c.delivered.store(0, std::memory_order_relaxed);
        for (RingControl* r : {&slot.event_ring, &slot.telemetry_ring}) {
            r->read_index.value.store(r->write_index.value.load(std::memory_order_acquire),
                                      std::memory_order_release);
        }
        c.claim_word.store(claim_word(generation, pid, SlotState::kActive),
                           std::memory_order_release);
        return i;
    }
    std::string holders;
    for (std::uint32_t i = first; i < last; ++i) {
        holders += (holders.empty() ? "pid " : ", pid ") +
                   std::to_string(claim_pid(layout.slots[i].control.claim_word.load()));
    }
    if (role != ConsumerRole::kTool) {
        return Err{IpcError{IpcErrc::kNoFreeSlot, "",
                            "the " + std::string(to_string(role)) + " slot is held by a live " +
                                std::string(to_string(role)) + " (" + holders + ")"}};
    }
    return Err{IpcError{IpcErrc::kNoFreeSlot, "",
                        "all " + std::to_string(last - first) + " tool slots are held (" + holders +
                            "); the display and monitor slots are reserved"}};
}

void release_slot(SegmentLayout& layout, std::uint32_t slot, std::uint64_t word) noexcept {
    if (slot >= kSlotCount) return;
    SlotControl& c = layout.slots[slot].control;
    c.consumer_pid.store(0, std::memory_order_relaxed);
    const auto free_word = (word & ~std::uint64_t{(1ull << 34) - 1});  // keep generation
    c.claim_word.compare_exchange_strong(word, free_word, std::memory_order_acq_rel,
                                         std::memory_order_relaxed);
}

struct Consumer::Impl {
    explicit Impl(ShmSegment s) : segment(std::move(s)) {}
    ShmSegment segment;
    std::uint32_t slot = 0;
    std::uint64_t word = 0;
    bool telemetry_wanted = false;
    ConsumerRole role = ConsumerRole::kTool;
    std::uint64_t stale_after_ns = kDefaultStaleAfter_ns;
    SpscConsumerEnd<EventRecord, kEventCapacity> events;
    SpscConsumerEnd<TelemetrySample, kTelemetryCapacity> telemetry;
    std::optional<JournalReader> journal;
    bool journal_error_logged = false;
    std::uint64_t expected = 0;
    std::uint64_t telemetry_expected = 0;
    bool telemetry_started = false;
    bool has_pending = false;
    EventRecord pending{};
    ConsumerStats stats;

    SegmentLayout& seg() { return segment.layout(); }
    SlotControl& control() { return seg().slots[slot].control; }

    void bind_rings() {
        ConsumerSlot& s = seg().slots[slot];
        events = SpscConsumerEnd<EventRecord, kEventCapacity>::resume(&s.event_ring, s.events);
        telemetry = SpscConsumerEnd<TelemetrySample, kTelemetryCapacity>::resume(&s.telemetry_ring,
                                                                                 s.telemetry);
    }

    Status<IpcError> claim() {
        auto claimed = claim_slot(seg(), getpid(), telemetry_wanted, role);
        if (!claimed) return Err{std::move(claimed).error()};
        slot = *claimed;
        word = control().claim_word.load(std::memory_order_acquire);
        bind_rings();
        return {};
    }

    // Our slot was taken (we looked dead or someone scribbled the claim word): claim again.
    bool ensure_slot() {
        if (control().claim_word.load(std::memory_order_acquire) == word) return true;
        spdlog::warn("kerf ipc: segment {}: slot {} lost its claim; claiming again", segment.name(),
                     slot);
        has_pending = false;
        return bool(claim());
    }

    void reject_record(const char* where, RecordFault fault) {
        ++stats.rejected_records;
        control().rejected_count.store(stats.rejected_records + stats.rejected_indices,
                                       std::memory_order_relaxed);
        if (log_now(stats.rejected_records)) {
            spdlog::warn("kerf ipc: segment {}: slot {}: {} record rejected: {} ({} so far)",
                         segment.name(), slot, where, to_string(fault), stats.rejected_records);
        }
    }

    void reject_index(const char* ring) {
        ++stats.rejected_indices;
        control().rejected_count.store(stats.rejected_records + stats.rejected_indices,
                                       std::memory_order_relaxed);
        if (log_now(stats.rejected_indices)) {
            spdlog::warn(
                "kerf ipc: segment {}: slot {}: {} ring write index corrupt, resynced "
                "({} so far)",
                segment.name(), slot, ring, stats.rejected_indices);
        }
    }

    Poll deliver(const EventRecord& record, EventRecord& out, bool from_journal) {
        out = record;
        expected = record.header.sequence + 1;
        ++stats.delivered;
        if (from_journal) ++stats.from_journal;
        control().delivered.store(stats.delivered, std::memory_order_relaxed);
        return Poll::kEvent;
    }

    bool open_journal() {
        if (journal) return true;
        // Only the descriptor the producer served: a path read from the segment is never opened.
        const int served = segment.journal_fd();
        const std::string label = journal_path_of(seg().header);
        auto opened =
            served < 0
                ? Result<JournalReader, IpcError>(Err{IpcError{
                      IpcErrc::kJournal, "journal " + label, "the producer served no descriptor"}})
                : JournalReader::adopt(fcntl(served, F_DUPFD_CLOEXEC, 0), label,
                                       seg().header.session_id);
        if (!opened) {
            if (!journal_error_logged) {
                spdlog::warn("kerf ipc: segment {}: {}", segment.name(), opened.error().message());
                journal_error_logged = true;
            }
            return false;
        }
        journal.emplace(std::move(*opened));
        return true;
    }

    Poll catch_up(EventRecord& out) {
        if (!open_journal()) return Poll::kNothing;
        const auto limit = seg().journal_next_sequence.value.load(std::memory_order_acquire);
        if (expected >= limit) return Poll::kNothing;  // journal thread has not written it yet
        EventRecord record;
        switch (journal->try_read(expected, record)) {
            case JournalRead::kNotYet:
                return Poll::kNothing;
            case JournalRead::kCorrupt:
                reject_record("journal", validate_event(record));
                ++stats.lost;
                ++expected;
                return Poll::kNothing;
            case JournalRead::kOk:
                break;
        }
        if (record.header.sequence > expected) stats.lost += record.header.sequence - expected;
        return deliver(record, out, true);
    }

    Poll next(EventRecord& out) {
        if (has_pending) {
            if (pending.header.sequence < expected) {
                has_pending = false;
            } else if (pending.header.sequence == expected) {
                has_pending = false;
                return deliver(pending, out, false);
            } else {
                return catch_up(out);
            }
        }
        EventRecord record;
        for (int i = 0; i < kMaxPopsPerPoll; ++i) {
            const PopResult r = events.try_pop(record);
            if (r == PopResult::kEmpty) break;
            if (r == PopResult::kCorruptIndex) {
                reject_index("event");
                continue;
            }
            const RecordFault fault = validate_event(record);
            if (fault != RecordFault::kNone) {
                reject_record("ring", fault);
                continue;
            }
            const auto seq = record.header.sequence;
            if (seq < expected) continue;  // already delivered from the journal
            if (seq == expected) return deliver(record, out, false);
            ++stats.ring_gaps;
            pending = record;
            has_pending = true;
            return catch_up(out);
        }
        const auto published = seg().producer.next_event_sequence.load(std::memory_order_acquire);
        return published > expected ? catch_up(out) : Poll::kNothing;
    }
};

Consumer::Consumer(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Consumer::Consumer(Consumer&&) noexcept = default;
Consumer& Consumer::operator=(Consumer&&) noexcept = default;
Consumer::~Consumer() {
    if (impl_) release_slot(impl_->seg(), impl_->slot, impl_->word);
}

Poll Consumer::try_next(EventRecord& out) {
    Impl& m = *impl_;
    if (!m.ensure_slot()) return Poll::kNothing;
    m.control().heartbeat_ns.store(monotonic_ns(), std::memory_order_release);
    return m.next(out);
}

Poll Consumer::try_next_telemetry(TelemetrySample& out) {
    Impl& m = *impl_;
    if (!m.ensure_slot()) return Poll::kNothing;
    m.control().heartbeat_ns.store(monotonic_ns(), std::memory_order_release);
    for (int i = 0; i < kMaxPopsPerPoll; ++i) {
        const PopResult r = m.telemetry.try_pop(out);
        if (r == PopResult::kEmpty) return Poll::kNothing;
        if (r == PopResult::kCorruptIndex) {
            m.reject_index("telemetry");
            continue;
        }
        const RecordFault fault = validate_telemetry(out);
        if (fault != RecordFault::kNone) {
            m.reject_record("telemetry", fault);
            continue;
        }
        const auto seq = out.header.sequence;
        if (m.telemetry_started && seq > m.telemetry_expected) {
            m.stats.telemetry_gaps += seq - m.telemetry_expected;
        }
        m.telemetry_started = true;
        m.telemetry_expected = seq + 1;
        ++m.stats.telemetry;
        return Poll::kEvent;
    }
    return Poll::kNothing;
}

SeqlockRead Consumer::try_read_state(LatestState& out) {
    const SeqlockRead r = try_seqlock_read(impl_->seg().state, out);
    if (r != SeqlockRead::kOk) return r;
    const RecordFault fault = validate_state(out);
    if (fault == RecordFault::kNone) return r;
    impl_->reject_record("state", fault);
    return SeqlockRead::kBusy;
}

ProducerHealth Consumer::producer_health() const {
    return kerf::ipc::producer_health(impl_->seg(), impl_->stale_after_ns);
}

std::uint64_t Consumer::next_sequence() const noexcept { return impl_->expected; }
std::uint32_t Consumer::slot() const noexcept { return impl_->slot; }
const ConsumerStats& Consumer::stats() const noexcept { return impl_->stats; }
const SegmentLayout& Consumer::layout() const noexcept { return impl_->segment.layout(); }
SegmentLayout& Consumer::writable_layout() noexcept { return impl_->segment.layout(); }

ConsumerBuilder& ConsumerBuilder::segment_name(std::string name) {
    name_ = std::move(name);
    return *this;
}
ConsumerBuilder& ConsumerBuilder::from_sequence(std::uint64_t sequence) {
    from_ = sequence;
    return *this;
}
ConsumerBuilder& ConsumerBuilder::telemetry(bool wanted) {
    telemetry_ = wanted;
    return *this;
}
ConsumerBuilder& ConsumerBuilder::role(ConsumerRole consumer_role) {
    role_ = consumer_role;
    return *this;
}
ConsumerBuilder& ConsumerBuilder::stale_after_ns(std::uint64_t age_ns) {
    stale_after_ns_ = age_ns;
    return *this;
}

Result<Consumer, IpcError> ConsumerBuilder::attach() const {
    auto segment = SegmentBuilder().name(name_).open();
    if (!segment) return Err{std::move(segment).error()};
    auto impl = std::make_unique<Consumer::Impl>(std::move(*segment));
    const std::string where = "segment " + name_;
    const auto state = impl->seg().header.state.load(std::memory_order_acquire);
    if (state != std::uint32_t(SegmentState::kRunning)) {
        return Err{IpcError{
            IpcErrc::kProducerGone, where,
            "state " + std::string(to_string(SegmentState(state))) + ", expected running"}};
    }
    const ProducerHealth health = kerf::ipc::producer_health(impl->seg(), stale_after_ns_);
    if (health != ProducerHealth::kAlive) {
        return Err{IpcError{IpcErrc::kProducerGone, where,
                            "producer pid " + std::to_string(impl->seg().header.producer_pid) +
                                " is " + std::string(to_string(health))}};
    }
    impl->telemetry_wanted = telemetry_;
    impl->role = role_;
    impl->stale_after_ns = stale_after_ns_;
    impl->expected = from_ == kFromNow
                         ? impl->seg().producer.next_event_sequence.load(std::memory_order_acquire)
                         : from_;
    if (auto claimed = impl->claim(); !claimed) {
        IpcError e = claimed.error();
        e.where = where;
        return Err{std::move(e)};
    }
    return Consumer(std::move(impl));
}

}  // namespace kerf::ipc
