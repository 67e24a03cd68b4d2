// Camera presets and orbit, the HUD text and frame statistics (no GL).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "display/render/camera.hpp"
#include "display/render/hud.hpp"
#include "display/render/renderer.hpp"

namespace kerf::render {
namespace {

TEST(Camera, EveryPresetFramesTheWholeBox) {
    const glm::dvec3 lo(-0.01, -0.02, 0.0), hi(0.03, 0.02, 0.08);
    for (CameraPreset p : {CameraPreset::kFront, CameraPreset::kSide, CameraPreset::kTop,
                           CameraPreset::kIsometric}) {
        const Camera c = Camera::framing(lo, hi, p);
        const glm::mat4 vp = c.projection(16.0 / 9.0) * c.view();
        for (int i = 0; i < 8; ++i) {
            const glm::dvec3 corner(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
            const glm::vec4 clip = vp * glm::vec4(glm::vec3(corner), 1.0f);
            ASSERT_GT(clip.w, 0.0f) << to_string(p);
            EXPECT_LE(std::abs(clip.x / clip.w), 1.0f) << to_string(p) << " corner " << i;
            EXPECT_LE(std::abs(clip.y / clip.w), 1.0f) << to_string(p) << " corner " << i;
            EXPECT_LE(std::abs(clip.z / clip.w), 1.0f) << to_string(p) << " corner " << i;
        }
    }
}

TEST(Camera, PresetsLookFromTheirNamedSide) {
    const glm::dvec3 lo(-1, -1, -1), hi(1, 1, 1);
    EXPECT_LT(Camera::framing(lo, hi, CameraPreset::kFront).eye().y, -1.0);
    EXPECT_GT(Camera::framing(lo, hi, CameraPreset::kSide).eye().x, 1.0);
    EXPECT_GT(Camera::framing(lo, hi, CameraPreset::kTop).eye().z, 1.0);
}

TEST(Camera, OrbitKeepsTheDistanceAndStopsShortOfThePoles) {
    Camera c = Camera::framing({-1, -1, -1}, {1, 1, 1});
    const double d = glm::length(c.eye() - c.target());
    c.orbit(0.7, 0.2);
    EXPECT_NEAR(glm::length(c.eye() - c.target()), d, 1e-9);
    c.orbit(0.0, 10.0);
    EXPECT_LT(c.pitch_rad(), 0.5 * 3.14159265358979);
    c.orbit(0.0, -20.0);
    EXPECT_GT(c.pitch_rad(), -0.5 * 3.14159265358979);
    const double yaw = c.yaw_rad();
    c.orbit(std::numeric_limits<double>::quiet_NaN(), 0.0);  // ignored
    EXPECT_EQ(c.yaw_rad(), yaw);
    c.zoom(0.5);
    EXPECT_NEAR(c.distance_m(), 0.5 * d, 1e-9);
    c.zoom(-1.0);  // ignored
    EXPECT_NEAR(c.distance_m(), 0.5 * d, 1e-9);
}

TEST(Hud, ShowsEveryItemAndDashesForUnknownNumbers) {
    HudState h;
    h.fps = 58.25;
    h.frame_p99_ms = 21.0;
    h.haptic_rate_hz = 999.6;
    h.haptic_overruns = 7;
    h.device_state = "connected";
    h.cut_state = "cutting";
    h.cut_depth_mm = 4.5;
    h.event_backlog = 3;
    h.triangles = 1234;
    const std::string s = format_hud(h);
    for (const char* want :
         {"58.2 fps", "p99 21.0 ms", "1234 tris", "1000 Hz", "overruns 7", "wake - us",
          "device connected", "cutting", "depth 4.5 mm", "backlog 3 events"}) {
        EXPECT_NE(s.find(want), std::string::npos) << want << " not in:\n" << s;
    }
}

TEST(FrameStats, ReportsRateAndPercentilesOverItsWindow) {
    FrameStats f;
    EXPECT_LT(f.fps(), 0.0);
    for (int i = 0; i < 99; ++i) f.add(0.010);
    f.add(0.050);
    EXPECT_NEAR(f.fps(), 100.0 / (99 * 0.010 + 0.050), 1e-9);
    EXPECT_NEAR(f.percentile_ms(0.5), 10.0, 1e-9);
    EXPECT_NEAR(f.percentile_ms(1.0), 50.0, 1e-9);
    for (int i = 0; i < FrameStats::kWindow; ++i) f.add(0.020);  // the old frames roll out
    EXPECT_NEAR(f.percentile_ms(0.99), 20.0, 1e-9);
    f.add(-1.0);  // ignored
    EXPECT_NEAR(f.fps(), 50.0, 1e-9);
}

TEST(BladePose, ComesFromTheLatestStateToolPose) {
    ipc::LatestState s{};
    s.tool_position_m[0] = 0.01;
    s.tool_position_m[2] = -0.02;
    s.tool_orientation_wxyz[0] = 2.0;  // not unit: normalised
    BladePose like;
    like.length_m = 0.04;
    const BladePose b = blade_pose_from(s, like);
    EXPECT_TRUE(b.visible);
    EXPECT_DOUBLE_EQ(b.position_m.x, 0.01);
    EXPECT_DOUBLE_EQ(b.position_m.z, -0.02);
    EXPECT_DOUBLE_EQ(b.orientation.w, 1.0);
    EXPECT_DOUBLE_EQ(b.length_m, 0.04);
    s.tool_orientation_wxyz[0] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(blade_pose_from(s).visible);
    s.tool_orientation_wxyz[0] = 0.0;
    EXPECT_FALSE(blade_pose_from(s).visible);
}

}  // namespace
}  // namespace kerf::render
