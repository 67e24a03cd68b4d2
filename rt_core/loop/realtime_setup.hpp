// Real-time set-up of the calling thread: the scheduling policy and priority, mlockall and CPU
// affinity that kerf.toml [realtime] requests. Each request is made, its result checked and kept
// in a RealtimeReport the process prints at start. Denied requests leave the loop running
// degraded (and saying so) unless `require_realtime` is set, in which case the caller refuses.
// Configure-time only (allocates, makes system calls).
#pragma once

#include <string>
#include <vector>

#include "config/kerf_config.hpp"

namespace kerf::rt {

/// One request and what the kernel answered.
struct RealtimeItem {
    std::string what;    ///< e.g. "SCHED_FIFO priority 80"
    bool ok = false;     ///< granted
    std::string result;  ///< "ok" or the reason it was denied (strerror + hint)
};

/// Everything requested at start.
struct RealtimeReport {
    std::vector<RealtimeItem> items;
    bool degraded() const noexcept;  ///< at least one request denied
    std::string format() const;      ///< one line per item, then "real time: full|DEGRADED"
};

/// Applies `settings` to the calling thread (and mlockall to the process).
RealtimeReport apply_realtime(const config::RealtimeSettings& settings);

/// Keeps freed heap memory in the process (glibc: one arena for all threads, mmap threshold
/// 32 MiB, no trimming), so a collision update after a cut, on the world builder's thread,
/// reuses pages already faulted in (and locked by mlockall) by the first build on the main
/// thread instead of faulting fresh ones. Call once at start, before any other thread; returns
/// what it set.
RealtimeItem keep_freed_memory();

}  // namespace kerf::rt
