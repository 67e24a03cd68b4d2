// The fault-injection check shared by the Kerf HID and Falcon integration tests: inject a
// fault between a tick's read and its write (so the next device packet is the first one
// affected), expect zero force within 2 ticks and for as long as the fault lasts, clear it,
// expect the loop to re-engage and deliver force again.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "tests/firmware_host/device_loop.hpp"
#include "tests/firmware_host/hapsim_process.hpp"

namespace kerf::firmware_host::test {

/// Engages (zero demand until the safety layer engages) and ramps to `force_n` upward.
/// Count-and-survive: on a loaded machine a stall may make reads late (the safety layer zeroes
/// force and ramps in again, as it must) or trip the device's watchdog (cleared only by a zero
/// command); so this starts over from zero demand when the force is not delivered, a bounded
/// number of times, counting the restarts, instead of asserting after a fixed number of ticks.
inline void engage(DeviceLoop& loop, double force_n = 2.0) {
    for (int attempt = 0; attempt < 20; ++attempt, ++loop.engage_restarts) {
        loop.desired = {0, 0, 0};
        for (int i = 0; i < 3000 && !(loop.status == DeviceStatus::kOk && loop.safety.engaged());
             ++i) {
            loop.tick(20000);
        }
        if (!loop.sample.flags.homed || !loop.safety.engaged()) continue;
        loop.desired = {0, 0, force_n};
        for (int i = 0; i < 400 && !(i >= 60 && std::abs(loop.force() - force_n) < 1e-6); ++i) {
            loop.tick(20000);
        }
        if (std::abs(loop.force() - force_n) < 1e-6) return;
    }
    ASSERT_TRUE(loop.sample.flags.homed);
    ASSERT_TRUE(loop.safety.engaged()) << to_string(loop.status);
    ASSERT_NEAR(loop.force(), force_n, 1e-6) << to_string(loop.status);
}

/// `reopen` is called after the fault clears when the connection was lost (unplug).
inline void check_fault(HapsimProcess& sim, DeviceLoop& loop, const std::string& name,
                        const std::string& on, const std::string& off,
                        const std::function<DeviceLoop*()>& reopen = {}) {
    SCOPED_TRACE("fault " + name);
    engage(loop);
    // The emulator answers the last write, however late; answers a stall left queued are read
    // too, so the write after the injection is the only packet in flight.
    loop.read_lockstep();
    loop.drain();
    ASSERT_GT(loop.force(), 0.0);
    ASSERT_TRUE(sim.command("fault " + name + " " + on));
    loop.write();
    int zero_after = -1;
    for (int i = 1; i <= 2 && zero_after < 0; ++i) {
        loop.tick(3000);
        if (loop.force() == 0.0) zero_after = i;
    }
    ASSERT_GT(zero_after, 0) << "force still " << loop.force() << " N two ticks after the fault";
    for (int i = 0; i < 20; ++i) {
        loop.tick(3000);
        ASSERT_EQ(loop.force(), 0.0) << "tick " << i << " while the fault lasts";
    }
    ASSERT_TRUE(sim.command("fault " + name + " " + off));
    DeviceLoop* active = &loop;
    if (reopen) {
        active = reopen();
        ASSERT_NE(active, nullptr);
    }
    engage(*active);  // recovery: re-engages through ramp-in and delivers the force again
}

}  // namespace kerf::firmware_host::test
