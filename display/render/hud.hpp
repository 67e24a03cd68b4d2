// kerf::render HUD — what the display shows over the bone: frame rate and frame-time p99, the
// haptic loop's health (rate, overruns, wake latency), device state, cut state and depth, and the
// event backlog. HudState is plain data the display fills each frame; format_hud() turns it into
// the text lines the Renderer draws with stb_easy_font (libstb-dev). FrameStats measures frames.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace kerf::render {

/// One frame's HUD content. NaN / negative numbers print as "-" (not known yet).
struct HudState {
    double fps = -1;                    ///< frames per second over the last window
    double frame_p99_ms = -1;           ///< 99th percentile frame time over the last window, ms
    double haptic_rate_hz = -1;         ///< kerf-rt loop rate, Hz
    std::uint64_t haptic_overruns = 0;  ///< ticks over budget so far
    double wake_latency_us = -1;        ///< kerf-rt wake-up latency (worst in the last second), us
    std::string_view device_state = "-";  ///< e.g. "connected", "faulted"
    std::string_view cut_state = "idle";  ///< e.g. "idle", "cutting", "severed"
    double cut_depth_mm = -1;             ///< feed depth of the current cut, mm
    std::uint64_t event_backlog = 0;      ///< events journalled but not yet applied
    std::uint64_t triangles = 0;          ///< triangles drawn
    std::string_view backend = "";        ///< e.g. "headless: llvmpipe ...", on a line of its own
};

/// The HUD as text, one line per '\n'-separated item (what draw_hud() draws).
std::string format_hud(const HudState& hud);

/// Frame times of the last kWindow frames in a fixed ring (no allocation per frame).
class FrameStats {
public:
    static constexpr int kWindow = 256;
    /// Records one frame's duration, seconds.
    void add(double frame_s) noexcept;
    /// Frames per second over the window (count / sum), or -1 with no frame yet.
    double fps() const noexcept;
    /// Percentile `p` in [0, 1] of the window's frame times, ms (sorts a copy: O(kWindow)).
    double percentile_ms(double p) const noexcept;
    int count() const noexcept { return count_; }

private:
    std::array<double, kWindow> ring_{};
    int next_ = 0;
    int count_ = 0;
};

}  // namespace kerf::render
