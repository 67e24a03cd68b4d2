// One round of `kerf soak`: a fresh session on one scene (the built-in foot with its own seed, or
// a mesh from the shared folder) — kerf-hapsim playing a random cutting script (soak_plan.*),
// kerf-rt, kerf-display headless under the supervisor — with faults injected on a schedule while
// the hand cuts, the soak monitor collecting telemetry and events, and resident memory sampled
// once a second. After the script: the display catches up, kerf-rt is stopped, and the round's
// checks run (soak_checks.*), the journal replayed through kerf_cut for the hash.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "config/base/result.hpp"
#include "tools/kerf/soak_checks.hpp"
#include "tools/kerf/soak_plan.hpp"

namespace kerf::cli {

/// 100 ms of telemetry for the plots: peaks, and the flags seen in it.
struct PlotBin {
    std::uint64_t time_ns = 0;         ///< CLOCK_MONOTONIC of the bin's start
    float force_n = 0;                 ///< peak |commanded force|, N
    float penetration_live_m = 0;      ///< peak penetration of ticks whose force reached the hand
    float penetration_no_force_m = 0;  ///< ... of ticks whose force could not (force_reaches_hand)
    std::uint32_t safety_reasons = 0;  ///< every SafetyReason bit seen in the bin
    std::uint32_t loop_flags = 0;      ///< every kLoopFlag* bit seen
    std::uint32_t contact_flags = 0;   ///< every kContact* bit seen
};

/// What a round runs on and for how long.
struct RoundSpec {
    int index = 0;
    std::string scene;               ///< "builtin_foot" or a mesh file's path
    std::size_t triangles = 50'000;  ///< built-in foot only
    std::uint64_t seed = 1;
    double duration_s = 60;  ///< the hand script's length (a little more)
    std::vector<SoakFault> faults;
    int device_rotation = 0;       ///< where this round starts in the device faults (rounds share)
    int host_rotation = 0;         ///< ... and in the display and segment faults
    std::filesystem::path config;  ///< kerf.toml to start from
    std::filesystem::path work;    ///< the round's temporary folder (removed by the caller)
    double display_rss_limit_mb = 1024;
    double rt_growth_limit_pct = 1;  ///< kerf-rt's RssAnon growth allowed after warm-up
};

/// An injected fault, for the plots and the report (seconds since the round started).
struct InjectedFault {
    SoakFault fault = SoakFault::kDrop;
    double on_s = 0, off_s = 0;
    std::string note;  ///< e.g. "scribbles 1987", "restarted after 2.1 s"
};

/// A sample of resident memory (seconds since the round started).
struct MemoryPoint {
    double t_s = 0;
    double rt_mb = -1, display_mb = -1;  ///< VmRSS; -1: not running
    /// kerf-rt's VmRSS split: RssAnon (its heap and private maps), RssShmem (the session
    /// segment), RssFile (its executable, libraries and mapped files); -1: not running.
    double rt_anon_mb = -1, rt_shmem_mb = -1, rt_file_mb = -1;
};

struct RoundResult {
    RoundSpec spec;
    std::string scene_name;
    double wall_s = 0;
    std::vector<PlannedCut> cuts;
    std::vector<InjectedFault> injected;
    std::vector<FaultVerdict> device_faults;
    ForceVerdict force;
    SequenceVerdict monitor_events;  ///< the soak monitor's delivered events vs the journal
    std::uint64_t journal_events = 0, display_next_sequence = 0, display_lost = 0;
    std::uint64_t display_rejected = 0, monitor_rejected = 0;
    std::uint64_t cut_begins = 0, cuts_completed = 0, refused = 0;
    std::string display_hash, replay_hash;
    int display_restarts = 0, display_kills = 0;
    /// kerf-rt's RssAnon (the checked one: what kerf-rt itself allocates) and kerf-display's VmRSS.
    MemoryVerdict rt_memory, display_memory;
    /// kerf-rt's VmRSS, RssShmem and RssFile, reported beside the check.
    MemoryVerdict rt_rss_memory, rt_shmem_memory, rt_file_memory;
    double display_peak_mb = 0;
    std::uint64_t telemetry_samples = 0, telemetry_gaps = 0;
    std::vector<PlotBin> plot_ticks;  ///< decimated (peaks per 100 ms) for the plots
    std::vector<MemoryPoint> memory;
    // kerf-rt's own summary.
    double ticks = 0, overruns = 0, late_wakes = 0, safe_state_entries = 0;
    double wake_p50_us = -1, wake_p99_us = -1, wake_p999_us = -1, wake_max_us = -1;
    std::map<double, std::uint64_t> wake_histogram;  ///< bin upper edge us -> count
    std::vector<std::string> failures;  ///< one line per violated check (empty: passed)
    /// Files worth keeping (name, contents): logs, hand script, journal, display status.
    std::vector<std::pair<std::string, std::string>> keep;
};

/// Runs the round; an Err only when it could not run at all (a missing executable, a bad
/// scene); check failures are in RoundResult::failures.
Result<RoundResult, std::string> run_round(const RoundSpec& spec, bool quiet);

}  // namespace kerf::cli
