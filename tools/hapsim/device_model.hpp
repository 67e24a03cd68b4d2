// The emulated mechanism: a Cartesian end effector with per-axis inertia, viscous and Coulomb
// friction, motor force limits, workspace end stops, and the hand holding it through a
// spring-damper (hand impedance), so forces the host commands push back against the hand.
#pragma once

#include <array>

#include "firmware_host/vec3.hpp"

namespace kerf::hapsim {

using firmware_host::Vec3;  ///< the device side's one 3-vector (firmware_host/vec3.hpp)

struct ModelParams {
    Vec3 mass_kg = {0.15, 0.15, 0.15};         ///< per-axis effective inertia
    Vec3 viscous_n_s_per_m = {0.8, 0.8, 0.8};  ///< per-axis viscous friction
    Vec3 coulomb_n = {0.02, 0.02, 0.02};       ///< per-axis dry friction
    double motor_limit_n = 10.0;               ///< |motor force| per axis
    double hand_stiffness_n_per_m = 800.0;
    double hand_damping_n_s_per_m = 8.0;
    double wall_stiffness_n_per_m = 5000.0;  ///< end stops at the workspace box
    Vec3 workspace_min_m = {-0.08, -0.08, -0.08};
    Vec3 workspace_max_m = {0.08, 0.08, 0.08};
    int substeps = 4;  ///< integration steps per device period
};

class DeviceModel {
public:
    explicit DeviceModel(const ModelParams& params) noexcept : p_(params) {}

    void reset(const Vec3& position_m) noexcept;
    /// Advances `dt_s` under the motor force (saturated per axis) and the hand at `hand_m`.
    void step(double dt_s, const Vec3& motor_force_n, const Vec3& hand_m,
              const Vec3& hand_m_per_s) noexcept;

    const Vec3& position_m() const noexcept { return x_; }
    const Vec3& velocity_m_per_s() const noexcept { return v_; }
    const Vec3& applied_force_n() const noexcept { return applied_; }  ///< after motor limits
    const ModelParams& params() const noexcept { return p_; }

private:
    ModelParams p_;
    Vec3 x_{}, v_{}, applied_{};
};

}  // namespace kerf::hapsim
