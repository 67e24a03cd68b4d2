// FaultLatch from several threads at once: one records, others read, one clears. Run under TSan
// in CI (label `concurrent`).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <string_view>
#include <thread>
#include <vector>

#include "config/base/check.hpp"

namespace kerf {
namespace {

TEST(FaultLatchConcurrent, ManyRecordersKeepExactlyOneWholeFaultAndCountAll) {
    FaultLatch latch;
    constexpr int kThreads = 4;
    constexpr int kPerThread = 5'000;
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&latch, t] {
            for (int i = 0; i < kPerThread; ++i) {
                // Each thread's faults carry its own code and line = code, so a torn record
                // (fields from two different faults) would show as line != code.
                const auto id = static_cast<std::uint16_t>(t + 1);
                latch.record(Fault{"thread", id, id, "torn?"});
            }
        });
    }
    for (auto& th : threads) th.join();
    EXPECT_EQ(latch.failures(), static_cast<std::uint32_t>(kThreads * kPerThread));
    auto f = latch.first();
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->line, f->code);
    EXPECT_GE(f->code, 1u);
    EXPECT_LE(f->code, static_cast<std::uint16_t>(kThreads));
}

TEST(FaultLatchConcurrent, AReaderNeverSeesATornFaultWhileTheOwnerClearsAndRecords) {
    FaultLatch latch;
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> whole_reads{0};
    std::atomic<std::uint64_t> torn_reads{0};
    std::thread reader([&] {
        while (!stop.load(std::memory_order_relaxed) || whole_reads.load() < 100) {
            if (auto f = latch.first()) {
                (f->line == f->code ? whole_reads : torn_reads).fetch_add(1);
            }
        }
    });
    // Lockstep on the reader's progress, not on time: the owner keeps cycling until the reader
    // has seen at least 100 whole faults.
    for (std::uint32_t i = 1; whole_reads.load() < 100 || i < 20'000; ++i) {
        const auto id = static_cast<std::uint16_t>(i % 60'000 + 1);
        latch.record(Fault{"owner", id, id, "cycled"});
        std::this_thread::yield();
        latch.clear();
    }
    latch.record(Fault{"owner", 1, 1, "last"});
    stop.store(true);
    reader.join();
    EXPECT_EQ(torn_reads.load(), 0u);
    EXPECT_GE(whole_reads.load(), 100u);
}

}  // namespace
}  // namespace kerf
