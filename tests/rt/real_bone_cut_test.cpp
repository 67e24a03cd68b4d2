// kerf-rt's cut events on a real bone, applied by the display's own code. The loop (the real
// kerf-hapsim in lockstep, the Kerf HID device code, a real session segment and journal) saws a
// slice off the end of the CT calcaneus with the planned blade, the scene loaded from the
// shipped `calcaneus` scene exactly as kerf-rt loads it. A consumer in the display's slot applies
// the events as they arrive (kerf::display::apply_record, what kerf-display runs) to a CutSession
// built from the same scene (build_scene_mesh, what kerf-display starts from); afterwards a second
// CutSession replays the session's journal. Expected: one cut begun and completed, nothing
// refused, two bodies — the slice beyond the plane and the rest, both closed — and the live hash
// equal to the replay hash.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "config/load_config.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/app/session_events_ipc.hpp"
#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/journal_reader.hpp"
#include "rt_core/loop/input_recording.hpp"
#include "tests/cut/mesh_checks.hpp"
#include "tests/rt/rt_process_support.hpp"
#include "tests/rt/rt_rig.hpp"

namespace kerf::rt {
namespace {

// The scene centres the calcaneus (its bbox centre at the origin; top at y = 40 mm, the far end
// at z = 31 mm); the Rig's device origin sits 10 mm above the top. The plane z = 25 mm (device
// z = 0.0249) crosses the bone 6 mm from its end, where the section is 22 mm wide (x) and 23 mm
// tall: the planned blade (edge 25 mm along x, normal +z) is lowered above it, the saw started,
// and the hand feeds it down at 10 mm/s until the edge is below the bone. (Slow feeds are
// closed_loop_test.cpp's: in process, without the per-tick socket round trip.)
const char* kSliceScript =
    "hold,0.05\n"
    "move,0.0041,0.0,0.0249,1.0\n"
    "move,0.0041,-0.015,0.0249,0.5\n"
    "button,0,down\n"
    "move,0.0041,-0.050,0.0249,3.5\n"
    "hold,0.5\n"
    "button,0,up\n"
    "hold,60\n";
constexpr double kPlaneZ_m = 0.0249;  // device z = world z (the device origin is above z = 0)

/// A consumer in the display's slot, reading the rig's session from its first event; a producer
/// silent for a minute (a loaded machine) still counts as alive.
auto attach_as_display(test::Rig& rig) {
    return ipc::ConsumerBuilder()
        .segment_name(rig.producer().segment_name())
        .role(ipc::ConsumerRole::kDisplay)
        .from_sequence(0)
        .stale_after_ns(60'000'000'000)
        .attach();
}

struct Seen {
    int begins = 0, progresses = 0, completed = 0, other_ends = 0, refused = 0;
    std::string why;  ///< refusals and other ends, for failure messages
};

void apply(cut::CutSession& session, const ipc::EventRecord& r, Seen& seen) {
    const display::RecordOutcome out = display::apply_record(session, r);
    if (out.report.outcome == cut::EventOutcome::kRefused) {
        ++seen.refused;
        seen.why += std::string("refused type ") + std::to_string(int(r.header.type)) + ": " +
                    out.report.why + "; ";
    }
    if (r.header.type == ipc::EventType::kCutBegin) ++seen.begins;
    if (r.header.type == ipc::EventType::kCutProgress) ++seen.progresses;
    if (r.header.type == ipc::EventType::kCutEnd) {
        if (r.cut.end_reason == ipc::CutEndReason::kCompleted) {
            ++seen.completed;
        } else {
            ++seen.other_ends;
            seen.why += "end reason " + std::to_string(int(r.cut.end_reason)) + "; ";
        }
    }
}

TEST(RtRealBoneCut, KerfRtEventsSawASliceOffTheCalcaneusAndTheReplayMatches) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg("calcaneus");
    auto config = config::load_config(cfg.kerf_toml());
    ASSERT_TRUE(config) << config.error().message();
    auto scene = display::build_scene_mesh(*config);
    ASSERT_TRUE(scene) << scene.error();
    const std::size_t scene_faces = scene->n_faces();

    test::Rig rig({kSliceScript, {}, 100'000, true}, cfg.kerf_toml());
    ASSERT_TRUE(rig.ok()) << rig.error();
    auto consumer = attach_as_display(rig);
    ASSERT_TRUE(consumer) << consumer.error().message();

    cut::CutSession live(std::move(*scene));
    Seen seen_live;
    int ticks_after_end = -1;
    for (int i = 0; i < 20'000 && ticks_after_end < 200; ++i) {
        rig.tick();
        ipc::EventRecord r;
        while (consumer->try_next(r) == ipc::Poll::kEvent) apply(live, r, seen_live);
        if (ticks_after_end >= 0 || seen_live.completed + seen_live.other_ends > 0)
            ++ticks_after_end;
    }
    EXPECT_EQ(seen_live.begins, 1);
    EXPECT_GT(seen_live.progresses, 10);
    EXPECT_EQ(seen_live.completed, 1) << seen_live.why;
    EXPECT_EQ(seen_live.refused, 0) << seen_live.why;
    EXPECT_EQ(live.counters().cuts_completed, 1u);

    // The pieces: the slice beyond the plane and the rest, each a closed surface.
    ASSERT_EQ(live.bodies().size(), 2u);
    cut::testing::expect_closed_2_manifold(live.mesh());
    EXPECT_GT(live.mesh().n_faces(), scene_faces);
    std::vector<double> min_z(2, 1e9), max_z(2, -1e9);
    for (auto v : live.mesh().vertices()) {
        if (live.mesh().is_isolated(v)) continue;
        const std::uint32_t b = live.body_of(v);
        ASSERT_LT(b, 2u);
        const double z = live.mesh().point(v)[2];
        min_z[b] = std::min(min_z[b], z), max_z[b] = std::max(max_z[b], z);
    }
    const int slice = min_z[0] > min_z[1] ? 0 : 1;  // the body beyond the plane
    EXPECT_GT(min_z[slice], kPlaneZ_m - 0.001) << "the slice reaches back through the plane";
    EXPECT_LT(max_z[1 - slice], kPlaneZ_m + 0.001) << "the rest reaches beyond the plane";

    // Replay: the journal alone, applied to a fresh session from the same scene.
    rig.producer().stop();  // flushes the journal
    auto journal = ipc::JournalReader::open(rig.producer().journal_path(), 0);
    ASSERT_TRUE(journal) << journal.error().message();
    auto scene_again = display::build_scene_mesh(*config);
    ASSERT_TRUE(scene_again) << scene_again.error();
    cut::CutSession replay(std::move(*scene_again));
    Seen seen_replay;
    ipc::EventRecord r;
    for (std::uint64_t seq = 0; journal->try_read(seq, r) == ipc::JournalRead::kOk;
         seq = r.header.sequence + 1) {
        apply(replay, r, seen_replay);
    }
    EXPECT_EQ(seen_replay.begins, seen_live.begins);
    EXPECT_EQ(seen_replay.progresses, seen_live.progresses);
    EXPECT_EQ(seen_replay.completed, 1);
    EXPECT_EQ(replay.hash(), live.hash()) << "the display's mesh differs from the replay's";
}

/// What a session produced: the per-tick commanded force, the journal, the display's hash.
struct Session {
    std::vector<firmware_host::Vec3> force;
    std::string journal;
    std::uint64_t hash = 0;
    LoopStats stats;
    Seen seen;
    std::uint64_t reopened_at = 0;  ///< live: the tick the re-opened device was installed
};

/// The journals' records equal one by one (sequence, type, payload; not the time stamps).
::testing::AssertionResult same_events(const std::string& a, const std::string& b) {
    auto ra = ipc::JournalReader::open(a, 0);
    auto rb = ipc::JournalReader::open(b, 0);
    if (!ra || !rb) return ::testing::AssertionFailure() << "a journal did not open";
    if (ra->record_count() != rb->record_count())
        return ::testing::AssertionFailure()
               << ra->record_count() << " events recorded, " << rb->record_count() << " replayed";
    for (std::uint64_t s = 0; s < ra->record_count(); ++s) {
        ipc::EventRecord x{}, y{};
        if (ra->try_read(s, x) != ipc::JournalRead::kOk ||
            rb->try_read(s, y) != ipc::JournalRead::kOk || x.header.type != y.header.type ||
            std::memcmp(reinterpret_cast<const char*>(&x) + sizeof x.header,
                        reinterpret_cast<const char*>(&y) + sizeof y.header,
                        sizeof x - sizeof x.header) != 0)
            return ::testing::AssertionFailure() << "event " << s << " differs";
    }
    return ::testing::AssertionSuccess() << ra->record_count() << " events equal";
}

/// Ticks `rig` `ticks` times (or, when `live`, until the device was unplugged on the way to the
/// bone, re-opened, and the cut after it completed), applying the events to a CutSession of the
/// scene as the display does.
Session run_session(test::Rig& rig, const config::Config& config, bool live, std::uint64_t ticks) {
    Session out;
    auto scene = display::build_scene_mesh(config);
    EXPECT_TRUE(scene) << scene.error();
    auto consumer = attach_as_display(rig);
    EXPECT_TRUE(consumer) << consumer.error().message();
    if (!scene || !consumer) return out;
    cut::CutSession session(std::move(*scene));
    int phase = 0;  // live: 0 approaching, 1 unplugged, 2 replugged, 3 re-opened, 4 cut, 5 done
    std::uint64_t after = 0;
    for (std::uint64_t t = 0; live ? (phase < 5 && t < 30'000) : t < ticks; ++t) {
        rig.tick();
        out.force.push_back(rig.loop().last_force_n());
        ipc::EventRecord r;
        while (consumer->try_next(r) == ipc::Poll::kEvent) apply(session, r, out.seen);
        if (!live) continue;
        const LoopStats& s = rig.loop().stats();
        if (phase == 0 && t == 400) {  // on the way to the bone: unplugged
            EXPECT_TRUE(rig.sim().command("fault unplug on"));
            phase = 1;
        } else if (phase == 1 && s.device_lost_ticks >= 300) {
            EXPECT_TRUE(rig.sim().command("fault unplug off"));
            phase = 2;
        } else if (phase == 2 && s.devices_reopened == 1) {
            phase = 3;
            out.reopened_at = t;
        } else if (phase == 3 && out.seen.completed + out.seen.other_ends > 0) {
            phase = 4;
        } else if (phase == 4 && ++after > 200) {
            phase = 5;
        }
    }
    EXPECT_TRUE(!live || phase == 5) << "stopped in phase " << phase << ": " << out.seen.why;
    // The journal is flushed by stop(); the display's mesh hash once every event is applied.
    rig.producer().stop();
    ipc::EventRecord r;
    while (consumer->try_next(r) == ipc::Poll::kEvent) apply(session, r, out.seen);
    out.journal = rig.producer().journal_path();
    out.hash = session.hash();
    out.stats = rig.loop().stats();
    return out;
}

// Record and replay of a session whose device was unplugged and re-opened (recording format 3,
// recorded from inside the loop). The live run is the slice off the calcaneus (real kerf-hapsim
// in lockstep, the Kerf HID device code, the DeviceReconnector re-opening it on its own thread);
// on the way to the bone the emulator's unplug fault closes the connection, 300 ticks run without
// a device, the replug lets the reconnector open it again, and the hand goes on: the whole cut is
// made with the re-opened device. Every tick is recorded; the replay (ReplayDevice, the same
// loop, world and limits, no emulator) must give the same events, the same force at every tick
// and the same mesh hash. Control: the same recording with its re-open erased (every tick on
// device generation 0, all format 2 could say) diverges: no device, no cut.
TEST(RtRealBoneCut, ARecordedUnplugAndReopenReplaysToTheSameEventsForcesAndHash) {
    if (!test::have_shared_meshes()) GTEST_SKIP() << "no " << test::calcaneus_path();
    test::TempConfig cfg("calcaneus");
    auto config = config::load_config(cfg.kerf_toml());
    ASSERT_TRUE(config) << config.error().message();
    const std::string file = (std::filesystem::temp_directory_path() /
                              ("kerf-reopen-" + std::to_string(getpid()) + ".rec"))
                                 .string();
    Session live;
    {
        auto recorder = InputRecorder::start(file, 1'000'000);
        ASSERT_TRUE(recorder) << recorder.error();
        test::Rig rig({kSliceScript, {}, 100'000, true}, cfg.kerf_toml());
        ASSERT_TRUE(rig.ok()) << rig.error();
        rig.loop().record_to(recorder->get());
        live = run_session(rig, *config, true, 0);
        auto stopped = (*recorder)->stop();
        ASSERT_TRUE(stopped) << stopped.error();
        ASSERT_EQ(*stopped, live.force.size()) << "a tick is missing from the recording";
    }
    EXPECT_EQ(live.stats.devices_lost, 1u);
    EXPECT_EQ(live.stats.devices_reopened, 1u);
    EXPECT_GE(live.stats.device_lost_ticks, 300u);
    EXPECT_EQ(live.seen.begins, 1);
    EXPECT_EQ(live.seen.completed, 1) << live.seen.why;
    EXPECT_EQ(live.seen.refused, 0) << live.seen.why;
    std::uint64_t pushed_after_reopen = 0;  // the re-opened device's ticks are really there
    for (std::size_t t = live.reopened_at; t < live.force.size(); ++t)
        pushed_after_reopen +=
            std::sqrt(live.force[t][0] * live.force[t][0] + live.force[t][1] * live.force[t][1] +
                      live.force[t][2] * live.force[t][2]) > 0.05
                ? 1
                : 0;
    EXPECT_GT(pushed_after_reopen, 100u) << "no force from the re-opened device";

    auto recording = load_recording(file);
    ASSERT_TRUE(recording) << recording.error();
    ASSERT_EQ(recording->version, kRecordingVersion);
    {
        test::RigOptions o;
        o.replay = &*recording;
        test::Rig replay(o, cfg.kerf_toml());
        ASSERT_TRUE(replay.ok()) << replay.error();
        const Session again = run_session(replay, *config, false, recording->inputs.size());
        EXPECT_EQ(again.stats.devices_lost, 1u);
        EXPECT_EQ(again.stats.devices_reopened, 1u);
        EXPECT_EQ(again.stats.device_lost_ticks, live.stats.device_lost_ticks);
        EXPECT_TRUE(same_events(live.journal, again.journal));
        EXPECT_TRUE(again.force == live.force) << "the per-tick forces differ";
        EXPECT_EQ(again.hash, live.hash) << "the replay's mesh differs";
    }
    {  // control: without the recorded re-open the device stays lost and the replay diverges
        Recording erased = *recording;
        for (RecordedInput& r : erased.inputs) r.device_generation = 0;
        test::RigOptions o;
        o.replay = &erased;
        test::Rig replay(o, cfg.kerf_toml());
        ASSERT_TRUE(replay.ok()) << replay.error();
        const Session wrong = run_session(replay, *config, false, erased.inputs.size());
        EXPECT_EQ(wrong.stats.devices_reopened, 0u);
        EXPECT_EQ(wrong.seen.begins, 0);
        EXPECT_FALSE(wrong.force == live.force);
        EXPECT_NE(wrong.hash, live.hash);
    }
    std::filesystem::remove(file);
}

}  // namespace
}  // namespace kerf::rt
