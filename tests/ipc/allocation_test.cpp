// The producer's per-tick API allocates nothing: global operator new/delete are replaced in this
// test binary (tests/allocation_counter.cpp) and the calling thread's allocations counted across
// 10,000 ticks of heartbeat + event + telemetry + state publishes,
// with two consumers attached (one of them never reading, so its rings overflow and drop).
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/producer.hpp"
#include "tests/allocation_counter.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

TEST(ProducerAllocations, TenThousandTicksOfPublishingAllocateNothing) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("alloc");
    auto producer = ProducerBuilder().segment_name(name).journal_dir(dir.path).create();
    ASSERT_TRUE(producer) << producer.error().message();
    // Beat just before attaching, with a heartbeat limit fit for a loaded machine: the test can be
    // descheduled for longer than the 40 ms default between the beat and an attach.
    producer->heartbeat(0, monotonic_ns());
    const auto consumer = ConsumerBuilder().segment_name(name).telemetry(true).stale_after_ns(
        test::kLoadedMachineStaleAfter_ns);
    auto reader = consumer.attach();
    auto sleeper = consumer.attach();
    ASSERT_TRUE(reader) << reader.error().message();
    ASSERT_TRUE(sleeper) << sleeper.error().message();
    EventRecord event = test::make_event(0);
    TelemetrySample sample = test::make_sample(0);
    LatestState state{};
    state.tool_orientation_wxyz[0] = 1.0;

    kerf::test::arm_allocation_counter();
    for (std::uint64_t tick = 1; tick <= 10'000; ++tick) {
        producer->heartbeat(tick, monotonic_ns());
        producer->publish_event(event);
        producer->publish_telemetry(sample);
        state.tick = tick;
        producer->publish_state(state);
    }
    EXPECT_EQ(kerf::test::disarm_allocation_counter(), 0u)
        << "the producer allocated on the real-time path";
    // The sleeper's rings overflowed (drop path exercised), the journal took everything.
    EXPECT_GT(producer->layout().producer.events_dropped.load(), 0u);
    EXPECT_GT(producer->layout().producer.telemetry_dropped.load(), 0u);
    EXPECT_EQ(producer->layout().journal_dropped.value.load(), 0u);
}

}  // namespace
}  // namespace kerf::ipc
