// kerf::physics::PassivityObserver — Hannaford-Ryu passivity observer and controller, with the
// environment's stored energy as its reserve.
//
// The observer integrates the energy that actually flowed into the virtual environment at the
// device port: over the last tick the device held the previous output force F while moving at the
// velocity v measured now, so E += -F_prev . v dt (the zero-order hold and the tick of delay are
// where a sampled stiff wall makes energy, so they must be in the sum). A passive environment can
// give back at most what it still stores (the contact spring's 1/2 k d^2, which the caller passes):
// the budget E - stored is what it has dissipated so far and must stay >= 0. When it goes below
// -dead_band_j the environment has produced energy: the controller adds a damper
// alpha = (-budget - dead_band) / (|v|^2 dt)
// (capped at max_damping_n_s_per_m) along the velocity, which removes the excess over the next
// tick (observed there), and reports the energy it expects to remove (telemetry). The budget leaks
// towards 0 (leak_time_s): a stiff wall's rebound makes its deficit within milliseconds, while
// encoder quantisation at rest makes a trickle that must not trigger damping (it would itself
// buzz: each velocity spike would meet the full damper). Counting the
// stored energy lets it act during the rebound off a stiff wall, not only after the device has
// left. When the environment is relaxed (no force, nothing stored) the sum restarts at 0, so
// surplus from an earlier contact never hides a later one. noexcept, fixed state, no allocation.
#pragma once

#include "rt_core/physics/vec3.hpp"

namespace kerf::physics {

struct PassivityParams {
    bool enabled = true;
    double max_damping_n_s_per_m = 20;  ///< cap on the added damper (the device's stable range)
    double dead_band_j = 2e-5;  ///< act only on a deficit beyond this: encoder quantisation makes
                                ///< velocity spikes whose apparent energy must not be damped
    double leak_time_s = 0.1;   ///< the budget relaxes towards 0 with this time constant, so slow
                                ///< drifts (quantisation at rest) never add up to a deficit
};

/// What the controller did this tick.
struct PassivityOutput {
    Vec3 force_n;                  ///< the corrected force on the device, N
    double damping_n_s_per_m = 0;  ///< damper added this tick
    double dissipated_j = 0;       ///< energy the damper removes over the next tick, J (>= 0)
    double budget_j = 0;           ///< observed energy minus stored energy, J (< 0: was active)
};

class PassivityObserver {
public:
    explicit PassivityObserver(const PassivityParams& params = {}) noexcept : params_(params) {}

    void set_params(const PassivityParams& params) noexcept { params_ = params; }
    /// Forgets the observed energy (e.g. when forces are re-engaged). noexcept.
    void reset() noexcept;
    /// Observes one tick: `force_n` is this tick's environment force on the device, `velocity`
    /// the device velocity measured now, `stored_j` the energy the environment stores now (J).
    /// Returns the corrected force. noexcept.
    PassivityOutput step(const Vec3& force_n, const Vec3& velocity_m_s, double stored_j,
                         double dt_s) noexcept;

    /// Energy removed since construction or reset(), J.
    double total_dissipated_j() const noexcept { return total_dissipated_j_; }

private:
    PassivityParams params_;
    double energy_j_ = 0;    ///< energy into the environment since it was last relaxed, J
    Vec3 previous_force_n_;  ///< output of the previous tick (held by the device since)
    double total_dissipated_j_ = 0;
};

}  // namespace kerf::physics
