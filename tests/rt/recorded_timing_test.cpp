// A session recorded in real time replays to the same forces and safe-state entries: the loop's
// timing faults (missed deadlines from hypervisor stalls, overruns) are recorded with each tick's
// device input and re-enacted by the replay (HapticLoop::replay_from). The loop runs on a
// real shared-memory session against a real collision world (a 40 mm cube, built by the
// WorldBuilder as kerf-rt does); the hand is a deterministic device pressing into it, backing
// out and pressing again, with stalls injected at fixed ticks. Without the recorded timing the
// replay diverges at the first stall (the control run shows the test can fail).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "rt_core/ipc/producer.hpp"
#include "rt_core/loop/collision_mesh_builder.hpp"
#include "rt_core/loop/haptic_loop.hpp"
#include "rt_core/loop/input_recording.hpp"
#include "rt_core/loop/world_builder.hpp"

namespace kerf::rt {
namespace {

namespace fs = std::filesystem;
using firmware_host::DeviceCommand;
using firmware_host::DeviceCounters;
using firmware_host::DeviceSample;
using firmware_host::DeviceStatus;

constexpr std::uint64_t kTicks = 6000;

/// The hand's height (device frame, m) at read n: down 8 mm, hold, back up, down again, hold.
double hand_y(std::uint64_t n) {
    const auto ramp = [](double t, double t0, double t1) {
        return std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    };
    const double t = double(n);
    if (n < 3800) return -0.008 * ramp(t, 200, 1700);
    if (n < 4300) return -0.008 * (1.0 - ramp(t, 3800, 4100));
    return -0.008 * ramp(t, 4300, 5100);
}

/// A homed device whose read n gives the hand at hand_y(n) (every 97th read: no new sample).
class PressingHand final : public firmware_host::Device {
public:
    DeviceStatus try_read(DeviceSample& out, std::uint32_t) noexcept override {
        const std::uint64_t n = reads_++;
        if (n % 97 == 50) return DeviceStatus::kNoData;
        out.count = n + 1;
        out.device_sequence = std::uint32_t(n);
        out.position_m = {0.0005, hand_y(n), -0.0003};
        out.velocity_m_per_s = {0.0, (hand_y(n + 1) - hand_y(n)) * 1000.0, 0.0};
        out.flags.homed = true;
        out.flags.amplifiers_on = true;
        return DeviceStatus::kOk;
    }
    DeviceStatus try_write(const DeviceCommand&) noexcept override { return DeviceStatus::kOk; }
    const DeviceCounters& counters() const noexcept override { return counters_; }

private:
    std::uint64_t reads_ = 0;
    DeviceCounters counters_;
};

/// The stalls the recorded run suffers: three late wake-ups in a row (safe state), later one
/// wake-up that skipped six deadlines (safe state again), and a lone late tick (no safe state).
std::uint64_t stall_at(std::uint64_t tick) {
    if (tick >= 3200 && tick < 3203) return 1;
    if (tick == 5500) return 6;
    if (tick == 2500) return 1;
    return 0;
}

/// A 40 mm cube centred on the origin, outward triangles, cortical.
std::unique_ptr<ipc::CollisionMesh> cube() {
    const float h = 0.02f;
    std::vector<float> p;
    for (int i = 0; i < 8; ++i) {
        p.push_back(i & 1 ? h : -h);
        p.push_back(i & 2 ? h : -h);
        p.push_back(i & 4 ? h : -h);
    }
    const std::vector<std::uint32_t> t = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                          2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    const std::vector<std::uint8_t> m(12, 0);
    std::array<float, 16> identity{};
    for (int i = 0; i < 4; ++i) identity[std::size_t(i * 5)] = 1.0f;
    auto out = std::make_unique<ipc::CollisionMesh>();
    if (!append_body(*out, p, t, m, identity)) return nullptr;
    return out;
}

struct Trace {
    std::vector<firmware_host::Vec3> force;
    std::vector<std::uint8_t> safe;
    LoopStats stats;
};

/// Runs kTicks ticks of a loop on `device` (a real session segment, the cube as its world), the
/// runner's timing from `stall_of`; `replay` gives the loop recorded timing instead.
Trace run(firmware_host::Device& device,
          const std::function<std::uint64_t(std::uint64_t)>& stall_of, const TickReplay* replay,
          InputRecorder* recorder, int run_id) {
    Trace out;
    auto producer = ipc::ProducerBuilder()
                        .segment_name("kerf.timing-test-" + std::to_string(getpid()) + "-" +
                                      std::to_string(run_id))
                        .create();
    EXPECT_TRUE(producer) << producer.error().message();
    if (!producer) return out;
    const auto world = cube();
    EXPECT_TRUE(world);
    if (!world) return out;
    RtLog log;
    LoopSettings settings;
    settings.lockstep = true;
    settings.device_origin_in_world_m = device_origin_above(*world, 0.005);
    firmware_host::SafetyLimits limits;
    limits.ramp_in_s = 0.02;
    limits.engage_quiet_ticks = 10;
    HapticLoop loop(device, *producer, log, settings, physics::PhysicsParams{}, limits);
    loop.record_to(recorder);
    loop.replay_from(replay);
    WorldBuilder builder(loop.world_handoff(), producer->layout());
    const auto built = builder.build(*world);
    EXPECT_TRUE(built) << built.error();
    loop.prime();
    for (std::uint64_t t = 0; t < kTicks; ++t) {
        TickTiming timing;
        timing.start_ns = 1'000'000 * (t + 1);
        timing.missed_deadlines = stall_of(t);
        loop.tick(timing);
        loop.record_compute(1000);
        out.force.push_back(loop.last_force_n());
        out.safe.push_back(loop.in_safe_state() ? 1 : 0);
    }
    out.stats = loop.stats();
    return out;
}

bool same_forces(const Trace& a, const Trace& b) {
    return a.force.size() == b.force.size() &&
           std::memcmp(a.force.data(), b.force.data(),
                       a.force.size() * sizeof(firmware_host::Vec3)) == 0;
}

TEST(RecordedTiming, StallsRecordedInRealTimeReplayToTheSameSafeStatesAndForces) {
    const fs::path file =
        fs::temp_directory_path() / ("kerf-timing-test-" + std::to_string(getpid()) + ".rec");
    Trace recorded;
    {
        auto recorder = InputRecorder::start(file.string(), 1'000'000);
        ASSERT_TRUE(recorder) << recorder.error();
        PressingHand hand;
        recorded = run(hand, stall_at, nullptr, recorder->get(), 0);
        auto stopped = (*recorder)->stop();
        ASSERT_TRUE(stopped) << stopped.error();
        ASSERT_EQ(*stopped, kTicks);
    }
    ASSERT_EQ(recorded.force.size(), kTicks);
    EXPECT_EQ(recorded.stats.safe_state_entries, 2u) << "the stalls did not trip the safe state";
    EXPECT_EQ(recorded.stats.missed_deadlines, 10u);
    int pressing = 0;
    for (std::uint64_t t = 0; t < kTicks; ++t) {
        const auto& f = recorded.force[t];
        pressing += std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) > 0.1 ? 1 : 0;
    }
    EXPECT_GT(pressing, 1000) << "the hand never pressed into the cube";
    EXPECT_EQ(recorded.safe[3202], 1) << "safe state from the third late tick on";
    EXPECT_EQ(recorded.safe[5500], 1);

    auto loaded = load_recording(file.string());
    ASSERT_TRUE(loaded) << loaded.error();
    const auto no_stalls = [](std::uint64_t) { return std::uint64_t{0}; };
    {
        ReplayDevice replay(*loaded, {});
        const Trace replayed = run(replay, no_stalls, &replay, nullptr, 1);
        EXPECT_TRUE(same_forces(recorded, replayed)) << "the replayed forces differ";
        EXPECT_EQ(replayed.safe, recorded.safe) << "safe state at other ticks";
        EXPECT_EQ(replayed.stats.safe_state_entries, 2u);
        EXPECT_EQ(replayed.stats.missed_deadlines, 10u);
    }
    {  // control: the same input without its timing diverges at the first stall
        ReplayDevice replay(*loaded, {});
        const Trace untimed = run(replay, no_stalls, nullptr, nullptr, 2);
        EXPECT_FALSE(same_forces(recorded, untimed));
        EXPECT_EQ(untimed.stats.safe_state_entries, 0u);
    }
    fs::remove(file);
}

TEST(RecordedTiming, RecordsOutOfRangeTimingAreRefused) {
    const fs::path file =
        fs::temp_directory_path() / ("kerf-timing-bad-" + std::to_string(getpid()) + ".rec");
    {
        auto recorder = InputRecorder::start(file.string(), 1'000'000);
        ASSERT_TRUE(recorder) << recorder.error();
        PressingHand hand;
        DeviceSample s;
        for (std::uint64_t i = 0; i < 10; ++i) {
            TickSeen seen;
            seen.tick = i;
            seen.status = hand.try_read(s, 0);
            seen.sample = &s;
            (*recorder)->record(seen);
        }
        ASSERT_TRUE((*recorder)->stop());
    }
    {  // tick 4 claims it overran twice
        std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
        const auto at = std::streamoff(sizeof(RecordingHeader) + 4 * sizeof(RecordedInput) +
                                       offsetof(RecordedInput, overran_last));
        f.seekp(at);
        const char two = 2;
        f.write(&two, 1);
    }
    auto loaded = load_recording(file.string());
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().find("record 4: bad timing"), std::string::npos) << loaded.error();
    fs::remove(file);
}

}  // namespace
}  // namespace kerf::rt
