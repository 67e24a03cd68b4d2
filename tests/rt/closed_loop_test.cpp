// The loop closed on the emulator's mechanism and scripted hand in process (sim_hand_device.hpp):
// HapticLoop with the shipped default force profile and the simulated device's limits, the real
// physics and safety layer, on the 24-shell forefoot from ../shared/meshes (shells that
// interpenetrate at the joints). Deterministic; each test runs a few seconds of device time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "config/device_profile.hpp"
#include "config/force_profile.hpp"
#include "firmware_host/open/open_device.hpp"
#include "rt_core/loop/collision_mesh_builder.hpp"
#include "rt_core/loop/lockstep_world_sync.hpp"
#include "rt_core/physics/physics_params_from_profile.hpp"
#include "tests/physics/physics_test_shapes.hpp"
#include "tests/rt/rt_rig.hpp"
#include "tests/rt/sim_hand_device.hpp"

namespace kerf::rt {
namespace {

using physics::Vec3;

std::string forefoot_path() {
    return std::string(KERF_SHARED_MESHES) + "/bp3d_right_forefoot_24shells.stl";
}

/// HapticLoop + SimHandDevice on one mesh file (mm), with kerf-rt's default profiles.
struct ClosedLoop {
    ClosedLoop(const std::string& mesh_file, const std::string& script) {
        bone = test::load_bone(mesh_file);
        if (!bone) return;
        std::string error;
        device = test::SimHandDevice::create(script, error);
        EXPECT_TRUE(device) << error;
        auto force =
            config::load_force_profile(std::string(KERF_SOURCE_DIR) + "/config/force/default.toml");
        auto profile = config::load_device_profile(std::string(KERF_SOURCE_DIR) +
                                                   "/config/devices/simulated.toml");
        auto made = ipc::ProducerBuilder()
                        .segment_name("kerf.rt-closed-" + std::to_string(getpid()) + "-" +
                                      std::to_string(reinterpret_cast<std::uintptr_t>(this)))
                        .create();
        if (!device || !force || !profile || !made) return;
        producer.emplace(std::move(*made));
        LoopSettings settings;
        settings.lockstep = true;
        settings.device_origin_in_world_m = device_origin_above(*bone, 0.02);
        origin = settings.device_origin_in_world_m;
        loop = std::make_unique<HapticLoop>(
            *device, *producer, log, settings, physics::physics_params_from_profile(*force),
            firmware_host::safety_limits_from(*profile, &*force, 1e-3));
        builder = std::make_unique<WorldBuilder>(loop->world_handoff(), producer->layout());
        ok = bool(builder->build(*bone));
        loop->prime();
    }
    ~ClosedLoop() { loop.reset(); }

    void tick(std::uint64_t missed = 0) {
        TickTiming t;
        t.start_ns = ++ticks * 1'000'000u;
        t.missed_deadlines = missed;
        loop->tick(t);
    }
    double force() const {
        const auto& f = loop->last_force_n();
        return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    }

    bool ok = false;
    std::unique_ptr<ipc::CollisionMesh> bone;
    std::unique_ptr<test::SimHandDevice> device;
    std::optional<ipc::Producer> producer;
    RtLog log;
    std::unique_ptr<HapticLoop> loop;
    std::unique_ptr<WorldBuilder> builder;
    Vec3 origin;
    std::uint64_t ticks = 0;
};

/// Points where a vertical press from above meets bone at least `depth_m` thick: the first
/// surface crossing of a drop from the device's start height on a 10 mm grid (world frame).
std::vector<Vec3> press_targets(const physics::test::TestMesh& mesh, const Vec3& origin,
                                double depth_m, std::size_t count) {
    auto built = physics::CollisionBody::build(mesh.view());
    EXPECT_TRUE(built);
    if (!built) return {};
    physics::CollisionWorld world;
    world.set_body(0, built->get());
    std::vector<Vec3> out;
    for (int iz = -6; iz <= 6 && out.size() < count; iz += 2) {
        for (int ix = -4; ix <= 4 && out.size() < count; ix += 2) {
            const Vec3 top = origin + Vec3{ix * 0.01, 0, iz * 0.01};
            const physics::SegmentHit hit =
                world.first_hit(top, top - Vec3{0, 0.15, 0}, physics::HitSides::kFront);
            if (!hit.found) continue;
            if (physics::test::winding_number(mesh, hit.point - Vec3{0, depth_m, 0}) < 0.5)
                continue;
            out.push_back(hit.point);
        }
    }
    return out;
}

// The soak's "20-120 mm penetration with zero force": after force was cut for a moment (a
// late sample, the loop's timing safe state), the safety layer waited for a quiet demand, but
// the proxy held on the surface kept the demand high while the hand pushed on, so force never
// came back and the tool went on through the bone. Here the hand presses 10 mm into bone at
// several places of the multi-shell forefoot; during each press force is cut (two late samples
// on some presses, three missed deadlines on the others). Force must come back within a few
// ticks, ramping in, and the tool is never left inside the bone without force for longer, and
// the proxy is never inside a shell.
TEST(RtClosedLoop, ForceCutWhilePressingIntoAMultiShellBoneComesBackAndPushesTheToolOut) {
    if (!std::filesystem::exists(forefoot_path())) GTEST_SKIP() << "no " << forefoot_path();
    const physics::test::TestMesh mesh = physics::test::read_binary_stl(forefoot_path(), 0.001);
    ASSERT_EQ(mesh.triangles(), 41320u);
    ClosedLoop probe(forefoot_path(), "hold,0.1\n");
    ASSERT_TRUE(probe.ok);
    const std::vector<Vec3> targets = press_targets(mesh, probe.origin, 0.012, 6);
    ASSERT_GE(targets.size(), 4u) << "too few places to press";

    // Each press: over the target (0.4 s), down to 10 mm below the surface (0.5 s), hold 1.2 s
    // (force cut at 0.4 s into the hold), back up (0.4 s).
    std::string script = "hold,0.1\n";
    char line[160];
    for (const Vec3& t : targets) {
        const Vec3 d = t - probe.origin;
        std::snprintf(line, sizeof line,
                      "move,%.6f,0,%.6f,0.4\nmove,%.6f,%.6f,%.6f,0.5\nhold,1.2\n"
                      "move,%.6f,0,%.6f,0.4\n",
                      d.x, d.z, d.x, d.y - 0.010, d.z, d.x, d.z);
        script += line;
    }
    ClosedLoop rig(forefoot_path(), script);
    ASSERT_TRUE(rig.ok);
    const int per_press = 2500;
    double top = -1e9;  // above the mesh the tool is outside without a pass over it
    for (std::size_t i = 1; i < mesh.positions.size(); i += 3)
        top = std::max(top, double(mesh.positions[i]));
    const auto inside_bone = [&](const Vec3& p) {
        return p.y < top && physics::test::winding_number(mesh, p) > 0.5;
    };
    int longest_zero_inside = 0, zero_inside = 0, proxy_inside = 0, inside_ticks = 0;
    int presses_felt_again = 0, presses_inside_at_cut = 0;
    for (std::size_t press = 0; press < targets.size(); ++press) {
        bool cut = false, felt_after_cut = false, inside_at_cut = false;
        for (int i = 0; i < per_press; ++i) {
            const int t = int(press) * per_press + i;  // ms since the first press began
            const bool cut_now = i == 1300;            // 0.4 s into the hold
            if (cut_now && press % 2 == 0) rig.device->drop_reads(2);
            rig.tick(cut_now && press % 2 == 1 ? 3 : 0);
            cut = cut || cut_now;
            if (cut_now) inside_at_cut = inside_bone(rig.loop->tool_position_m());
            if (cut && i > 1320 && i < 2000 && rig.force() > 0.05) felt_after_cut = true;
            if (t % 10 != 0) continue;  // the winding number costs a full pass over the mesh
            const Vec3 tool = rig.loop->tool_position_m(), proxy = rig.loop->last_physics().proxy_m;
            const bool inside = inside_bone(tool);
            inside_ticks += inside ? 10 : 0;
            zero_inside = inside && rig.force() == 0.0 ? zero_inside + 10 : 0;
            longest_zero_inside = std::max(longest_zero_inside, zero_inside);
            if (proxy == tool ? inside : inside_bone(proxy)) {
                ADD_FAILURE() << "proxy inside a shell, press " << press << ", tick " << i;
                ++proxy_inside;
            }
        }
        presses_inside_at_cut += inside_at_cut ? 1 : 0;
        presses_felt_again += inside_at_cut && felt_after_cut ? 1 : 0;
    }
    EXPECT_GT(inside_ticks, 500) << "the presses never went into the bone";
    EXPECT_GE(presses_inside_at_cut, 3) << "force was cut while the tool was in bone too rarely";
    EXPECT_EQ(presses_felt_again, presses_inside_at_cut) << "force did not come back after a cut";
    // Cut: 2 late samples + 10 fresh ones, or 3 misses + 100 recovery ticks + 10 fresh ones.
    EXPECT_LE(longest_zero_inside, 130) << "the tool stayed inside the bone without force (ms)";
    EXPECT_EQ(proxy_inside, 0) << "samples with the proxy inside a shell";
    EXPECT_EQ(rig.loop->stats().safe_state_entries, targets.size() / 2);
}

// The slow-feed bounce: the feed resistance used to be a damper on the sampled velocity, 800 N·s/m
// on the 0.15 kg device, far above what a sampled damper renders stably at 1 kHz (about 2m/dt =
// 300 N·s/m): the force flipped tick by tick, the blade ratcheted up above the entry and the cut
// ended as withdrawn. Now the edge pushes a cut front through a spring. The saw is fed into the
// CT calcaneus by the emulated hand (its 800 N/m spring) at 1, 2, 3.5 and 10 mm/s, held, lifted
// out: one CutBegin, no CutEnd while feeding, one CutEnd{withdrawn} at the lift; while the blade is
// in the bone the feed force never pulls (never below zero along the blade's back), never lets go
// (never back to zero once it has pushed, until the lift) and never alternates in sign from one
// tick to the next; the cut front never goes back.
TEST(RtClosedLoop, ASlowFeedIsOneStableCutUntilTheBladeIsPulledOut) {
    const std::string file = test::calcaneus_path();
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
    const physics::test::TestMesh mesh = physics::test::read_binary_stl(file, 0.001);
    ClosedLoop probe(file, "hold,0.1\n");
    ASSERT_TRUE(probe.ok);
    const std::vector<Vec3> targets = press_targets(mesh, probe.origin, 0.015, 1);
    ASSERT_EQ(targets.size(), 1u);
    const Vec3 d = targets[0] - probe.origin;
    for (const double feed_mm_s : {1.0, 2.0, 3.5, 10.0}) {
        // Over the bone with the blade 3 mm above it, the saw on, 13 mm of feed (10 mm into the
        // bone) at the feed speed, a second's hold, then lifted 10 mm above the surface.
        const double feed_m = 0.013, feed_s = feed_m * 1e3 / feed_mm_s;
        char script[512];
        std::snprintf(script, sizeof script,
                      "hold,0.1\nmove,%.6f,0,%.6f,0.5\nmove,%.6f,%.6f,%.6f,0.5\nbutton,0,down\n"
                      "hold,0.2\nmove,%.6f,%.6f,%.6f,%.4f\nhold,1.0\nmove,%.6f,%.6f,%.6f,1.15\n"
                      "button,0,up\nhold,0.5\n",
                      d.x, d.z, d.x, d.y + 0.003, d.z, d.x, d.y + 0.003 - feed_m, d.z, feed_s, d.x,
                      d.y + 0.010, d.z);
        ClosedLoop rig(file, script);
        ASSERT_TRUE(rig.ok);
        const int ticks = int((0.1 + 0.5 + 0.5 + 0.2 + feed_s + 1.0 + 1.15 + 0.4) * 1e3);
        const int lift_at = int((0.1 + 0.5 + 0.5 + 0.2 + feed_s + 1.0) * 1e3);
        int begins = 0, withdrawn = 0, other_ends = 0, pulls = 0, flips = 0, front_back = 0;
        int let_go = 0;
        double depth_at_end = 0, front = 0, last_feed_force = 0;
        Vec3 v;  // the locked blade's edge -> back direction (normal x u)
        for (int t = 0; t < ticks; ++t) {
            rig.tick();
            const physics::SawOutput& saw = rig.loop->last_physics().saw;
            if (saw.event_count > 0 && saw.events[0].type == physics::CutEventType::kBegin)
                v = physics::cross(saw.events[0].plane_normal, saw.events[0].plane_u);
            if (saw.locked && t < lift_at) {
                // The feed force: the saw's force along the blade's back (v = normal x u).
                const double feed_force = physics::dot(saw.force_n, v);
                if (feed_force < -1e-9) ++pulls;
                if (feed_force * last_feed_force < 0) ++flips;
                if (last_feed_force > 0 && !(feed_force > 0)) ++let_go;
                if (saw.front_depth_m < front) ++front_back;
                front = saw.front_depth_m;
                last_feed_force = feed_force;
            }
            for (std::uint32_t e = 0; e < saw.event_count; ++e) {
                const physics::CutEvent& ev = saw.events[e];
                if (ev.type == physics::CutEventType::kBegin) ++begins, front = 0;
                if (ev.type != physics::CutEventType::kEnd) continue;
                depth_at_end = ev.feed_depth_m;
                if (ev.end_reason == physics::CutEndReason::kWithdrawn && t >= lift_at)
                    ++withdrawn;
                else
                    ++other_ends;
            }
        }
        EXPECT_EQ(begins, 1) << feed_mm_s << " mm/s";
        EXPECT_EQ(withdrawn, 1) << feed_mm_s << " mm/s";
        EXPECT_EQ(other_ends, 0) << feed_mm_s << " mm/s";
        EXPECT_GT(depth_at_end, 0.008) << feed_mm_s << " mm/s: the cut ended early";
        EXPECT_EQ(pulls, 0) << feed_mm_s << " mm/s";
        EXPECT_EQ(flips, 0) << feed_mm_s << " mm/s";
        EXPECT_EQ(let_go, 0) << feed_mm_s << " mm/s";
        EXPECT_EQ(front_back, 0) << feed_mm_s << " mm/s";
    }
}

// kerf-rt --lockstep reads through a LockstepWorldSync (cut meshes swapped at fixed ticks). A
// device re-opened after an unplug used to replace it in the loop, so world sync stopped for the
// rest of the run; now the new device goes behind it.
TEST(RtLockstepWorldSync, AReopenedDeviceGoesBehindTheSyncInsteadOfReplacingIt) {
    const std::string file = test::calcaneus_path();
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "no " << file;
    ClosedLoop rig(file, "hold,1.0\n");
    ASSERT_TRUE(rig.ok);
    LockstepWorldSync sync(*rig.device);
    rig.loop->keep_in_front(sync);
    for (int t = 0; t < 50; ++t) rig.tick();
    EXPECT_GE(rig.device->counters().samples, 50u);

    std::string error;
    auto reopened = test::SimHandDevice::create("hold,1.0\n", error);
    ASSERT_TRUE(reopened) << error;
    test::SimHandDevice* second = reopened.get();
    auto slot = std::make_unique<DeviceSlot>();
    slot->device = std::move(reopened);
    slot->generation = 1;
    rig.loop->device_handoff().offer(std::move(slot));
    const std::uint64_t first_samples = rig.device->counters().samples;
    for (int t = 0; t < 50; ++t) rig.tick();
    EXPECT_EQ(rig.loop->stats().devices_reopened, 1u);
    EXPECT_EQ(&rig.loop->device(), static_cast<firmware_host::Device*>(&sync));
    EXPECT_EQ(&sync.inner(), static_cast<firmware_host::Device*>(second));
    EXPECT_GE(second->counters().samples, 49u) << "the loop does not read the new device";
    EXPECT_EQ(rig.device->counters().samples, first_samples) << "still reading the old one";
}

}  // namespace
}  // namespace kerf::rt
