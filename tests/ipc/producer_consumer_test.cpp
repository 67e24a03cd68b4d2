// Producer and Consumer in one process, one thread: ordering, catch-up from the journal (late
// attach, drops), slots (claim, release, reclaim), telemetry gaps, the state seqlock, rejection
// of scribbled records.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <optional>
#include <thread>
#include <vector>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/journal_reader.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

struct Session {
    test::ScratchDir dir;
    std::string name = test::unique_segment_name("pc");
    std::optional<Producer> producer;
    Session() {
        auto p = ProducerBuilder()
                     .segment_name(name)
                     .journal_dir(dir.path)
                     .journal_flush_period_ns(1'000'000)
                     .create();
        EXPECT_TRUE(p) << (p ? "" : p.error().message());
        if (p) producer.emplace(std::move(*p));
        producer->heartbeat(0, monotonic_ns());
    }
    /// A consumer of this session: the producer beats just before the attach, as a ticking one
    /// would, and the heartbeat limit fits a loaded machine (test::kLoadedMachineStaleAfter_ns).
    ConsumerBuilder consumer() {
        producer->heartbeat(0, monotonic_ns());
        return ConsumerBuilder().segment_name(name).stale_after_ns(
            test::kLoadedMachineStaleAfter_ns);
    }
    void publish(std::uint64_t from, std::uint64_t to) {
        for (std::uint64_t i = from; i < to; ++i) {
            EventRecord r = test::make_event(i);
            producer->publish_event(r);
        }
    }
};

/// Polls until `count` events arrived or 5 s passed; checks each is make_event(seq).
std::vector<std::uint64_t> drain(Consumer& c, std::uint64_t count) {
    std::vector<std::uint64_t> seqs;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    EventRecord r;
    while (seqs.size() < count && std::chrono::steady_clock::now() < deadline) {
        if (c.try_next(r) == Poll::kEvent) {
            EventRecord want = test::make_event(r.header.sequence);
            want.header.sequence = r.header.sequence;
            stamp_checksum(want);
            EXPECT_EQ(std::memcmp(&want, &r, sizeof r), 0) << "seq " << r.header.sequence;
            seqs.push_back(r.header.sequence);
        } else {
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    }
    return seqs;
}

void expect_contiguous(const std::vector<std::uint64_t>& seqs, std::uint64_t first,
                       std::uint64_t count) {
    ASSERT_EQ(seqs.size(), count);
    for (std::uint64_t i = 0; i < count; ++i) ASSERT_EQ(seqs[i], first + i);
}

TEST(ProducerConsumer, EventsArriveInSequenceThroughTheRing) {
    Session s;
    auto c = s.consumer().from_sequence(ConsumerBuilder::kFromNow).attach();
    ASSERT_TRUE(c) << c.error().message();
    s.publish(0, 1000);  // < ring capacity: no drops
    expect_contiguous(drain(*c, 1000), 0, 1000);
    EXPECT_EQ(c->stats().from_journal, 0u);
    EXPECT_EQ(c->stats().ring_gaps, 0u);
}

TEST(ProducerConsumer, LateConsumerReadsTheJournalThenFollowsTheRing) {
    Session s;
    s.publish(0, 3000);
    auto c = s.consumer().attach();  // from 0
    ASSERT_TRUE(c) << c.error().message();
    s.publish(3000, 3500);
    expect_contiguous(drain(*c, 3500), 0, 3500);
    EXPECT_EQ(c->stats().from_journal, 3000u);
    EXPECT_EQ(c->stats().lost, 0u);
}

TEST(ProducerConsumer, OverflowDropsAreFilledFromTheJournalExactly) {
    Session s;
    auto c = s.consumer().attach();
    ASSERT_TRUE(c) << c.error().message();
    s.publish(0, kEventCapacity + 1000);  // consumer asleep: 1000 dropped for it
    const auto& ring = s.producer->layout().slots[c->slot()].event_ring;
    EXPECT_EQ(ring.dropped_count.value.load(), 1000u);
    EXPECT_EQ(ring.pushed_count.value.load(), kEventCapacity);
    EXPECT_EQ(s.producer->layout().producer.events_dropped.load(), 1000u);
    expect_contiguous(drain(*c, 10), 0, 10);                  // frees 10 ring slots
    s.publish(kEventCapacity + 1000, kEventCapacity + 1005);  // these fit: ring shows a gap
    expect_contiguous(drain(*c, kEventCapacity + 995), 10, kEventCapacity + 995);
    EXPECT_EQ(c->stats().ring_gaps, 1u);
    EXPECT_EQ(c->stats().from_journal, 1000u);  // exactly the dropped ones
    EXPECT_EQ(c->stats().lost, 0u);
}

TEST(ProducerConsumer, PublishOutcomeCountsDeliveriesAndDrops) {
    Session s;
    auto a = s.consumer().attach();
    auto b = s.consumer().attach();
    ASSERT_TRUE(a) << a.error().message();
    ASSERT_TRUE(b) << b.error().message();
    EXPECT_NE(a->slot(), b->slot());
    EventRecord r = test::make_event(0);
    PublishOutcome o = s.producer->publish_event(r);
    EXPECT_EQ(o.sequence, 0u);
    EXPECT_EQ(o.delivered, 2u);
    EXPECT_EQ(o.dropped, 0u);
    EXPECT_TRUE(o.journalled);
}

TEST(ProducerConsumer, ToolSlotsRunOutThenFreeOnReleaseButNeverLockOutDisplayOrMonitor) {
    Session s;
    std::vector<Consumer> held;
    for (std::uint32_t i = kFirstToolSlot; i < kSlotCount; ++i) {
        auto c = s.consumer().attach();
        ASSERT_TRUE(c) << c.error().message();
        EXPECT_GE(c->slot(), kFirstToolSlot);
        held.push_back(std::move(*c));
    }
    auto extra = s.consumer().attach();
    ASSERT_FALSE(extra);
    EXPECT_EQ(extra.error().code, IpcErrc::kNoFreeSlot);
    EXPECT_NE(extra.error().message().find("tool slots are held"), std::string::npos)
        << extra.error().message();
    auto display = s.consumer().role(ConsumerRole::kDisplay).attach();
    ASSERT_TRUE(display) << display.error().message();
    EXPECT_EQ(display->slot(), kDisplaySlot);
    auto monitor = s.consumer().role(ConsumerRole::kMonitor).attach();
    ASSERT_TRUE(monitor) << monitor.error().message();
    EXPECT_EQ(monitor->slot(), kMonitorSlot);
    auto second = s.consumer().role(ConsumerRole::kDisplay).attach();
    ASSERT_FALSE(second);
    EXPECT_NE(second.error().message().find("display slot is held"), std::string::npos)
        << second.error().message();
    held.pop_back();
    EXPECT_TRUE(s.consumer().attach());
}

TEST(ProducerConsumer, SlotOfADeadConsumerIsReclaimed) {
    Session s;
    SegmentLayout& seg = const_cast<SegmentLayout&>(s.producer->layout());
    for (std::uint32_t i = 0; i < kSlotCount; ++i) {  // every slot "held" by a dead pid
        seg.slots[i].control.claim_word.store(claim_word(1, 999'999'9, SlotState::kActive));
        seg.slots[i].control.heartbeat_ns.store(monotonic_ns());
    }
    auto c = s.consumer().attach();
    ASSERT_TRUE(c) << c.error().message();
    s.publish(0, 10);
    expect_contiguous(drain(*c, 10), 0, 10);
}

TEST(ProducerConsumer, ConsumerRefusesStoppedOrDeadProducer) {
    Session s;
    s.producer->stop();
    auto c = s.consumer().attach();
    ASSERT_FALSE(c);
    EXPECT_EQ(c.error().code, IpcErrc::kProducerGone);
    EXPECT_NE(c.error().message().find("stopped"), std::string::npos) << c.error().message();
}

TEST(ProducerConsumer, TelemetryGapsAreCountedNotFilled) {
    Session s;
    auto c = s.consumer().telemetry(true).attach();
    ASSERT_TRUE(c) << c.error().message();
    for (std::uint64_t i = 0; i < kTelemetryCapacity + 500; ++i) {
        TelemetrySample t = test::make_sample(i);
        s.producer->publish_telemetry(t);
    }
    EXPECT_EQ(s.producer->layout().producer.telemetry_dropped.load(), 500u);
    TelemetrySample t;
    std::uint64_t got = 0;
    while (c->try_next_telemetry(t) == Poll::kEvent) ++got;
    EXPECT_EQ(got, kTelemetryCapacity);
    for (std::uint64_t i = 0; i < 10; ++i) {
        TelemetrySample more = test::make_sample(i);
        s.producer->publish_telemetry(more);
    }
    while (c->try_next_telemetry(t) == Poll::kEvent) ++got;
    EXPECT_EQ(got, kTelemetryCapacity + 10);
    EXPECT_EQ(c->stats().telemetry_gaps, 500u);
}

TEST(ProducerConsumer, ConsumersWithoutTelemetryGetNone) {
    Session s;
    auto c = s.consumer().attach();
    ASSERT_TRUE(c) << c.error().message();
    TelemetrySample t = test::make_sample(0);
    s.producer->publish_telemetry(t);
    EXPECT_EQ(c->try_next_telemetry(t), Poll::kNothing);
}

TEST(ProducerConsumer, StateSeqlockCarriesTheLatestValue) {
    Session s;
    auto c = s.consumer().attach();
    ASSERT_TRUE(c) << c.error().message();
    LatestState out{};
    EXPECT_EQ(c->try_read_state(out), SeqlockRead::kNeverWritten);
    LatestState st{};
    st.tick = 7;
    st.tool_orientation_wxyz[0] = 1.0;
    s.producer->publish_state(st);
    st.tick = 8;
    s.producer->publish_state(st);
    ASSERT_EQ(c->try_read_state(out), SeqlockRead::kOk);
    EXPECT_EQ(out.tick, 8u);
}

TEST(ProducerConsumer, ScribbledRingRecordIsRejectedCountedAndRecoveredFromTheJournal) {
    Session s;
    auto c = s.consumer().attach();
    ASSERT_TRUE(c) << c.error().message();
    s.publish(0, 10);
    SegmentLayout& seg = const_cast<SegmentLayout&>(s.producer->layout());
    const auto base = seg.slots[c->slot()].event_ring.read_index.value.load();
    seg.slots[c->slot()].events[(base + 4) % kEventCapacity].raw[3] ^= 0xFF;  // record 4 garbled
    expect_contiguous(drain(*c, 10), 0, 10);
    EXPECT_EQ(c->stats().rejected_records, 1u);
    EXPECT_EQ(c->stats().from_journal, 1u);
    EXPECT_EQ(seg.slots[c->slot()].control.rejected_count.load(), 1u);
}

TEST(ProducerConsumer, JournalHoldsEverythingAfterStop) {
    Session s;
    s.publish(0, 500);
    const std::string path = s.producer->journal_path();
    s.producer->stop();
    auto j = JournalReader::open(path, s.producer->layout().header.session_id);
    ASSERT_TRUE(j) << j.error().message();
    EXPECT_EQ(j->record_count(), 500u);
    EventRecord r;
    ASSERT_EQ(j->try_read(321, r), JournalRead::kOk);
    EXPECT_EQ(r.header.sequence, 321u);
    EXPECT_EQ(j->try_read(500, r), JournalRead::kNotYet);
    EXPECT_EQ(s.producer->layout().journal_next_sequence.value.load(), 500u);
}

}  // namespace
}  // namespace kerf::ipc
