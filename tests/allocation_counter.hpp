// Counts heap allocations made by the calling thread while armed: the proof that a real-time path
// allocates nothing. allocation_counter.cpp replaces global operator new/delete; add it to the
// sources of each test binary that uses this (kerf_add_test(... SOURCES
// ../allocation_counter.cpp)). The replacements live in their own translation unit on purpose:
// visible next to `new T`, GCC 12 inlines them and then warns (-Wmismatched-new-delete) under
// -Werror.
#pragma once

#include <cstdint>

namespace kerf::test {

void arm_allocation_counter() noexcept;
/// Disarms and returns the allocations counted since arming.
std::uint64_t disarm_allocation_counter() noexcept;

}  // namespace kerf::test
