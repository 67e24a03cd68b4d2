// Counts heap allocations made by the calling thread while armed (replaces global operator new
// in allocation_counter.cpp; link that file into one test binary only).
#pragma once

#include <cstdint>

namespace kerf::firmware_host::test {

void arm_allocation_counter() noexcept;
/// Disarms and returns the allocations counted since arming.
std::uint64_t disarm_allocation_counter() noexcept;

}  // namespace kerf::firmware_host::test
