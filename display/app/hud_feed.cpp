#include "display/app/hud_feed.hpp"

namespace kerf::display {

void HapticRate::add(std::uint64_t tick, std::uint64_t tick_time_ns,
                     std::uint64_t now_ns) noexcept {
    if (!anchored_ || tick < last_tick_ || tick_time_ns < anchor_ns_) {
        anchor_tick_ = last_tick_ = tick;
        anchor_ns_ = tick_time_ns;
        last_change_ns_ = now_ns;
        anchored_ = true;
        hz_ = -1;
        return;
    }
    if (tick != last_tick_) {
        last_tick_ = tick;
        last_change_ns_ = now_ns;
    } else if (now_ns - last_change_ns_ >= kWindow_ns) {
        hz_ = 0;  // kerf-rt's loop has not ticked for a whole window
        return;
    }
    if (tick_time_ns - anchor_ns_ >= kWindow_ns) {
        hz_ = double(tick - anchor_tick_) * 1e9 / double(tick_time_ns - anchor_ns_);
        anchor_tick_ = tick;
        anchor_ns_ = tick_time_ns;
    }
}

render::HudState make_hud(const FollowerStatus& s, const render::FrameStats& frames,
                          const HapticRate& rate, std::uint64_t triangles,
                          std::string_view backend) {
    render::HudState hud;
    hud.fps = frames.fps();
    hud.frame_p99_ms = frames.percentile_ms(0.99);
    hud.haptic_rate_hz = s.attached ? rate.hz() : -1;
    hud.haptic_overruns = s.state_valid ? s.state.overrun_count : 0;
    hud.wake_latency_us = s.state_valid ? s.state.period_ns_max * 1e-3 : -1;
    hud.device_state = s.attached ? "attached" : "waiting for kerf-rt";
    hud.cut_state = s.cut_open ? "cutting" : s.session.cuts_completed ? "severed" : "idle";
    hud.cut_depth_mm = s.cut_depth_m >= 0 ? s.cut_depth_m * 1e3 : -1;
    hud.event_backlog = s.backlog;
    hud.triangles = triangles;
    hud.backend = backend;
    return hud;
}

}  // namespace kerf::display
