// Simulation — the device model, the scripted hand and the faults, advanced in fixed periods.
// Both protocol sides step it; it records a per-step trace (ground truth for tests).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/hapsim/device_model.hpp"
#include "tools/hapsim/faults.hpp"
#include "tools/hapsim/hand_script.hpp"

namespace kerf::hapsim {

struct TraceRow {
    std::uint64_t step = 0;
    Vec3 position_m{};
    Vec3 hand_m{};
    Vec3 motor_force_n{};
};

class Simulation {
public:
    Simulation(const ModelParams& params, HandScript script, const Vec3& start_m, double period_s);

    /// One device period under `motor_force_n` (Cartesian, N). Fires scripted fault events.
    void step(const Vec3& motor_force_n);

    DeviceModel& model() noexcept { return model_; }
    const HandPlayer& hand() const noexcept { return hand_; }
    Faults& faults() noexcept { return faults_; }
    std::uint64_t steps() const noexcept { return steps_; }
    double time_s() const noexcept { return steps_ * period_s_; }
    double period_s() const noexcept { return period_s_; }
    /// Messages about scripted faults that were refused (shown once by main).
    std::vector<std::string>& warnings() noexcept { return warnings_; }

    void enable_trace(bool on) { trace_on_ = on; }
    bool write_trace(const std::filesystem::path& path, std::string& why) const;

private:
    DeviceModel model_;
    HandPlayer hand_;
    Faults faults_;
    double period_s_;
    std::uint64_t steps_ = 0;
    bool trace_on_ = false;
    std::vector<TraceRow> trace_;
    std::vector<FaultEvent> events_;
    std::vector<std::string> warnings_;
};

}  // namespace kerf::hapsim
