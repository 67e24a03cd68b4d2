// Hannaford-Ryu passivity observer / controller (passivity_observer.hpp).
#include "rt_core/physics/passivity_observer.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::physics {

void PassivityObserver::reset() noexcept {
    energy_j_ = 0;
    previous_force_n_ = {};
    total_dissipated_j_ = 0;
}

PassivityOutput PassivityObserver::step(const Vec3& force_n, const Vec3& velocity_m_s,
                                        double stored_j, double dt_s) noexcept {
    PassivityOutput out;
    out.force_n = force_n;
    if (!params_.enabled || !(dt_s > 0) || !is_finite(force_n) || !is_finite(velocity_m_s) ||
        !std::isfinite(stored_j)) {
        previous_force_n_ = out.force_n;
        return out;
    }
    // Energy into the environment over the last tick: the device held the previous force.
    energy_j_ += -dot(previous_force_n_, velocity_m_s) * dt_s;
    const double v2 = norm2(velocity_m_s);
    const double stored = std::max(stored_j, 0.0);
    if (params_.leak_time_s > 0) {  // budget -> 0: energy -> stored
        energy_j_ = stored + (energy_j_ - stored) * std::exp(-dt_s / params_.leak_time_s);
    }
    out.budget_j = energy_j_ - stored;
    const double deficit = -out.budget_j - std::max(params_.dead_band_j, 0.0);
    if (deficit > 0 && v2 > 0) {
        const double alpha = std::min(deficit / (v2 * dt_s), params_.max_damping_n_s_per_m);
        out.force_n -= velocity_m_s * alpha;
        out.damping_n_s_per_m = alpha;
        out.dissipated_j = alpha * v2 * dt_s;
        total_dissipated_j_ += out.dissipated_j;
    }
    if (norm2(force_n) == 0 && stored_j <= 0) energy_j_ = 0;  // relaxed: start afresh
    previous_force_n_ = out.force_n;
    return out;
}

}  // namespace kerf::physics
