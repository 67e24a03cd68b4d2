// Delta kinematics of the Novint Falcon in R. E. Stamper's notation (the figures libnifalcon
// uses): encoder counts -> arm angles -> end-effector position (forward, Newton iteration on the
// three arm constraints), its Jacobian, and Cartesian force -> arm torques -> 16-bit motor
// commands, clamped before the wire field could wrap. Pure, noexcept, no allocation, bounded.
//
// Model (leg i, leg frame u = cos(phi_i) x + sin(phi_i) y, v = -sin(phi_i) x + cos(phi_i) y,
// w = z): the thigh pivots at (r, s, 0) and its knee is at (r + a cos t, s, a sin t); the shin
// parallelogram (side b; half-widths d, e cancel in the position constraint) joins the knee to
// the effector joint at P_leg + (c, f, 0). Constraint: |joint - knee|^2 = b^2.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "firmware_host/vec3.hpp"

namespace kerf::firmware_host::falcon {

using Mat3 = std::array<Vec3, 3>;  ///< row-major: m[row][col]

/// Geometry and scaling; filled from config::DeviceProfile by the device adapter.
struct DeltaGeometry {
    double a_m = 0.060, b_m = 0.1025, c_m = 0.014, d_m = 0.01125, e_m = 0.01125, f_m = -0.025;
    double r_m = 0.037233758, s_m = -0.027330909;
    Vec3 leg_angles_deg = {105.0, -15.0, -135.0};
    double theta_offset_deg = 35.0;     ///< arm angle at encoder count 0
    double counts_per_rev = 1280.0;     ///< motor-shaft encoder counts per revolution
    double shaft_diameter_m = 0.01425;  ///< capstan; arm angle = motor angle * shaft / drum
    double drum_diameter_m = 0.110;
    double command_per_n_m = 10000.0;    ///< motor command units per N·m of arm torque
    std::int32_t command_limit = 32767;  ///< largest |command|; the host never exceeds it
};

enum class KinematicsStatus : std::uint8_t {
    kOk,
    kNoConvergence,  ///< Newton did not converge in the iteration budget
    kSingular,       ///< the constraint Jacobian is (nearly) singular
    kUnreachable,    ///< no arm angle reaches the position (inverse)
    kNonFinite,      ///< a NaN or infinity in the input
};
std::string_view to_string(KinematicsStatus status) noexcept;

class DeltaKinematics {
public:
    explicit DeltaKinematics(const DeltaGeometry& geometry) noexcept;

    /// Arm angle (rad) of an unwrapped encoder count.
    double angle_rad(std::int32_t counts) const noexcept;
    /// Nearest encoder count of an arm angle (the emulator's quantisation).
    std::int32_t counts(double angle_rad) const noexcept;

    /// Position (m) from arm angles; `guess` seeds the Newton iteration (use the last position).
    KinematicsStatus forward(const Vec3& theta_rad, const Vec3& guess_m,
                             Vec3& position_m) const noexcept;
    /// Arm angles for a position (closed form per leg, elbow-out branch).
    KinematicsStatus inverse(const Vec3& position_m, Vec3& theta_rad) const noexcept;
    /// dP/dtheta at a consistent (theta, position) pair.
    KinematicsStatus jacobian(const Vec3& theta_rad, const Vec3& position_m,
                              Mat3& dp_dtheta) const noexcept;

    /// Arm torques (N·m) producing `force_n` at the effector: tau = J^T F.
    KinematicsStatus torques(const Vec3& theta_rad, const Vec3& position_m, const Vec3& force_n,
                             Vec3& torque_n_m) const noexcept;
    /// Motor commands for arm torques, scaled down together (direction-preserving) so none
    /// exceeds the command limit; `clamped` tells whether scaling happened.
    std::array<std::int16_t, 3> commands(const Vec3& torque_n_m, bool& clamped) const noexcept;
    /// Effector force (N) from arm torques: F = J^-T tau (the emulator's motor model).
    KinematicsStatus force_from_torques(const Vec3& theta_rad, const Vec3& position_m,
                                        const Vec3& torque_n_m, Vec3& force_n) const noexcept;

    const DeltaGeometry& geometry() const noexcept { return g_; }

private:
    void residuals(const Vec3& theta, const Vec3& p, Vec3& g, Mat3& dg_dp,
                   Vec3& dg_dtheta) const noexcept;

    DeltaGeometry g_;
    Vec3 cos_phi_{}, sin_phi_{};
    double rad_per_count_ = 0;
    double theta_offset_rad_ = 0;
};

/// Solves m x = b by Cramer's rule; false when |det| is below `min_det`.
bool solve3(const Mat3& m, const Vec3& b, Vec3& x, double min_det = 1e-18) noexcept;

}  // namespace kerf::firmware_host::falcon
