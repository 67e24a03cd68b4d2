// The HUD's sources: kerf-rt's loop rate from its tick counter, the cut depth from the cut events,
// and the text the display draws (what format_hud() gives for them).
#include "display/app/hud_feed.hpp"

#include <gtest/gtest.h>

namespace kerf::display {
namespace {

constexpr std::uint64_t kMs = 1'000'000;

TEST(HapticRate, MeasuresTicksPerSecondOverHalfASecondAndStartsOverOnANewSession) {
    HapticRate rate;
    EXPECT_LT(rate.hz(), 0.0) << "unknown before a window";
    // A 1 kHz loop sampled by a display at ~30 fps (every 33 ms): ticks 33 apart.
    std::uint64_t tick = 5000, t = 10'000 * kMs;
    for (int frame = 0; frame < 20; ++frame, tick += 33, t += 33 * kMs) rate.add(tick, t, t);
    EXPECT_NEAR(rate.hz(), 1000.0, 1e-6);
    // A loop that skips deadlines (a 2 ms period) shows half the rate after the next window.
    for (int frame = 0; frame < 40; ++frame, tick += 16, t += 32 * kMs) rate.add(tick, t, t);
    EXPECT_NEAR(rate.hz(), 500.0, 1e-6);
    // kerf-rt restarted: its tick counter starts again; the rate is unknown until a window.
    rate.add(10, t, t);
    EXPECT_LT(rate.hz(), 0.0);
}

TEST(HapticRate, ALoopThatStopsTickingReadsZero) {
    HapticRate rate;
    std::uint64_t t = 1'000 * kMs;
    for (std::uint64_t tick = 1; tick < 700; tick += 10, t += 10 * kMs) rate.add(tick, t, t);
    EXPECT_GT(rate.hz(), 900.0);
    const std::uint64_t stalled_at = t;
    for (int frame = 0; frame < 30; ++frame) rate.add(700, stalled_at, t += 33 * kMs);
    EXPECT_EQ(rate.hz(), 0.0);
}

TEST(HudFeed, TheHudTextShowsTheHapticRateAndTheCutDepthFromTheirSources) {
    FollowerStatus s;
    s.attached = true;
    s.state_valid = true;
    s.state.overrun_count = 3;
    s.state.period_ns_max = 1'250'000;
    s.cut_open = true;
    s.cut_depth_m = 0.0125;  // from the newest CutProgress
    s.backlog = 2;
    HapticRate rate;
    for (std::uint64_t k = 0; k <= 20; ++k) rate.add(k * 50, k * 50 * kMs, k * 50 * kMs);
    render::FrameStats frames;
    for (int i = 0; i < 10; ++i) frames.add(0.040);
    const std::string text = render::format_hud(make_hud(s, frames, rate, 999'666, "headless"));
    EXPECT_EQ(text,
              "display  25.0 fps   p99 40.0 ms   999666 tris\n"
              "haptics  1000 Hz   overruns 3   wake 1250 us   device attached\n"
              "cut      cutting   depth 12.5 mm   backlog 2 events\n"
              "headless");
    // Not attached, no cut yet: dashes, not stale numbers.
    s.attached = false;
    s.cut_open = false;
    s.cut_depth_m = -1;
    const std::string waiting = render::format_hud(make_hud(s, frames, rate, 0, ""));
    EXPECT_NE(waiting.find("haptics  - Hz"), std::string::npos) << waiting;
    EXPECT_NE(waiting.find("idle   depth - mm"), std::string::npos) << waiting;
}

}  // namespace
}  // namespace kerf::display
