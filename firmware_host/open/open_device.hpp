// From configuration to a running Device: the thin adapter between config::DeviceProfile /
// config::ForceProfile (the config loader's structs) and firmware_host's own parameter structs,
// and `open_device()`, which picks the transport a profile describes:
//   kind "falcon"    -> LibusbLink (vid/pid/serial) -> FalconDevice
//   kind "kerf_hid"  -> HidapiTransport (vid/pid/serial or path) -> KerfHidDevice
//   kind "simulated" -> Unix socket to kerf-hapsim -> FalconDevice or KerfHidDevice
// Open-time only (allocates, blocks within timeouts).
#pragma once

#include <memory>
#include <string>

#include "config/base/result.hpp"
#include "config/device_profile.hpp"
#include "config/force_profile.hpp"
#include "firmware_host/device/device.hpp"
#include "firmware_host/device/falcon_device.hpp"
#include "firmware_host/device/kerf_hid_device.hpp"
#include "firmware_host/safety/force_safety.hpp"

namespace kerf::firmware_host {

/// Safety limits: the device's limits, tightened by the force profile's envelope when given.
SafetyLimits safety_limits_from(const config::DeviceProfile& device,
                                const config::ForceProfile* force, double period_s);

/// The Falcon delta geometry, encoder and motor scaling of a profile.
falcon::DeltaGeometry delta_geometry_from(const config::DeviceProfile& device);

/// Kerf HID start-up options (watchdog, expected ids) of a profile.
KerfHidOptions kerf_hid_options_from(const config::DeviceProfile& device);

/// What the command line may add to a profile.
struct OpenOverrides {
    std::string firmware_path;  ///< Falcon firmware image (empty: expect it loaded)
    std::string socket_path;    ///< emulator socket instead of the profile's
    std::string hid_path;       ///< open this hidraw node instead of searching by ids
};

/// Opens the device `profile` describes. Errors name what, where and why.
Result<std::unique_ptr<Device>, TransportError> open_device(const config::DeviceProfile& profile,
                                                            const OpenOverrides& overrides);

}  // namespace kerf::firmware_host
