// keep_freed_memory(): the heap kerf-rt sets up before its first world build. The world builder
// thread must allocate from the same heap the main thread's first build (and its throwaway
// update) freed, so a collision update after a cut reuses pages already faulted in and locked
// instead of growing a thread arena of its own (the soak's "kerf-rt memory grew 1-2 %").
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "rt_core/loop/realtime_setup.hpp"

namespace {

constexpr std::size_t kBlocks = 128;
constexpr std::size_t kBlockBytes = 64 * 1024;  // below the mmap threshold: from the heap

TEST(KeepFreedMemory, AnotherThreadReusesWhatTheMainThreadFreed) {
    if (!kerf::rt::keep_freed_memory().ok)
        GTEST_SKIP() << "mallopt refused (a sanitizer's allocator replaces glibc's)";
    // The main thread faults in 8 MiB of heap and frees it, as the first build's update does.
    std::vector<void*> blocks;
    auto lo = UINTPTR_MAX, hi = std::uintptr_t{0};
    for (std::size_t i = 0; i < kBlocks; ++i) {
        void* p = std::malloc(kBlockBytes);
        ASSERT_NE(p, nullptr);
        std::memset(p, 1, kBlockBytes);
        lo = std::min(lo, reinterpret_cast<std::uintptr_t>(p));
        hi = std::max(hi, reinterpret_cast<std::uintptr_t>(p) + kBlockBytes);
        blocks.push_back(p);
    }
    for (void* p : blocks) std::free(p);
    // A new thread (the world builder) allocates as much: it must land in those freed pages
    // (all but a block or two: the thread's start-up takes a few bytes of them, and the heap may
    // hold an older free chunk elsewhere). In an arena of its own, none would.
    std::size_t reused = 0;
    std::thread builder([&] {
        std::vector<void*> mine;
        for (std::size_t i = 0; i < kBlocks; ++i) {
            void* p = std::malloc(kBlockBytes);
            const auto a = reinterpret_cast<std::uintptr_t>(p);
            reused += p && a >= lo && a + kBlockBytes <= hi;
            mine.push_back(p);
        }
        for (void* p : mine) std::free(p);
    });
    builder.join();
    EXPECT_GE(reused, kBlocks - 2) << "the thread allocated outside the main thread's freed heap "
                                      "(an arena of its own)";
}

}  // namespace
