// The consumer slots of a session segment as kerf.toml's [shm] consumer_slots sees them: how many
// a segment has (rt_core/ipc/layout.hpp, kSlotCount) and how many are reserved — slot 0 for
// kerf-display, slot 1 for the soak monitor. Tools share the rest, so `consumer_slots` must leave
// at least one. tests/ipc/layout_test.cpp checks these against the layout.
#pragma once

#include <cstdint>

namespace kerf::config {

/// Consumer slots in one session segment.
inline constexpr std::uint32_t kSegmentConsumerSlots = 4;
/// Slots no tool may take (the display's and the soak monitor's).
inline constexpr std::uint32_t kReservedConsumerSlots = 2;

}  // namespace kerf::config
