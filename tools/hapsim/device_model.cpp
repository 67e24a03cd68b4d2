#include "tools/hapsim/device_model.hpp"

#include <algorithm>
#include <cmath>

namespace kerf::hapsim {

void DeviceModel::reset(const Vec3& position_m) noexcept {
    x_ = position_m;
    v_ = {};
    applied_ = {};
}

void DeviceModel::step(double dt_s, const Vec3& motor_force_n, const Vec3& hand_m,
                       const Vec3& hand_m_per_s) noexcept {
    const int n = std::max(1, p_.substeps);
    const double h = dt_s / n;
    for (int axis = 0; axis < 3; ++axis) {
        const double f = std::isfinite(motor_force_n[axis]) ? motor_force_n[axis] : 0.0;
        applied_[axis] = std::clamp(f, -p_.motor_limit_n, p_.motor_limit_n);
    }
    for (int s = 0; s < n; ++s) {
        for (int axis = 0; axis < 3; ++axis) {
            double f = applied_[axis];
            f += p_.hand_stiffness_n_per_m * (hand_m[axis] - x_[axis]) +
                 p_.hand_damping_n_s_per_m * (hand_m_per_s[axis] - v_[axis]);
            f -= p_.viscous_n_s_per_m[axis] * v_[axis];
            if (x_[axis] < p_.workspace_min_m[axis])
                f += p_.wall_stiffness_n_per_m * (p_.workspace_min_m[axis] - x_[axis]);
            if (x_[axis] > p_.workspace_max_m[axis])
                f -= p_.wall_stiffness_n_per_m * (x_[axis] - p_.workspace_max_m[axis]);
            // Coulomb friction opposes motion; at rest it holds up to its limit (stick).
            const double c = p_.coulomb_n[axis];
            if (std::abs(v_[axis]) > 1e-6) {
                f -= std::copysign(c, v_[axis]);
            } else if (std::abs(f) <= c) {
                f = 0;
            } else {
                f -= std::copysign(c, f);
            }
            v_[axis] += h * f / p_.mass_kg[axis];  // semi-implicit Euler
            x_[axis] += h * v_[axis];
        }
    }
}

}  // namespace kerf::hapsim
