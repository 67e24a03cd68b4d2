// The producer's per-tick API allocates nothing: global operator new/delete are replaced in this
// test binary and counted across 10,000 ticks of heartbeat + event + telemetry + state publishes,
// with two consumers attached (one of them never reading, so its rings overflow and drop).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <optional>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/producer.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace {
std::atomic<std::uint64_t> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    throw std::bad_alloc{};
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, std::align_val_t align) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    const std::size_t a = static_cast<std::size_t>(align);
    if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
    throw std::bad_alloc{};
}
void* operator new[](std::size_t size, std::align_val_t align) { return operator new(size, align); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace kerf::ipc {
namespace {

TEST(ProducerAllocations, TenThousandTicksOfPublishingAllocateNothing) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("alloc");
    auto producer = ProducerBuilder().segment_name(name).journal_dir(dir.path).create();
    ASSERT_TRUE(producer) << producer.error().message;
    producer->heartbeat(0, monotonic_ns());
    auto reader = ConsumerBuilder().segment_name(name).telemetry(true).attach();
    auto sleeper = ConsumerBuilder().segment_name(name).telemetry(true).attach();
    ASSERT_TRUE(reader && sleeper);
    EventRecord event = test::make_event(0);
    TelemetrySample sample = test::make_sample(0);
    LatestState state{};
    state.tool_orientation_wxyz[0] = 1.0;

    const auto before = g_allocations.load();
    for (std::uint64_t tick = 1; tick <= 10'000; ++tick) {
        producer->heartbeat(tick, monotonic_ns());
        producer->publish_event(event);
        producer->publish_telemetry(sample);
        state.tick = tick;
        producer->publish_state(state);
    }
    const auto after = g_allocations.load();
    EXPECT_EQ(after - before, 0u) << "the producer allocated on the real-time path";
    // The sleeper's rings overflowed (drop path exercised), the journal took everything.
    EXPECT_GT(producer->layout().producer.events_dropped.load(), 0u);
    EXPECT_GT(producer->layout().producer.telemetry_dropped.load(), 0u);
    EXPECT_EQ(producer->layout().journal_dropped.value.load(), 0u);
}

}  // namespace
}  // namespace kerf::ipc
