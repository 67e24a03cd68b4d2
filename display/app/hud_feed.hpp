// Where the HUD's numbers come from (render::HudState is plain data; this fills it):
//   display  fps and frame p99        the frame loop's own FrameStats
//   haptics  rate (Hz)                HapticRate: kerf-rt's loop tick counter and its stamp in
//                                     the LatestState seqlock, differenced over >= 0.5 s
//            overruns, wake           LatestState (overrun_count, period_ns_max)
//   cut      state, depth (mm)        the follower: the open cut, cuts completed, and the blade's
//                                     feed depth as kerf-rt reported it in the newest cut event
//            backlog                  events published by kerf-rt and not applied yet
#pragma once

#include <cstdint>
#include <string_view>

#include "display/app/session_follower.hpp"
#include "display/render/hud.hpp"

namespace kerf::display {

/// The haptic loop's rate from its (tick, tick time) pairs as the display samples them.
class HapticRate {
public:
    /// Shortest span a rate is measured over, ns (the loop's 1 kHz gives >= 500 ticks).
    static constexpr std::uint64_t kWindow_ns = 500'000'000;
    /// Takes the newest LatestState (tick, time_ns) seen at the display's `now_ns`
    /// (CLOCK_MONOTONIC, same clock as kerf-rt's stamps). A tick that goes back (a new session)
    /// starts over; a tick that stays put for kWindow_ns of `now_ns` reads as 0 Hz (stalled).
    void add(std::uint64_t tick, std::uint64_t tick_time_ns, std::uint64_t now_ns) noexcept;
    /// Ticks per second over the last full window, or -1 before one.
    double hz() const noexcept { return hz_; }

private:
    std::uint64_t anchor_tick_ = 0, anchor_ns_ = 0;  ///< start of the window being measured
    std::uint64_t last_tick_ = 0, last_change_ns_ = 0;
    bool anchored_ = false;
    double hz_ = -1;
};

/// The HUD for one frame from the follower's status and the frame loop's measures.
render::HudState make_hud(const FollowerStatus& status, const render::FrameStats& frames,
                          const HapticRate& rate, std::uint64_t triangles,
                          std::string_view backend);

}  // namespace kerf::display
