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
        decide();
    }
    /// The safety layer's step on the last read.
    void decide() noexcept {
        SafetyInput in;
        in.desired_force_n = desired;
        in.read_status = status;
        in.flags = sample.flags;
        out = safety.step(in);
    }
    /// Lockstep tick for tests whose point is correctness (sample i is the answer to packet i):
    /// a read that times out because the emulator was descheduled on a loaded machine is waited
    /// for (and counted in `late_reads`), never taken as a lost sample. Only for emulators that
    /// answer every packet: gives up after `max_wait_us` in all.
    void tick_lockstep(std::uint32_t max_wait_us = 30'000'000) noexcept {
        read_lockstep(max_wait_us);
        write();
    }
    /// First half of a lockstep tick: read (waiting out late answers), run the safety layer.
    void read_lockstep(std::uint32_t max_wait_us = 30'000'000) noexcept {
        constexpr std::uint32_t kSliceUs = 20000;
        status = device->try_read(sample, kSliceUs);
        for (std::uint32_t waited = kSliceUs;
             status == DeviceStatus::kNoData && waited < max_wait_us; waited += kSliceUs) {
            ++late_reads;
            status = device->try_read(sample, kSliceUs);
        }
        decide();
    }
    /// Reads every answer already queued (a stalled tick leaves the exchange a packet behind),
    /// keeps the newest sample and runs the safety layer once on it. Waits for nothing.
    void drain() noexcept {
        DeviceSample newer;
        while (device->try_read(newer, 0) == DeviceStatus::kOk) {
            sample = newer;
            status = DeviceStatus::kOk;
            ++drained;
        }
        decide();
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
    Vec3 desired{};
    Vec3 out{};
    std::uint64_t late_reads = 0;       ///< lockstep reads that had to wait past one 20 ms slice
    std::uint64_t drained = 0;          ///< queued answers drain() read
    std::uint64_t engage_restarts = 0;  ///< test::engage() attempts that had to start over
};

}  // namespace kerf::firmware_host::test
