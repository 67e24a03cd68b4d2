#include "firmware_host/falcon/delta_kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kerf::firmware_host::falcon {
namespace {

constexpr int kMaxNewtonIterations = 30;
constexpr double kStepTolerance_m = 1e-11;

bool finite(const Vec3& v) noexcept {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

double det(const Mat3& m) noexcept {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Mat3 transpose(const Mat3& m) noexcept {
    Mat3 t{};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) t[c][r] = m[r][c];
    }
    return t;
}

}  // namespace

std::string_view to_string(KinematicsStatus status) noexcept {
    switch (status) {
        case KinematicsStatus::kOk:
            return "ok";
        case KinematicsStatus::kNoConvergence:
            return "forward kinematics did not converge";
        case KinematicsStatus::kSingular:
            return "kinematic singularity";
        case KinematicsStatus::kUnreachable:
            return "position outside the reachable workspace";
        case KinematicsStatus::kNonFinite:
            return "non-finite input";
    }
    return "unknown kinematics status";
}

bool solve3(const Mat3& m, const Vec3& b, Vec3& x, double min_det) noexcept {
    const double d = det(m);
    if (!std::isfinite(d) || std::abs(d) < min_det) return false;
    for (int col = 0; col < 3; ++col) {
        Mat3 mc = m;
        for (int row = 0; row < 3; ++row) mc[row][col] = b[row];
        x[col] = det(mc) / d;
    }
    return true;
}

DeltaKinematics::DeltaKinematics(const DeltaGeometry& geometry) noexcept : g_(geometry) {
    constexpr double kDeg = std::numbers::pi / 180.0;
    for (int i = 0; i < 3; ++i) {
        cos_phi_[i] = std::cos(g_.leg_angles_deg[i] * kDeg);
        sin_phi_[i] = std::sin(g_.leg_angles_deg[i] * kDeg);
    }
    rad_per_count_ =
        2.0 * std::numbers::pi / g_.counts_per_rev * g_.shaft_diameter_m / g_.drum_diameter_m;
    theta_offset_rad_ = g_.theta_offset_deg * kDeg;
}

double DeltaKinematics::angle_rad(std::int32_t counts) const noexcept {
    return counts * rad_per_count_ + theta_offset_rad_;
}

std::int32_t DeltaKinematics::counts(double angle) const noexcept {
    const double c = std::round((angle - theta_offset_rad_) / rad_per_count_);
    return static_cast<std::int32_t>(std::clamp(c, -2.0e9, 2.0e9));
}

// g_i = |joint_i - knee_i|^2 - b^2 with its derivatives by position and by theta_i.
void DeltaKinematics::residuals(const Vec3& theta, const Vec3& p, Vec3& g, Mat3& dg_dp,
                                Vec3& dg_dtheta) const noexcept {
    for (int i = 0; i < 3; ++i) {
        const double pu = cos_phi_[i] * p[0] + sin_phi_[i] * p[1];
        const double pv = -sin_phi_[i] * p[0] + cos_phi_[i] * p[1];
        const double ct = std::cos(theta[i]), st = std::sin(theta[i]);
        const double du = pu + g_.c_m - (g_.r_m + g_.a_m * ct);
        const double dv = pv + g_.f_m - g_.s_m;
        const double dw = p[2] - g_.a_m * st;
        g[i] = du * du + dv * dv + dw * dw - g_.b_m * g_.b_m;
        dg_dp[i] = {2 * (du * cos_phi_[i] - dv * sin_phi_[i]),
                    2 * (du * sin_phi_[i] + dv * cos_phi_[i]), 2 * dw};
        dg_dtheta[i] = 2 * (du * g_.a_m * st - dw * g_.a_m * ct);
    }
}

KinematicsStatus DeltaKinematics::forward(const Vec3& theta, const Vec3& guess,
                                          Vec3& position) const noexcept {
    if (!finite(theta) || !finite(guess)) return KinematicsStatus::kNonFinite;
    Vec3 p = guess;
    for (int it = 0; it < kMaxNewtonIterations; ++it) {
        Vec3 g{}, dg_dtheta{}, step{};
        Mat3 dg_dp{};
        residuals(theta, p, g, dg_dp, dg_dtheta);
        if (!solve3(dg_dp, g, step)) return KinematicsStatus::kSingular;
        for (int k = 0; k < 3; ++k) p[k] -= step[k];
        const double norm = std::abs(step[0]) + std::abs(step[1]) + std::abs(step[2]);
        if (!finite(p)) return KinematicsStatus::kNoConvergence;
        if (norm < kStepTolerance_m) {
            position = p;
            return KinematicsStatus::kOk;
        }
    }
    return KinematicsStatus::kNoConvergence;
}

KinematicsStatus DeltaKinematics::inverse(const Vec3& p, Vec3& theta) const noexcept {
    if (!finite(p)) return KinematicsStatus::kNonFinite;
    Vec3 out{};
    for (int i = 0; i < 3; ++i) {
        const double pu = cos_phi_[i] * p[0] + sin_phi_[i] * p[1];
        const double pv = -sin_phi_[i] * p[0] + cos_phi_[i] * p[1];
        const double du = pu + g_.c_m - g_.r_m, dv = pv + g_.f_m - g_.s_m, dw = p[2];
        // du cos t + dw sin t = k, from |D - a(cos t, 0, sin t)|^2 = b^2.
        const double k =
            (du * du + dv * dv + dw * dw + g_.a_m * g_.a_m - g_.b_m * g_.b_m) / (2 * g_.a_m);
        const double rho = std::hypot(du, dw);
        if (rho < 1e-12 || std::abs(k) > rho) return KinematicsStatus::kUnreachable;
        out[i] = std::atan2(dw, du) - std::acos(k / rho);
    }
    theta = out;
    return KinematicsStatus::kOk;
}

KinematicsStatus DeltaKinematics::jacobian(const Vec3& theta, const Vec3& p,
                                           Mat3& dp_dtheta) const noexcept {
    if (!finite(theta) || !finite(p)) return KinematicsStatus::kNonFinite;
    Vec3 g{}, dg_dtheta{};
    Mat3 dg_dp{};
    residuals(theta, p, g, dg_dp, dg_dtheta);
    // dg/dp dp + diag(dg/dtheta) dtheta = 0  =>  column j of dp/dtheta solves dg_dp x = -e_j g'_j.
    for (int j = 0; j < 3; ++j) {
        Vec3 rhs{}, col{};
        rhs[j] = -dg_dtheta[j];
        if (!solve3(dg_dp, rhs, col)) return KinematicsStatus::kSingular;
        for (int r = 0; r < 3; ++r) dp_dtheta[r][j] = col[r];
    }
    return KinematicsStatus::kOk;
}

KinematicsStatus DeltaKinematics::torques(const Vec3& theta, const Vec3& p, const Vec3& force,
                                          Vec3& torque) const noexcept {
    if (!finite(force)) return KinematicsStatus::kNonFinite;
    Mat3 j{};
    if (auto s = jacobian(theta, p, j); s != KinematicsStatus::kOk) return s;
    for (int k = 0; k < 3; ++k) {
        torque[k] = j[0][k] * force[0] + j[1][k] * force[1] + j[2][k] * force[2];
    }
    return KinematicsStatus::kOk;
}

KinematicsStatus DeltaKinematics::force_from_torques(const Vec3& theta, const Vec3& p,
                                                     const Vec3& torque,
                                                     Vec3& force) const noexcept {
    if (!finite(torque)) return KinematicsStatus::kNonFinite;
    Mat3 j{};
    if (auto s = jacobian(theta, p, j); s != KinematicsStatus::kOk) return s;
    if (!solve3(transpose(j), torque, force, 1e-30)) return KinematicsStatus::kSingular;
    return KinematicsStatus::kOk;
}

std::array<std::int16_t, 3> DeltaKinematics::commands(const Vec3& torque,
                                                      bool& clamped) const noexcept {
    clamped = false;
    std::array<std::int16_t, 3> out{};
    if (!finite(torque)) return out;
    const double limit = std::clamp<double>(g_.command_limit, 0.0, 32767.0);
    Vec3 c{};
    double largest = 0;
    for (int k = 0; k < 3; ++k) {
        c[k] = torque[k] * g_.command_per_n_m;
        largest = std::max(largest, std::abs(c[k]));
    }
    const double scale = largest > limit ? limit / largest : 1.0;
    clamped = scale < 1.0;
    for (int k = 0; k < 3; ++k) {
        out[k] = static_cast<std::int16_t>(std::clamp(std::round(c[k] * scale), -limit, limit));
    }
    return out;
}

}  // namespace kerf::firmware_host::falcon
