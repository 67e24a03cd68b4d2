#include "firmware_host/falcon/delta_kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace kerf::firmware_host::falcon {
namespace {

const DeltaKinematics kFalcon{DeltaGeometry{}};
constexpr Vec3 kCentre = {0.0, 0.0, 0.11};

TEST(DeltaKinematics, EncoderZeroIsNearTheWorkspaceCentre) {
    Vec3 p{};
    const Vec3 theta = {kFalcon.angle_rad(0), kFalcon.angle_rad(0), kFalcon.angle_rad(0)};
    ASSERT_EQ(kFalcon.forward(theta, kCentre, p), KinematicsStatus::kOk);
    EXPECT_NEAR(p[0], 0.0, 0.01);
    EXPECT_NEAR(p[1], 0.0, 0.01);
    EXPECT_GT(p[2], 0.075);
    EXPECT_LT(p[2], 0.175);
}

TEST(DeltaKinematics, ForwardInvertsInverseAcrossTheWorkspace) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> xy(-0.04, 0.04), z(0.075, 0.13);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 target = {xy(rng), xy(rng), z(rng)};
        Vec3 theta{}, p{};
        ASSERT_EQ(kFalcon.inverse(target, theta), KinematicsStatus::kOk);
        ASSERT_EQ(kFalcon.forward(theta, kCentre, p), KinematicsStatus::kOk);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], target[k], 1e-9);
    }
}

TEST(DeltaKinematics, JacobianMatchesFiniteDifferences) {
    const Vec3 target = {0.02, -0.01, 0.12};
    Vec3 theta{}, p{};
    ASSERT_EQ(kFalcon.inverse(target, theta), KinematicsStatus::kOk);
    Mat3 j{};
    ASSERT_EQ(kFalcon.jacobian(theta, target, j), KinematicsStatus::kOk);
    const double h = 1e-7;
    for (int col = 0; col < 3; ++col) {
        Vec3 tp = theta, tm = theta, pp{}, pm{};
        tp[col] += h;
        tm[col] -= h;
        ASSERT_EQ(kFalcon.forward(tp, target, pp), KinematicsStatus::kOk);
        ASSERT_EQ(kFalcon.forward(tm, target, pm), KinematicsStatus::kOk);
        for (int row = 0; row < 3; ++row) {
            EXPECT_NEAR(j[row][col], (pp[row] - pm[row]) / (2 * h), 1e-5);
        }
    }
    (void)p;
}

TEST(DeltaKinematics, TorquesAndForcesAreInverse) {
    const Vec3 target = {-0.03, 0.02, 0.1};
    Vec3 theta{}, tau{}, f{};
    ASSERT_EQ(kFalcon.inverse(target, theta), KinematicsStatus::kOk);
    const Vec3 force = {1.0, -2.0, 3.0};
    ASSERT_EQ(kFalcon.torques(theta, target, force, tau), KinematicsStatus::kOk);
    ASSERT_EQ(kFalcon.force_from_torques(theta, target, tau, f), KinematicsStatus::kOk);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[k], force[k], 1e-9);
}

TEST(DeltaKinematics, CommandsAreScaledTogetherAndNeverWrap) {
    bool clamped = false;
    auto c = kFalcon.commands({100.0, -50.0, 10.0}, clamped);  // 1e6 units: far beyond 16 bits
    EXPECT_TRUE(clamped);
    EXPECT_EQ(c[0], 32767);
    EXPECT_NEAR(c[1], -16384, 1);
    EXPECT_NEAR(c[2], 3277, 1);
    c = kFalcon.commands({-1e300, 0, 0}, clamped);
    EXPECT_EQ(c[0], -32767);
    c = kFalcon.commands({0.1, 0.2, -0.3}, clamped);
    EXPECT_FALSE(clamped);
    EXPECT_EQ(c[2], -3000);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    c = kFalcon.commands({nan, 1, 1}, clamped);
    EXPECT_EQ(c, (std::array<std::int16_t, 3>{0, 0, 0}));
}

TEST(DeltaKinematics, RejectsNonFiniteAndUnreachableInput) {
    const double inf = std::numeric_limits<double>::infinity();
    Vec3 out{};
    EXPECT_EQ(kFalcon.forward({inf, 0, 0}, kCentre, out), KinematicsStatus::kNonFinite);
    EXPECT_EQ(kFalcon.inverse({0, 0, 1.0}, out), KinematicsStatus::kUnreachable);
}

TEST(DeltaKinematics, EncoderCountsRoundTripThroughAngles) {
    for (std::int32_t c : {-3000, -1, 0, 1, 1234, 3000}) {
        EXPECT_EQ(kFalcon.counts(kFalcon.angle_rad(c)), c);
    }
}

}  // namespace
}  // namespace kerf::firmware_host::falcon
