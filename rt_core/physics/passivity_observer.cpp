// Hannaford-Ryu passivity observer / controller (passivity_observer.hpp).
#include "rt_core/physics/passivity_observer.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::physics {

void PassivityObserver::reset() noexcept {
    flow_j_.fill(0);
    head_ = count_ = 0;
    energy_j_ = 0;
    total_dissipated_j_ = 0;
}

PassivityOutput PassivityObserver::step(const Vec3& force_n, const Vec3& velocity_m_s,
                                        double dt_s) noexcept {
    PassivityOutput out;
    out.force_n = force_n;
    if (!params_.enabled || !(dt_s > 0) || !is_finite(force_n) || !is_finite(velocity_m_s)) {
        return out;
    }
    // Energy into the environment this tick: the device pushes with -F_env while moving at v.
    double flow = -dot(force_n, velocity_m_s) * dt_s;
    const double v2 = norm2(velocity_m_s);
    const double budget = energy_j_ + flow;
    if (budget < 0 && v2 > 0) {
        const double alpha = std::min(-budget / (v2 * dt_s), params_.max_damping_n_s_per_m);
        out.force_n -= velocity_m_s * alpha;
        out.damping_n_s_per_m = alpha;
        out.dissipated_j = alpha * v2 * dt_s;
        flow += out.dissipated_j;
        total_dissipated_j_ += out.dissipated_j;
    }
    // Sliding horizon: forget the flow of the tick that leaves the window.
    const auto window = static_cast<std::uint32_t>(
        std::clamp(params_.window_s / dt_s, 1.0, static_cast<double>(kMaxWindow)));
    while (count_ >= window) {
        const std::uint32_t tail = (head_ + kMaxWindow - count_) % kMaxWindow;
        energy_j_ -= flow_j_[tail];
        --count_;
    }
    flow_j_[head_] = flow;
    head_ = (head_ + 1) % kMaxWindow;
    ++count_;
    energy_j_ += flow;
    out.observed_j = energy_j_;
    return out;
}

}  // namespace kerf::physics
