// An in-process device for closed-loop tests of the loop: the emulator's own mechanism model and
// scripted hand (kerf_hapsim_core's Simulation: inertia, friction, motor limits, the hand's
// spring-damper), stepped one period per command like a lockstep kerf-hapsim, with the Kerf HID
// side's 10 um encoder quantisation. No socket and no process: a whole soak round's hand script
// runs in seconds and bit for bit the same on every run. Transient faults are injected per tick
// (a read that finds no new sample: the "stale" a loaded emulator produces).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "firmware_host/device/device.hpp"
#include "tools/hapsim/simulation.hpp"

namespace kerf::rt::test {

class SimHandDevice final : public firmware_host::Device {
public:
    /// `script_text`: a kerf-hapsim hand script; the hand starts at the device origin.
    static std::unique_ptr<SimHandDevice> create(const std::string& script_text,
                                                 std::string& error) {
        auto script = hapsim::parse_hand_script(script_text, "script");
        if (!script) {
            error = script.error().message();
            return nullptr;
        }
        hapsim::ModelParams model;
        model.motor_limit_n = 10.0;  // config/devices/simulated.toml peak_force_n
        return std::unique_ptr<SimHandDevice>(new SimHandDevice(model, std::move(*script)));
    }

    /// The next `ticks` reads find no new sample (the device is still stepped by each command).
    void drop_reads(std::uint32_t ticks) noexcept { drop_ = ticks; }

    firmware_host::DeviceStatus try_read(firmware_host::DeviceSample& out,
                                         std::uint32_t) noexcept override {
        if (drop_ > 0) {
            --drop_;
            return firmware_host::DeviceStatus::kNoData;
        }
        const auto& x = sim_.model().position_m();
        const auto& v = sim_.model().velocity_m_per_s();
        out.count = ++count_;
        for (int i = 0; i < 3; ++i) {
            out.position_m[i] = std::round(x[i] / 1e-5) * 1e-5;
            out.velocity_m_per_s[i] = v[i];
        }
        out.buttons = sim_.hand().buttons();
        out.flags.homed = true;
        out.flags.amplifiers_on = true;
        ++counters_.samples;
        return firmware_host::DeviceStatus::kOk;
    }

    firmware_host::DeviceStatus try_write(const firmware_host::DeviceCommand& c) noexcept override {
        const hapsim::Vec3 f = c.enable ? hapsim::Vec3{c.force_n[0], c.force_n[1], c.force_n[2]}
                                        : hapsim::Vec3{0, 0, 0};
        sim_.step(f);
        return firmware_host::DeviceStatus::kOk;
    }

    const firmware_host::DeviceCounters& counters() const noexcept override { return counters_; }
    hapsim::Simulation& sim() noexcept { return sim_; }

private:
    SimHandDevice(const hapsim::ModelParams& model, hapsim::HandScript script)
        : sim_(model, std::move(script), {0, 0, 0}, 1e-3) {}
    hapsim::Simulation sim_;
    firmware_host::DeviceCounters counters_;
    std::uint64_t count_ = 0;
    std::uint32_t drop_ = 0;
};

}  // namespace kerf::rt::test
