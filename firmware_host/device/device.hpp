// Device — what the 1 kHz loop calls, whatever the hardware: Falcon over libusb or the emulator
// socket, a Kerf-protocol device over hidapi or the socket. Caller-owned buffers; every call is
// noexcept, non-blocking or bounded by its timeout, and allocates nothing after open.
//
//   per tick:  dev.try_read(sample, 0)  ->  kinematics, force, safety  ->  dev.try_write(cmd)
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "firmware_host/vec3.hpp"

namespace kerf::firmware_host {

/// What one read produced (hidapi-style status: ok, timeout, disconnected, malformed).
enum class DeviceStatus : std::uint8_t {
    kOk,            ///< a fresh, valid sample is in `DeviceSample`
    kNoData,        ///< nothing new within the timeout (the previous sample is stale)
    kMalformed,     ///< bytes arrived but failed the codec (counted; not used)
    kDisconnected,  ///< the device or emulator is gone
    kError,         ///< any other transport error
};
std::string_view to_string(DeviceStatus status) noexcept;

/// Conditions the device reports (or the host derives) about itself.
struct DeviceFlags {
    bool homed = false;
    bool amplifiers_on = false;
    bool estop = false;
    bool watchdog_tripped = false;
    bool encoder_fault = false;
    bool over_temperature = false;
    bool any_fault() const noexcept {
        return estop || watchdog_tripped || encoder_fault || over_temperature;
    }
};

/// One sample, SI units, device frame.
struct DeviceSample {
    std::uint64_t count = 0;            ///< fresh samples since open (host-side, never wraps)
    std::uint32_t device_sequence = 0;  ///< the device's own sequence, when it has one
    Vec3 position_m{};
    Vec3 velocity_m_per_s{};  ///< reported, or differenced by the host
    std::uint32_t buttons = 0;
    DeviceFlags flags;
    std::uint32_t command_lag = 0;  ///< host commands sent but not yet seen by the device
    bool has_orientation = false;   ///< the device senses the tool's orientation (6-DoF input)
    std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};  ///< tool rotation, device frame
};

/// One command, SI units, device frame. The caller's safety layer has already shaped it.
struct DeviceCommand {
    Vec3 force_n{};
    bool enable = false;  ///< amplifiers on; false sends zero force with amplifiers off
    std::uint8_t leds = 0;
};

/// Running counters (read from the loop's thread).
struct DeviceCounters {
    std::uint64_t samples = 0;
    std::uint64_t malformed = 0;
    std::uint64_t timeouts = 0;
    std::uint64_t write_busy = 0;
    std::uint64_t clamped_commands = 0;
};

class Device {
public:
    virtual ~Device() = default;

    /// Reads the newest sample, waiting at most `timeout_us` (0: non-blocking). Older queued
    /// samples are consumed and dropped. `out` is written only on kOk.
    virtual DeviceStatus try_read(DeviceSample& out, std::uint32_t timeout_us) noexcept = 0;
    /// Sends one command without waiting. Commands force only when homed; else zero + homing.
    virtual DeviceStatus try_write(const DeviceCommand& command) noexcept = 0;
    /// Counters since open.
    virtual const DeviceCounters& counters() const noexcept = 0;
};

}  // namespace kerf::firmware_host
