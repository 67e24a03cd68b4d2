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

#include <algorithm>
#include <string>
#include <vector>

#include "config/load_config.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/app/session_events_ipc.hpp"
#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/journal_reader.hpp"
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
    auto consumer = ipc::ConsumerBuilder()
                        .segment_name(rig.producer().segment_name())
                        .role(ipc::ConsumerRole::kDisplay)
                        .from_sequence(0)
                        .stale_after_ns(60'000'000'000)
                        .attach();
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

}  // namespace
}  // namespace kerf::rt
