// Simulation — the device model, the scripted hand and the faults, advanced in fixed periods.
// Both protocol sides step it; it records a per-step trace (ground truth for tests).
#pragma once

#include <cstdint>
#include <cstdio>
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

    /// Streams the per-step trace (CSV) to `path` from now on: the file is created here, so an
    /// unwritable path fails at start (false, `why` says what); rows go out as they are made
    /// (nothing accumulates in memory) until the file holds `max_bytes`, then it stops and says so.
    bool open_trace(const std::filesystem::path& path, std::uint64_t max_bytes, std::string& why);
    /// Flushes and closes the trace; false (and `why`) if a write failed or the cap was reached.
    bool close_trace(std::string& why);
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

private:
    DeviceModel model_;
    HandPlayer hand_;
    Faults faults_;
    double period_s_;
    std::uint64_t steps_ = 0;
    void write_trace_row(const TraceRow& row);
    std::FILE* trace_ = nullptr;
    std::filesystem::path trace_path_;
    std::uint64_t trace_bytes_ = 0, trace_max_bytes_ = 0;
    bool trace_full_ = false, trace_failed_ = false;
    std::vector<FaultEvent> events_;
    std::vector<std::string> warnings_;
};

}  // namespace kerf::hapsim
