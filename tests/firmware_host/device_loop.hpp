// A test-sized version of the 1 kHz tick: read device -> safety -> write device.
#pragma once

#include <cmath>
#include <memory>

#include "firmware_host/device/device.hpp"
#include "firmware_host/safety/force_safety.hpp"

namespace kerf::firmware_host::test {

inline SafetyLimits loop_limits() {
    SafetyLimits l;
    l.peak_force_n = 8.0;
    l.continuous_force_n = 4.0;
    l.ramp_in_s = 0.02;
    l.engage_quiet_ticks = 10;
    l.stale_ticks = 2;
    return l;
}

struct DeviceLoop {
    /// Lockstep emulators answer host packets: the first command primes the exchange.
    explicit DeviceLoop(Device& d) : device(&d), safety(loop_limits()) {
        write_status = device->try_write(DeviceCommand{});
    }

    /// One tick; `timeout_us` bounds the read (lockstep: the emulator answers our last write).
    void tick(std::uint32_t timeout_us = 20000) noexcept {
        read_and_decide(timeout_us);
        write();
    }
    /// First half of a tick: read the device and run the safety layer.
    void read_and_decide(std::uint32_t timeout_us = 20000) noexcept {
        status = device->try_read(sample, timeout_us);
        SafetyInput in;
        in.desired_force_n = desired;
        in.read_status = status;
        in.flags = sample.flags;
        out = safety.step(in);
    }
    /// Second half: send the command.
    void write() noexcept {
        write_status = device->try_write(DeviceCommand{out, safety.engaged(), 0});
    }
    double force() const { return std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]); }

    Device* device;
    ForceSafety safety;
    DeviceSample sample;
    DeviceStatus status = DeviceStatus::kNoData;
    DeviceStatus write_status = DeviceStatus::kOk;
    Vec3d desired{};
    Vec3d out{};
};

}  // namespace kerf::firmware_host::test
