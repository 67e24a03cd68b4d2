#include "display/render/hud.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kerf::render {

namespace {

// `v` with `decimals` decimals, or "-" when not known (negative or not finite).
std::string number(double v, int decimals) {
    if (!std::isfinite(v) || v < 0) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

}  // namespace

std::string format_hud(const HudState& h) {
    std::string s;
    s += "display  " + number(h.fps, 1) + " fps   p99 " + number(h.frame_p99_ms, 1) + " ms   " +
         std::to_string(h.triangles) + " tris";
    s += "\nhaptics  " + number(h.haptic_rate_hz, 0) + " Hz   overruns " +
         std::to_string(h.haptic_overruns) + "   wake " + number(h.wake_latency_us, 0) +
         " us   device " + std::string(h.device_state);
    s += "\ncut      " + std::string(h.cut_state) + "   depth " + number(h.cut_depth_mm, 1) +
         " mm   backlog " + std::to_string(h.event_backlog) + " events";
    if (!h.backend.empty()) s += "\n" + std::string(h.backend);
    return s;
}

void FrameStats::add(double frame_s) noexcept {
    if (!std::isfinite(frame_s) || frame_s < 0) return;
    ring_[static_cast<std::size_t>(next_)] = frame_s;
    next_ = (next_ + 1) % kWindow;
    count_ = std::min(count_ + 1, kWindow);
}

double FrameStats::fps() const noexcept {
    if (count_ == 0) return -1;
    double sum = 0;
    for (int i = 0; i < count_; ++i) sum += ring_[static_cast<std::size_t>(i)];
    return sum > 0 ? count_ / sum : -1;
}

double FrameStats::percentile_ms(double p) const noexcept {
    if (count_ == 0) return -1;
    std::array<double, kWindow> sorted = ring_;
    std::sort(sorted.begin(), sorted.begin() + count_);
    const double rank = std::clamp(p, 0.0, 1.0) * (count_ - 1);
    return sorted[static_cast<std::size_t>(std::lround(rank))] * 1e3;
}

}  // namespace kerf::render
