// `kerf replay DIR` — re-runs a recorded session (recording_dir.hpp): kerf-rt replays the
// recorded device input in lockstep (kerf-rt --replay: the same reads at the same ticks, the
// collision worlds swapped at the recorded ticks) while kerf-display (headless; or, with
// --no-display, the display's own cutting code in this process) applies the events and
// publishes the collision meshes. Then it compares with the recording: the event stream record
// by record, kerf-rt's per-tick force trace byte for byte, and the final mesh hash. Exit 0 only
// when all three are equal.
#include <unistd.h>

#include <chrono>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "config/load_config.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/app/session_follower.hpp"
#include "rt_core/ipc/journal_reader.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/demo_replay.hpp"
#include "tools/kerf/recording_dir.hpp"
#include "tools/kerf/session_files.hpp"
#include "tools/supervise/supervisor.hpp"

namespace kerf::cli {
namespace {

namespace fs = std::filesystem;
using supervise::Policy;
using supervise::Supervisor;

struct ReplayOptions {
    std::string dir;
    bool no_display = false;
    bool json = false;
};

[[noreturn]] void fail(const std::string& what, int code = kExitFailure) {
    std::cerr << "kerf replay: " << what << "\n";
    throw CLI::RuntimeError(code);
}

void run_replay(const ReplayOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path dir = fs::absolute(o.dir);
    auto meta = load_recording_meta(dir);
    if (!meta) fail(meta.error());
    const std::uint64_t recorded_events = (*meta)["events"].get<std::uint64_t>();
    const fs::path bin = supervise::executable_dir();
    for (const char* exe : {"kerf-rt", "kerf-display"})
        if (access((bin / exe).c_str(), X_OK) != 0 &&
            (!o.no_display || std::string(exe) == "kerf-rt"))
            fail((bin / exe).string() + ": not found (build it: cmake --build build)");

    Supervisor sup;  // Ctrl-C: a stop request, kerf-rt stopped first
    auto work_dir = WorkDir::create("kerf-replay");
    if (!work_dir) fail(work_dir.error());
    const fs::path work = work_dir->path();
    const std::string session = "kerf-replay-" + std::to_string(getpid());
    std::error_code ec;
    fs::copy(dir / "config", work / "config", fs::copy_options::recursive, ec);
    if (ec) fail("copy of " + (dir / "config").string() + ": " + ec.message());
    const fs::path toml = work / "config" / "kerf.toml";
    std::string text = slurp(toml);
    text = set_key(text, "session_name", "\"" + session + "\"");
    text = set_key(text, "dir", "\"" + (work / "journal").string() + "\"");
    if (fs::is_directory(dir / "shared"))  // the recorded scene's shared meshes
        text = set_key(text, "shared", "\"" + (dir / "shared").string() + "\"");
    if (!write_file(toml, text)) fail("cannot write " + toml.string());
    auto cfg = config::load_config(toml);
    if (!cfg) fail(cfg.error().message());

    const fs::path status = work / "display.json", display_log = work / "kerf-display.log";
    std::unique_ptr<display::SessionFollower> follower;
    if (o.no_display) {
        display::FollowerOptions fo;
        fo.segment_name = session;
        fo.hash_at_sequence = recorded_events;
        auto started = display::SessionFollower::start(
            fo, [&] { return display::build_scene_mesh(*cfg); },
            [](const cut::CutSession&, const cut::SessionChanges&, std::uint64_t) {});
        if (!started) fail("session follower: " + started.error());
        follower = std::move(*started);
    } else {
        const std::vector<std::string> args =
            display_args(bin, {toml, session, status, "headless", true, {}});
        auto display = sup.add(
            {{"kerf-display", args, display_log, {}}, Policy::kRestart},
            [&] { return number_after(slurp(status), "\"frames\": ") >= 1; },
            std::chrono::seconds(120));
        if (!display) fail(display.error().message());
    }
    const fs::path trace = work / "trace.csv", rt_log = work / "kerf-rt.log";
    std::vector<std::string> rt_args = {
        (bin / "kerf-rt").string(),           "--config",  toml.string(), "--device",
        (*meta)["device"].get<std::string>(), "--session", session,       "--replay",
        (dir / "input.rec").string(),         "--trace",   trace.string()};
    auto rt = sup.add({{"kerf-rt", rt_args, rt_log, {}}, Policy::kMayFinish},
                      [&] { return slurp(rt_log).find("kerf-rt: session") != std::string::npos; });
    if (!rt) fail(rt.error().message() + "\n" + slurp(rt_log));
    auto outcome = sup.run([&] { return !sup.find("kerf-rt")->running(); });
    const auto stop_and_fail = [&](const std::string& why, int code) {
        sup.stop_all();
        fail(why + "\n--- kerf-rt log\n" + slurp(rt_log), code);
    };
    if (outcome.reason == supervise::RunOutcome::Reason::kStopSignal)
        stop_and_fail("stopped by signal " + std::to_string(Supervisor::stop_signal()), 130);
    const auto& rt_exit = sup.find("kerf-rt")->exit_info();
    if (!rt_exit || !rt_exit->success())
        stop_and_fail("kerf-rt " + (rt_exit ? rt_exit->describe() : outcome.detail), kExitFailure);

    const fs::path journal = first_file(work / "journal");
    if (journal.empty()) stop_and_fail("kerf-rt left no journal", kExitFailure);
    std::uint64_t events = 0;
    if (auto reader = ipc::JournalReader::open(journal.string(), 0); reader)
        events = reader->record_count();
    // The display (or the follower) applies every event; its hash is the replay's mesh hash.
    std::string hash;
    const auto catch_up_start = std::chrono::steady_clock::now();
    outcome = sup.run([&] {
        if (std::chrono::steady_clock::now() - catch_up_start > std::chrono::seconds(300))
            return true;
        if (follower) {
            const display::FollowerStatus s = follower->status();
            if (s.next_sequence >= events && s.hash_valid && s.hash_sequence >= events)
                hash = hash_hex(s.hash);
            return !hash.empty() || (s.next_sequence >= events && events != recorded_events);
        }
        const std::string st = slurp(status);
        if (number_after(st, "\"next_sequence\": ") >= double(events) &&
            st.find("\"hash_valid\": true") != std::string::npos &&
            number_after(st, "\"hash_sequence\": ") >= double(events))
            hash = json_string(st, "hash");
        return !hash.empty();
    });
    if (outcome.reason == supervise::RunOutcome::Reason::kStopSignal)
        stop_and_fail("stopped by signal " + std::to_string(Supervisor::stop_signal()), 130);
    sup.stop_all();
    if (follower) follower->stop();
    // Without a display and with a different event count the follower never hashes: the
    // journal replay gives the hash (the same CutSession code).
    if (hash.empty()) {
        auto replayed = replay_journal(*cfg, journal, {});
        if (!replayed) fail("replay of " + journal.string() + ": " + replayed.error());
        hash = hash_hex(replayed->hash);
    }

    auto events_cmp = compare_journals(dir / "session.journal", journal);
    if (!events_cmp) fail(events_cmp.error());
    const bool have_trace = fs::is_regular_file(dir / "force-trace.csv");
    const bool trace_equal = have_trace && slurp(dir / "force-trace.csv") == slurp(trace);
    const std::string recorded_hash = (*meta)["hash"].get<std::string>();
    const std::string rt_text = slurp(rt_log);
    const nlohmann::json report = {
        {"recording", dir.string()},
        {"display", o.no_display ? "none (in-process follower)" : "kerf-display headless"},
        {"ticks", std::uint64_t(std::max(0.0, number_after(rt_text, "kerf-rt summary: ticks ")))},
        {"recorded_ticks", (*meta)["ticks"]},
        {"worlds_not_ready",
         std::uint64_t(std::max(0.0, number_after(rt_text, "worlds not ready in time ")))},
        {"events", events_cmp->records_b},
        {"recorded_events", events_cmp->records_a},
        {"events_equal", events_cmp->equal},
        {"first_event_difference", events_cmp->first_difference},
        {"trace_compared", have_trace},
        {"trace_equal", trace_equal},
        {"hash", hash},
        {"recorded_hash", recorded_hash},
        {"hash_equal", hash == recorded_hash},
        {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
    const bool ok = events_cmp->equal && (!have_trace || trace_equal) && hash == recorded_hash;
    if (o.json) {
        std::cout << report.dump() << "\n";
    } else {
        std::cout << "kerf replay: " << dir.string() << " (" << report["display"].get<std::string>()
                  << ")\n  ticks:   " << report["ticks"] << " of " << report["recorded_ticks"]
                  << " recorded\n  events:  " << events_cmp->records_b << " (recorded "
                  << events_cmp->records_a << "): "
                  << (events_cmp->equal ? std::string("equal")
                                        : "DIFFERENT from sequence " +
                                              std::to_string(events_cmp->first_difference))
                  << "\n  forces:  "
                  << (have_trace ? (trace_equal ? "per-tick trace equal" : "trace DIFFERENT")
                                 : "no recorded trace")
                  << "\n  hash:    " << hash << " (recorded " << recorded_hash
                  << "): " << (hash == recorded_hash ? "equal" : "DIFFERENT") << "\n";
    }
    if (!ok) throw CLI::RuntimeError(kExitFailure);
}

}  // namespace

void add_replay_command(CLI::App& app) {
    auto opts = std::make_shared<ReplayOptions>();
    CLI::App* replay = app.add_subcommand(
        "replay",
        "Re-run a recorded session (kerf demo's recording/, kerf run --record DIR) in lockstep "
        "and check the events, forces and mesh hash are the recorded ones, bit for bit");
    replay->add_option("dir", opts->dir, "recording folder")
        ->required()
        ->check(CLI::ExistingDirectory);
    replay->add_flag("--no-display", opts->no_display,
                     "no kerf-display: this process applies the events (same cutting code)");
    replay->add_flag("--json", opts->json, "print the comparison as one JSON document");
    replay->callback([opts] { run_replay(*opts); });
}

}  // namespace kerf::cli
