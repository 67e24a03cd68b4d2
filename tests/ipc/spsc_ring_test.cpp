// SpscRing, Seqlock and record validation, single-threaded: the rules, one at a time.
#include "rt_core/ipc/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/seqlock.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

struct Item {
    std::uint64_t value;
    std::uint64_t pad[7];
};

struct Ring8 {
    RingControl control{};
    Item slots[8]{};
    SpscProducerEnd<Item, 8> producer{&control, slots};
    SpscConsumerEnd<Item, 8> consumer{&control, slots};
};

TEST(SpscRing, DeliversInOrderAcrossWrapAround) {
    auto ring = std::make_unique<Ring8>();
    std::uint64_t next_out = 0;
    for (std::uint64_t i = 0; i < 100; ++i) {
        ASSERT_TRUE(ring->producer.try_push(Item{i, {}}));
        if (i % 3 == 2) {
            Item out{};
            while (ring->consumer.try_pop(out) == PopResult::kOk) EXPECT_EQ(out.value, next_out++);
        }
    }
    Item out{};
    while (ring->consumer.try_pop(out) == PopResult::kOk) EXPECT_EQ(out.value, next_out++);
    EXPECT_EQ(next_out, 100u);
    EXPECT_EQ(ring->producer.dropped(), 0u);
}

TEST(SpscRing, OverflowDropsNewestAndCountsIt) {
    auto ring = std::make_unique<Ring8>();
    for (std::uint64_t i = 0; i < 8; ++i) ASSERT_TRUE(ring->producer.try_push(Item{i, {}}));
    EXPECT_FALSE(ring->producer.try_push(Item{8, {}}));
    EXPECT_FALSE(ring->producer.try_push(Item{9, {}}));
    EXPECT_EQ(ring->producer.dropped(), 2u);
    EXPECT_EQ(ring->control.dropped_count.value.load(), 2u);
    EXPECT_EQ(ring->control.pushed_count.value.load(), 8u);
    Item out{};
    for (std::uint64_t i = 0; i < 8; ++i) {  // the oldest survive: 0..7, not 8 or 9
        ASSERT_EQ(ring->consumer.try_pop(out), PopResult::kOk);
        EXPECT_EQ(out.value, i);
    }
    EXPECT_EQ(ring->consumer.try_pop(out), PopResult::kEmpty);
    EXPECT_TRUE(ring->producer.try_push(Item{10, {}}));  // room again after the consumer read
}

TEST(SpscRing, EmptyRingPopsNothing) {
    auto ring = std::make_unique<Ring8>();
    Item out{};
    EXPECT_EQ(ring->consumer.try_pop(out), PopResult::kEmpty);
    EXPECT_EQ(ring->consumer.lag(), 0u);
}

TEST(SpscRing, CorruptWriteIndexIsReportedAndResynced) {
    auto ring = std::make_unique<Ring8>();
    ring->control.write_index.value.store(1'000'000);  // a scribbler jumped it by >> capacity
    Item out{};
    EXPECT_EQ(ring->consumer.try_pop(out), PopResult::kCorruptIndex);
    EXPECT_EQ(ring->consumer.try_pop(out), PopResult::kEmpty);
    EXPECT_EQ(ring->control.read_index.value.load(), 1'000'000u);
}

TEST(SpscRing, GarbageReadIndexNeverMakesTheProducerWriteOutOfBounds) {
    auto ring = std::make_unique<Ring8>();
    for (std::uint64_t i = 0; i < 8; ++i) ASSERT_TRUE(ring->producer.try_push(Item{i, {}}));
    ring->control.read_index.value.store(~0ull);  // scribbled: "read ahead of write"
    EXPECT_FALSE(ring->producer.try_push(Item{8, {}}));
    EXPECT_EQ(ring->producer.dropped(), 1u);
}

TEST(Seqlock, ReadsBackTheLastWrite) {
    auto cell = std::make_unique<SeqlockCell<LatestState>>();
    LatestState out{};
    EXPECT_EQ(try_seqlock_read(*cell, out), SeqlockRead::kNeverWritten);
    LatestState s{};
    s.tick = 42;
    s.force_n[2] = 1.5;
    seqlock_write(*cell, s);
    ASSERT_EQ(try_seqlock_read(*cell, out), SeqlockRead::kOk);
    EXPECT_EQ(out.tick, 42u);
    EXPECT_EQ(out.force_n[2], 1.5);
    EXPECT_EQ(cell->sequence.value.load() % 2, 0u);
}

TEST(Seqlock, ReaderGivesUpWhileAWriteIsInProgress) {
    auto cell = std::make_unique<SeqlockCell<LatestState>>();
    cell->sequence.value.store(3);  // odd: a writer died mid-write (or a scribbler)
    LatestState out{};
    EXPECT_EQ(try_seqlock_read(*cell, out, 10), SeqlockRead::kBusy);
}

TEST(RecordCheck, StampedRecordsOfEveryTypeValidate) {
    for (std::uint64_t i = 0; i < 5; ++i) {
        EventRecord r = test::make_event(i);
        stamp_checksum(r);
        EXPECT_EQ(validate_event(r), RecordFault::kNone) << to_string(r.header.type);
    }
    EventRecord d{};
    d.header.type = EventType::kDeviceStateChanged;
    d.device.state = DeviceState::kFault;
    stamp_checksum(d);
    EXPECT_EQ(validate_event(d), RecordFault::kNone);
    EventRecord reset{};
    reset.header.type = EventType::kSessionReset;
    stamp_checksum(reset);
    EXPECT_EQ(validate_event(reset), RecordFault::kNone);
}

TEST(RecordCheck, AnyFlippedBitFailsTheChecksum) {
    EventRecord r = test::make_event(3);
    stamp_checksum(r);
    for (std::size_t byte = 0; byte < sizeof r; ++byte) {
        if (byte >= 20 && byte < 24) continue;  // the checksum itself
        EventRecord bad = r;
        reinterpret_cast<unsigned char*>(&bad)[byte] ^= 0x10;
        EXPECT_EQ(validate_event(bad), RecordFault::kBadChecksum) << "byte " << byte;
    }
}

TEST(RecordCheck, BadTypeNanAndRangesAreRejectedByName) {
    EventRecord r = test::make_event(0);
    r.header.type = static_cast<EventType>(55);
    stamp_checksum(r);
    EXPECT_EQ(validate_event(r), RecordFault::kBadType);

    r = test::make_event(0);
    r.cut.plane_point_m[1] = std::numeric_limits<float>::quiet_NaN();
    stamp_checksum(r);
    EXPECT_EQ(validate_event(r), RecordFault::kNotFinite);

    r = test::make_event(0);
    r.cut.plane_normal[2] = 2.0f;  // not unit
    stamp_checksum(r);
    EXPECT_EQ(validate_event(r), RecordFault::kOutOfRange);

    r = test::make_event(1);
    r.cut.end_reason = CutEndReason::kAborted;  // only cut_end carries a reason
    stamp_checksum(r);
    EXPECT_EQ(validate_event(r), RecordFault::kOutOfRange);

    r = test::make_event(4);
    std::memset(r.parameters.name, 'x', sizeof r.parameters.name);  // no terminator
    stamp_checksum(r);
    EXPECT_EQ(validate_event(r), RecordFault::kOutOfRange);

    TelemetrySample s = test::make_sample(1);
    s.force_n[0] = std::numeric_limits<float>::infinity();
    stamp_checksum(s);
    EXPECT_EQ(validate_telemetry(s), RecordFault::kNotFinite);
    EXPECT_EQ(to_string(RecordFault::kBadChecksum), "bad_checksum");
}

}  // namespace
}  // namespace kerf::ipc
