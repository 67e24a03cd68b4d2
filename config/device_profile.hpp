// kerf::config::DeviceProfile — what Kerf knows about one haptic device (config/devices/*.toml).
//
// Plain data in SI units, consumed by the device layer (firmware_host/) and the real-time loop.
// The loader checks every field (types, ranges, units, unknown keys); a profile that loads is
// internally consistent (workspace min < max, continuous force <= peak force, ...).
//
//   auto profile = kerf::config::load_device_profile("config/devices/falcon.toml");
//   if (!profile) { std::cerr << profile.error().message() << '\n'; return 1; }
//   double peak = profile->limits.peak_force_n;
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/result.hpp"
#include "config/config_error.hpp"

namespace kerf::config {

/// Which transport and protocol drive the device.
enum class DeviceKind : std::uint8_t {
    kFalcon,     ///< Novint Falcon over libusb (FTDI), 16-byte nibble protocol
    kKerfHid,    ///< a device speaking Kerf's open HID protocol (firmware_host/PROTOCOL.md)
    kSimulated,  ///< kerf-hapsim, the byte-level emulator, reached through a Unix socket
};
std::string_view to_string(DeviceKind kind) noexcept;

/// Whether the device reports joint angles (the host runs kinematics) or Cartesian positions.
enum class ReportingSpace : std::uint8_t { kJoint, kCartesian };
std::string_view to_string(ReportingSpace space) noexcept;

/// The kinematic model the host applies to joint-space reports.
enum class KinematicModel : std::uint8_t {
    kFalconDelta,  ///< the Falcon's three-legged delta (Stamper's notation, as in libnifalcon)
    kCartesian,    ///< positions already Cartesian; no kinematics on the host
};
std::string_view to_string(KinematicModel model) noexcept;

/// USB / HID identity. For kSimulated the ids are those the emulator reports.
struct DeviceIds {
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::string serial;  ///< empty: any serial number matches
};

/// Falcon delta geometry, Stamper's link naming (libnifalcon FalconGeometry.h). Metres, degrees.
struct FalconDeltaGeometry {
    double a_m = 0;  ///< leg base to knee
    double b_m = 0;  ///< shin parallelogram side
    double c_m = 0;  ///< shin joint to end-effector centre, u component
    double d_m = 0;  ///< shin to end-effector joint
    double e_m = 0;  ///< knee to shin joint
    double f_m = 0;  ///< shin joint to end-effector centre, v component (signed)
    double r_m = 0;  ///< frame origin to leg base, u component (signed)
    double s_m = 0;  ///< frame origin to leg base, v component (signed)
    std::array<double, 3> leg_angles_deg{};  ///< angle of each leg about the z axis
    double theta_offset_deg = 0;             ///< arm angle at encoder count 0
};

/// How joint or Cartesian positions are quantised.
struct EncoderSpec {
    std::uint32_t counts_per_rev = 0;  ///< motor-shaft counts per revolution (joint space; else 0)
    double shaft_diameter_m = 0;       ///< capstan on the motor shaft (joint space; else 0)
    double drum_diameter_m = 0;        ///< arm drum the capstan drives (joint space; else 0)
    double resolution_m = 0;           ///< smallest reported step (Cartesian space; else 0)
};

/// Motor command scaling (joint-space devices; zero for Cartesian devices).
struct MotorSpec {
    double command_per_n_m = 0;      ///< device command units per N·m of arm torque
    std::int32_t command_limit = 0;  ///< largest |command| the wire field holds
};

/// Force limits the host-side safety layer enforces, whatever the force model asks.
struct DeviceLimits {
    double peak_force_n = 0;        ///< direction-preserving clamp on |F|
    double continuous_force_n = 0;  ///< sustained limit, <= peak_force_n
    double max_slew_n_per_s = 0;    ///< largest rate of change of |F|
    /// Command watchdog. Kerf HID devices get it in their configuration report (forces off when
    /// no valid command arrives within it); for devices without one (the Falcon) the host
    /// applies it to the input side (zero force when no valid packet arrives within it).
    std::uint32_t watchdog_ms = 0;
};

/// Axis-aligned box the end effector can reach, in the device frame (m).
struct Workspace {
    std::array<double, 3> min_m{};
    std::array<double, 3> max_m{};
};

/// Connection details of the emulator (kind == kSimulated only).
struct EmulatorSpec {
    DeviceKind protocol = DeviceKind::kKerfHid;  ///< which wire protocol kerf-hapsim speaks
    std::string socket_path;                     ///< Unix socket; `${runtime}` allowed
    bool lockstep = false;                       ///< one emulator step per host packet
};

/// One device profile.
struct DeviceProfile {
    std::string name;  ///< human-readable, e.g. "Novint Falcon"
    DeviceKind kind = DeviceKind::kSimulated;
    std::uint32_t dof = 3;  ///< translational degrees of freedom
    ReportingSpace reporting_space = ReportingSpace::kCartesian;
    DeviceIds ids;
    KinematicModel kinematic_model = KinematicModel::kCartesian;
    FalconDeltaGeometry falcon_delta;  ///< meaningful when kinematic_model == kFalconDelta
    EncoderSpec encoder;
    MotorSpec motor;
    DeviceLimits limits;
    Workspace workspace;
    EmulatorSpec emulator;  ///< meaningful when kind == kSimulated
};

/// Parses a device profile from TOML text; `source_name` is used in error messages.
Result<DeviceProfile, ConfigError> parse_device_profile(std::string_view text,
                                                        std::string_view source_name);

/// Reads and parses a device profile file.
Result<DeviceProfile, ConfigError> load_device_profile(const std::filesystem::path& path);

/// The profile file stem (in `devices/`) a `--device` choice names: "simulated" and "falcon" are
/// their own profiles; "hid" and "hid:<serial>" use "kerf_hid_reference". kerf-rt opens it and
/// `kerf run --record` copies it, so both go through this one mapping.
std::string_view device_profile_stem(std::string_view device) noexcept;

/// A device profile and the name kerf.toml refers to it by (its file stem).
struct NamedDeviceProfile {
    std::string profile_name;  ///< e.g. "falcon" for devices/falcon.toml
    DeviceProfile profile;
};

/// Loads every `*.toml` in `devices_dir`, sorted by name (e.g. to match enumerated USB ids);
/// the first bad file is the error.
Result<std::vector<NamedDeviceProfile>, ConfigError> load_device_profiles(
    const std::filesystem::path& devices_dir);

}  // namespace kerf::config
