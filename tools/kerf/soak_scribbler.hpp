// `kerf soak`'s hostile neighbour: for a while, random bytes over a live session segment's event
// records and ring indices (the display's slot, the soak monitor's event ring, the spare slots),
// and over the mesh mailbox's newest-buffer word and the bytes of its buffers — everything a
// consumer writes or reads besides the header. Once a millisecond, deterministic for a seed.
// kerf-rt must not notice; the display and the monitor must reject what they read, fill the gaps
// from the journal and end with the same events and mesh as without it.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "config/base/result.hpp"

namespace kerf::cli {

/// Scribbles over `session`'s segment for `seconds` (or until `stop`); returns the number of
/// scribbles, or why the segment could not be opened.
Result<std::uint64_t, std::string> scribble_segment(const std::string& session, double seconds,
                                                    std::uint64_t seed,
                                                    const std::atomic<bool>& stop);

}  // namespace kerf::cli
