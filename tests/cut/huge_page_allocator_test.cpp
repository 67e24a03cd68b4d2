// HugePageAllocator: a large block is a fresh mapping of its own, 2 MiB-aligned (so the kernel can
// back it with huge pages from its first touch), holds what is written to it, and is unmapped
// when freed; a small block is an ordinary allocation that still honours the element's
// alignment (the face tree's 64-byte groups).
#include "display/cut/huge_page_allocator.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace kerf::cut::detail {
namespace {

struct alignas(64) Line {
    std::uint64_t words[8];
};

// Whether any mapping in /proc/self/maps covers address p.
bool mapped(const void* p) {
    std::ifstream maps("/proc/self/maps");
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    std::string line;
    while (std::getline(maps, line)) {
        std::uintptr_t begin = 0, end = 0;
        if (std::sscanf(line.c_str(), "%lx-%lx", &begin, &end) == 2 && at >= begin && at < end)
            return true;
    }
    return false;
}

// The AnonHugePages of the mapping that covers p, kB (-1 when /proc/self/smaps cannot tell).
long huge_kb_at(const void* p) {
    std::ifstream smaps("/proc/self/smaps");
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        if (std::sscanf(line.c_str(), "%lx-%lx ", &begin, &end) == 2 &&
            line.find(':') > line.find(' ')) {
            inside = at >= begin && at < end;
            continue;
        }
        long kb = 0;
        if (inside && std::sscanf(line.c_str(), "AnonHugePages: %ld kB", &kb) == 1) return kb;
    }
    return -1;
}

TEST(HugePageAllocator, LargeBlocksAreTheirOwnAlignedMappingsAndAreUnmappedWhenFreed) {
    // A 30 MiB malloc and free first: glibc then raises its mmap threshold to 30 MiB and serves
    // smaller blocks from the heap, here from the pages of a 20 MiB array already touched (4 KiB
    // pages the huge-page advice no longer changes) and kept in the heap when freed. The
    // allocator must map its blocks itself.
    void* volatile raise = std::malloc(std::size_t{30} << 20);
    std::free(raise);
    void* volatile touched = std::malloc(std::size_t{20} << 20);
    std::memset(touched, 1, std::size_t{20} << 20);
    std::free(touched);
    const std::size_t n = (std::size_t{16} << 20) / sizeof(Line);  // 16 MiB
    const Line* first = nullptr;
    {
        std::vector<Line, HugePageAllocator<Line>> v(n);
        first = v.data();
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(first) % kHugePageBytes, 0u);
        for (std::size_t i = 0; i < n; ++i) v[i].words[i % 8] = i;
        for (std::size_t i = 0; i < n; i += 4099) ASSERT_EQ(v[i].words[i % 8], i) << i;
        ASSERT_TRUE(mapped(first));
        ASSERT_TRUE(mapped(first + n - 1));
        // Huge pages are the kernel's to give (THP may be off, or memory too fragmented): shown,
        // not asserted.
        std::printf("16 MiB block: %ld kB on huge pages\n", huge_kb_at(first));
    }
    EXPECT_FALSE(mapped(first)) << "a freed large block stays mapped";
}

TEST(HugePageAllocator, SmallBlocksHonourTheElementsAlignment) {
    std::vector<std::vector<Line, HugePageAllocator<Line>>> blocks;
    for (std::size_t n = 1; n < 2000; n = n * 3 + 1) {
        blocks.emplace_back(n);
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blocks.back().data()) % alignof(Line), 0u) << n;
        blocks.back().back().words[7] = n;
    }
    for (auto& b : blocks) EXPECT_EQ(b.back().words[7], b.size());
}

}  // namespace
}  // namespace kerf::cut::detail
