// kerf::physics::PassivityObserver — Hannaford-Ryu passivity observer and controller.
//
// The observer integrates the energy flowing into the virtual environment at the device port,
// E += -F_env . v dt (F_env: force the environment applies to the device, v: device velocity),
// over a sliding horizon (energy older than `window_s` is forgotten: without it, energy stored
// during a long passive contact would hide later activity). When E < 0 the environment has
// produced energy; the controller adds a damper alpha = -E / (|v|^2 dt) (capped at
// max_damping_n_s_per_m) along the velocity to dissipate exactly that excess, and counts the
// energy it removed (telemetry). noexcept, fixed-size state, no allocation.
#pragma once

#include <array>
#include <cstdint>

#include "rt_core/physics/vec3.hpp"

namespace kerf::physics {

struct PassivityParams {
    bool enabled = true;
    double max_damping_n_s_per_m = 20;  ///< cap on the added damper (device stability bound)
    double window_s = 0.256;            ///< energy horizon; window_s / dt ticks are kept (<= 1024)
};

/// What the controller did this tick.
struct PassivityOutput {
    Vec3 force_n;                  ///< the corrected force on the device, N
    double damping_n_s_per_m = 0;  ///< damper added this tick
    double dissipated_j = 0;       ///< energy removed this tick, J (>= 0)
    double observed_j = 0;         ///< observed environment energy after correction, J
};

class PassivityObserver {
public:
    explicit PassivityObserver(const PassivityParams& params = {}) noexcept : params_(params) {}

    void set_params(const PassivityParams& params) noexcept { params_ = params; }
    /// Forgets the observed energy (e.g. when forces are re-engaged). noexcept.
    void reset() noexcept;
    /// Observes F_env and v for one tick of dt and returns the corrected force. noexcept.
    PassivityOutput step(const Vec3& force_n, const Vec3& velocity_m_s, double dt_s) noexcept;

    /// Energy removed since construction or reset(), J.
    double total_dissipated_j() const noexcept { return total_dissipated_j_; }

private:
    static constexpr std::uint32_t kMaxWindow = 1024;
    PassivityParams params_;
    std::array<double, kMaxWindow> flow_j_{};  ///< per-tick energy flow, ring
    std::uint32_t head_ = 0, count_ = 0;
    double energy_j_ = 0;  ///< sum of flow_j_ over the window
    double total_dissipated_j_ = 0;
};

}  // namespace kerf::physics
