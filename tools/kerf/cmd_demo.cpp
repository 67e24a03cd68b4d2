// `kerf demo` — the README's main job: the simulator end to end, as real processes on one
// shared-memory session. kerf-hapsim plays a scripted surgeon's hand (demo_script.*: a chevron
// osteotomy of the built-in foot's first metatarsal — two limbs fed just past their apex inside
// the bone, each withdrawn along its kerf — then the freed head taken and shifted laterally,
// generated from the scene's geometry and kerf-rt's device -> world mapping), kerf-rt runs the
// 1 kHz loop, cuts and moves the held head (BodyMoved), kerf-display (headless, or --window)
// applies the cuts and the move and publishes the collision mesh. Afterwards the journal kerf-rt
// left is replayed here through CutSession (demo_replay.*): hash, pieces, volumes and the
// pictures (before, mid-cut, after); the display's own hash must equal the replay's.
//
// Everything lives in a temporary work folder (config copy, sockets, journal, logs) that is
// removed at exit; the output folder keeps the pictures, the display's last frame, the hand
// script, the journal, kerf-rt's force trace and report.json. Ctrl-C at any moment: kerf-rt is
// stopped first (its device goes to zero force), then the others; exit status 130.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "config/data_dir.hpp"
#include "config/file_io/file_io.hpp"
#include "config/load_config.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/mesh/foot_generator.hpp"
#include "rt_core/ipc/journal_reader.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/demo_replay.hpp"
#include "tools/kerf/demo_script.hpp"
#include "tools/kerf/recording_dir.hpp"
#include "tools/kerf/session_files.hpp"
#include "tools/supervise/supervisor.hpp"

namespace kerf::cli {
namespace {

namespace fs = std::filesystem;
using supervise::ChildSpec;
using supervise::Policy;
using supervise::Supervisor;

struct DemoOptions {
    std::size_t triangles = 200'000;
    std::uint64_t seed = 1;
    std::string out_dir = "kerf-demo-out";
    std::string config;  ///< kerf.toml to start from; empty: the installed or in-tree one
    bool window = false;
    bool lockstep = false;
    bool json = false;
};

[[noreturn]] void fail(const std::string& what) {
    std::cerr << "kerf demo: " << what << "\n";
    throw CLI::RuntimeError(kExitFailure);
}

/// The shipped kerf.toml: $KERF_DATA_DIR, installed share/kerf or the source tree's config/.
fs::path default_config() { return config::data_file("kerf.toml"); }

/// Copies the configuration into `work`/config with this run's session, journal and scene.
fs::path prepare_config(const DemoOptions& o, const fs::path& work, const std::string& session) {
    const fs::path src = o.config.empty() ? default_config() : fs::path(o.config);
    // Read like every input (regular file only, never blocks): says what a bad path is.
    if (auto read = files::read_regular_file(src, 4u << 20); !read)
        fail("configuration " + read.error().message());
    const fs::path dst = work / "config";
    std::error_code ec;
    fs::copy(src.parent_path(), dst, fs::copy_options::recursive, ec);
    if (ec) fail("copy of " + src.parent_path().string() + ": " + ec.message());
    std::string toml = slurp(dst / src.filename());
    toml = set_key(toml, "session_name", "\"" + session + "\"");
    toml = set_key(toml, "dir", "\"" + (work / "journal").string() + "\"");
    toml = set_key(toml, "scene", "\"builtin_foot\"");
    toml = set_key(toml, "device", "\"simulated\"");
    toml = set_key(toml, "shared", "\"" + (src.parent_path() / "../../shared").string() + "\"");
    if (!write_file(dst / "kerf.toml", toml)) fail("cannot write " + (dst / "kerf.toml").string());
    const fs::path scene = dst / "scenes" / "builtin_foot.toml";
    std::string s = slurp(scene);
    s = set_key(s, "target_triangles", std::to_string(o.triangles));
    s = set_key(s, "seed", std::to_string(o.seed));
    if (!write_file(scene, s)) fail("cannot write " + scene.string());
    return dst / "kerf.toml";
}

/// The device origin kerf-rt uses: above the centre of the scene's bounds, 20 mm over the top.
mesh::Point device_origin(const mesh::TriMesh& scene) {
    mesh::Point lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (const auto v : scene.vertices()) {
        lo.minimize(scene.point(v));
        hi.maximize(scene.point(v));
    }
    return {(lo[0] + hi[0]) / 2, hi[1] + 0.02, (lo[2] + hi[2]) / 2};
}

/// Forces from kerf-rt's trace: peak and mean magnitude over the ticks that commanded one.
struct ForceFigures {
    std::uint64_t ticks = 0, pushing = 0;
    double peak_n = 0, mean_n = 0;
};
ForceFigures read_forces(const fs::path& trace) {
    ForceFigures f;
    std::ifstream in(trace);
    std::string line;
    std::getline(in, line);  // header
    double sum = 0;
    while (std::getline(in, line)) {
        double v[7];
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3],
                        &v[4], &v[5], &v[6]) != 7)
            continue;
        ++f.ticks;
        const double m = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
        if (m > 1e-6) {
            ++f.pushing;
            sum += m;
            f.peak_n = std::max(f.peak_n, m);
        }
    }
    if (f.pushing) f.mean_n = sum / double(f.pushing);
    return f;
}

/// kerf-rt's exit summary (its last lines from "kerf-rt summary").
std::string rt_summary(const std::string& log) {
    const auto at = log.find("kerf-rt summary");
    return at == std::string::npos ? std::string() : log.substr(at);
}

/// Sequence number just after the middle of the first cut's progress events (0: none).
std::uint64_t mid_first_cut(const fs::path& journal) {
    auto reader = ipc::JournalReader::open(journal.string(), 0);
    if (!reader) return 0;
    std::uint64_t begin = 0, end = 0;
    ipc::EventRecord r{};
    for (std::uint64_t s = 0; s < reader->record_count(); ++s) {
        if (reader->try_read(s, r) != ipc::JournalRead::kOk) break;
        if (r.header.type == ipc::EventType::kCutBegin && !begin) begin = s + 1;
        if (r.header.type == ipc::EventType::kCutEnd) {
            end = s;
            break;
        }
    }
    return begin ? (begin + end) / 2 : 0;
}

/// The last step kerf-hapsim's trace (`--trace`) has reached, its first column; 0 before any.
/// In real time that is the hand script's clock: it falls behind the wall clock whenever the
/// emulator is not scheduled for over 10 periods (it drops the periods it missed).
std::uint64_t last_trace_step(const fs::path& trace) {
    std::ifstream f(trace, std::ios::binary | std::ios::ate);
    if (!f) return 0;
    const std::streamoff size = f.tellg();
    f.seekg(std::max<std::streamoff>(0, size - 512));
    const std::string tail{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    const auto end = tail.rfind('\n');  // the last complete row ends here
    if (end == std::string::npos || end == 0) return 0;
    const auto begin = tail.rfind('\n', end - 1);
    if (begin == std::string::npos) return 0;
    return std::strtoull(tail.c_str() + begin + 1, nullptr, 10);
}

void run_demo(const DemoOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    const fs::path bin = supervise::executable_dir();
    for (const char* exe : {"kerf-hapsim", "kerf-rt", "kerf-display"})
        if (access((bin / exe).c_str(), X_OK) != 0)
            fail((bin / exe).string() + ": not found (build it: cmake --build build)");
    const fs::path out = fs::absolute(o.out_dir);
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) fail("output folder " + out.string() + ": " + ec.message());

    Supervisor sup;  // from here on Ctrl-C is a stop request, never an abrupt end
    auto work_dir = WorkDir::create("kerf-demo");
    if (!work_dir) fail(work_dir.error());
    const WorkDir& work = *work_dir;
    const std::string session = "kerf-demo-" + std::to_string(getpid());
    const fs::path toml = prepare_config(o, work.path(), session);
    auto cfg = config::load_config(toml);
    if (!cfg) fail(cfg.error().message());
    auto foot = mesh::generate_foot({o.triangles, o.seed});
    if (!foot) fail("--triangles: " + foot.error());
    auto scene = display::build_scene_mesh(*cfg);
    if (!scene) fail("scene: " + scene.error());
    const mesh::BoneInfo* m2 = nullptr;  // the second metatarsal: the lateral neighbour
    for (const mesh::BoneInfo& b : foot->bones)
        if (b.ray == 2 && b.kind == mesh::BoneKind::kMetatarsal) m2 = &b;
    if (!m2) fail("the built-in foot has no second metatarsal");
    auto script = make_demo_script(foot->first_metatarsal(), *m2, device_origin(*scene));
    if (!script) fail("hand script: " + script.error());
    scene = Err{std::string()};
    const fs::path hand = work.path() / "hand.csv";
    if (!write_file(hand, script->csv)) fail("cannot write " + hand.string());
    const double duration_s = std::ceil(script->duration_s + 1.0);
    if (!o.json) {
        // The limbs' angle is measured on the quantised tilts (29.97 for 30): one decimal.
        std::printf(
            "kerf demo: chevron osteotomy of the first metatarsal (%zu limbs at +-%.1f degrees "
            "to its axis, feed %.1f mm/s), the head shifted %.1f mm laterally; %.0f s of "
            "surgery, %s, work folder %s\n",
            script->tilt_deg.size(), script->half_angle_deg, script->feed_speed_m_s * 1e3,
            script->shift_m.norm() * 1e3, duration_s, o.lockstep ? "lockstep" : "real time",
            work.path().c_str());
        std::fflush(stdout);
    }

    const fs::path sock = work.path() / "hapsim.sock";
    const fs::path status = work.path() / "display.json";
    const fs::path trace = work.path() / "trace.csv";
    const fs::path logs = work.path();
    // A Ctrl-C before or while a process starts is a stop like any other (exit 130), not a
    // failure; the supervisor stops what already runs.
    const auto stopped = [] {
        if (!Supervisor::stop_requested()) return;
        std::cerr << "kerf demo: stopped by signal " << Supervisor::stop_signal() << "\n";
        throw CLI::RuntimeError(130);
    };
    stopped();
    std::vector<std::string> hapsim_args = {
        (bin / "kerf-hapsim").string(),
        "--profile",
        (toml.parent_path() / "devices/simulated.toml").string(),
        "--socket",
        sock.string(),
        "--script",
        hand.string(),
        o.lockstep ? "--lockstep" : "--realtime"};
    // Real time: the surgery lasts until the hand's script is over in the hand's own time (the
    // emulator's trace), not for a wall-clock budget. The emulator drops the periods it misses
    // when not scheduled, so on a loaded machine its script ran seconds behind kerf-rt's
    // --duration, which then ended the session mid-shift (the head moved 0.5-2 mm of 4).
    const fs::path hand_trace = work.path() / "hapsim-trace.csv";
    constexpr double kHapsimPeriod_s = 1e-3;  // kerf-hapsim's default --period-us
    const auto script_steps = std::uint64_t(std::ceil(duration_s / kHapsimPeriod_s));
    if (!o.lockstep) {
        hapsim_args.push_back("--trace");
        hapsim_args.push_back(hand_trace.string());
    }
    auto hapsim =
        sup.add({{"kerf-hapsim", hapsim_args, logs / "hapsim.log", {}}, Policy::kMayFinish},
                [&] { return fs::exists(sock); });
    if (!hapsim) stopped(), fail(hapsim.error().message());
    const std::vector<std::string> display_argv =
        display_args(bin, {toml, session, status, o.window ? "window" : "headless", true,
                           out / "display-last-frame.png"});
    const fs::path display_log = logs / "kerf-display.log";
    auto display = sup.add(
        {{"kerf-display", display_argv, display_log, {}}, Policy::kRestart},
        [&] { return number_after(slurp(status), "\"frames\": ") >= 1; },
        std::chrono::seconds(120));  // scene built, first frame drawn
    if (!display) stopped(), fail(display.error().message());
    // Real time: a cap; the hand's trace ends the surgery (above).
    const double rt_duration_s = o.lockstep ? duration_s : 4 * duration_s;
    std::vector<std::string> rt_args = {(bin / "kerf-rt").string(),
                                        "--config",
                                        toml.string(),
                                        "--device",
                                        "simulated",
                                        "--socket",
                                        sock.string(),
                                        "--session",
                                        session,
                                        "--duration",
                                        std::to_string(rt_duration_s),
                                        "--trace",
                                        trace.string(),
                                        "--record",
                                        (work.path() / "input.rec").string()};
    if (o.lockstep) {  // deterministic: the display's world from the first tick on
        rt_args.push_back("--lockstep");
        rt_args.push_back("--await-display");
    }
    const fs::path rt_log = logs / "kerf-rt.log";
    auto rt = sup.add({{"kerf-rt", rt_args, rt_log, {}}, Policy::kMayFinish},
                      [&] { return slurp(rt_log).find("kerf-rt: session") != std::string::npos; });
    if (!rt) stopped(), fail(rt.error().message() + "\n" + slurp(rt_log));

    // The surgery: until kerf-rt's --duration is over (a stop signal or a crash ends it early).
    double last_print = 0;
    const auto progress = [&](const char* phase) {
        if (o.json || elapsed() - last_print < 1.0) return;
        last_print = elapsed();
        const std::string st = slurp(status);
        std::printf(
            "  %5.1f s  %s: display %s events applied, %s frames\n", elapsed(), phase,
            st.empty() ? "-" : std::to_string(long(number_after(st, "\"applied\": "))).c_str(),
            st.empty() ? "-" : std::to_string(long(number_after(st, "\"frames\": "))).c_str());
        std::fflush(stdout);
    };
    bool rt_stopped = false;
    supervise::RunOutcome outcome = sup.run([&] {
        progress("cutting");
        if (!o.lockstep && !rt_stopped && last_trace_step(hand_trace) >= script_steps) {
            sup.find("kerf-rt")->signal(SIGTERM);  // an orderly end: force zeroed, exit 0
            rt_stopped = true;
        }
        return !sup.find("kerf-rt")->running();
    });
    const auto stop_and_exit = [&](const std::string& why, int code) {
        sup.stop_all();
        std::cerr << "kerf demo: " << why << "\n";
        if (!slurp(rt_log).empty()) std::cerr << "--- kerf-rt log\n" << slurp(rt_log);
        if (code == kExitFailure) std::cerr << "--- kerf-display log\n" << slurp(display_log);
        throw CLI::RuntimeError(code);
    };
    if (outcome.reason == supervise::RunOutcome::Reason::kStopSignal)
        stop_and_exit("stopped by signal " + std::to_string(Supervisor::stop_signal()), 130);
    const auto* rt_exit = &sup.find("kerf-rt")->exit_info();
    if (!*rt_exit || !(*rt_exit)->success())
        stop_and_exit("kerf-rt " + (*rt_exit ? (*rt_exit)->describe() : outcome.detail),
                      kExitFailure);

    // The display catches up with the whole journal, then is stopped (its last frame is saved).
    const fs::path journal = first_file(work.path() / "journal");
    if (journal.empty()) stop_and_exit("kerf-rt left no journal", kExitFailure);
    std::uint64_t events = 0;
    if (auto reader = ipc::JournalReader::open(journal.string(), 0); reader)
        events = reader->record_count();
    std::string display_hash;
    const double catch_up_from = elapsed();
    outcome = sup.run([&] {
        progress("display catching up");
        if (elapsed() - catch_up_from > 300) return true;  // reported below
        const std::string st = slurp(status);
        if (st.empty() || number_after(st, "\"applied\": ") < 0) return false;
        const bool caught_up = number_after(st, "\"next_sequence\": ") >= double(events) &&
                               st.find("\"hash_valid\": true") != std::string::npos &&
                               number_after(st, "\"hash_sequence\": ") >= double(events);
        if (caught_up) display_hash = json_string(st, "hash");
        return caught_up;
    });
    if (outcome.reason == supervise::RunOutcome::Reason::kStopSignal)
        stop_and_exit("stopped by signal " + std::to_string(Supervisor::stop_signal()), 130);
    if (display_hash.empty())
        stop_and_exit("kerf-display did not apply the journal's " + std::to_string(events) +
                          " events within 300 s",
                      kExitFailure);
    sup.stop_all();
    const int display_restarts = sup.restarts("kerf-display");

    // The replay here: hash, pieces, pictures.
    const std::uint64_t mid = mid_first_cut(journal);
    auto replay = replay_journal(*cfg, journal,
                                 {{0, out / "1-before.png", "before"},
                                  {mid, out / "2-mid-cut.png", "mid-cut (first limb)"},
                                  {~0ull, out / "3-after.png", "after"}},
                                 script->apex_world_m);
    if (!replay) fail("replay of " + journal.string() + ": " + replay.error());
    fs::copy_file(journal, out / "session.journal", fs::copy_options::overwrite_existing, ec);
    fs::copy_file(hand, out / "hand.csv", fs::copy_options::overwrite_existing, ec);
    fs::copy_file(trace, out / "force-trace.csv", fs::copy_options::overwrite_existing, ec);
    fs::copy_file(rt_log, out / "kerf-rt.log", fs::copy_options::overwrite_existing, ec);
    fs::copy_file(display_log, out / "kerf-display.log", fs::copy_options::overwrite_existing, ec);

    const std::string rt_text = rt_summary(slurp(rt_log));
    // The recording `kerf replay OUT/recording` re-runs (recording_dir.hpp).
    const nlohmann::json recording_meta = {
        {"source", "kerf demo"},
        {"device", "simulated"},
        {"lockstep", o.lockstep},
        {"ticks", std::uint64_t(std::max(0.0, number_after(rt_text, "ticks ")))},
        {"events", replay->events},
        {"hash", hash_hex(replay->hash)}};
    if (auto saved = save_recording(out / "recording", work.path() / "config",
                                    work.path() / "input.rec", journal, trace, recording_meta);
        !saved)
        fail(saved.error());
    const ForceFigures forces = read_forces(trace);
    const bool hashes_equal = display_hash == hash_hex(replay->hash);
    nlohmann::json pieces_mm3 = nlohmann::json::array();
    nlohmann::json pieces = nlohmann::json::array();
    for (const ReplayPiece& p : replay->pieces) {
        pieces_mm3.push_back(p.volume_m3 * 1e9);
        pieces.push_back({{"body", p.body},
                          {"parent", p.parent == 0xFFFFFFFFu ? -1 : std::int64_t(p.parent)},
                          {"severed_by_cut", p.severed_by_cut},
                          {"volume_mm3", p.volume_m3 * 1e9},
                          {"position_mm",
                           {p.position_m[0] * 1e3, p.position_m[1] * 1e3, p.position_m[2] * 1e3}}});
    }
    const nlohmann::json report = {
        {"lockstep", o.lockstep},
        {"triangles", o.triangles},
        {"seed", o.seed},
        {"surgery_s", duration_s},
        {"ticks", number_after(rt_text, "ticks ")},
        {"overruns", number_after(rt_text, "overruns ")},
        {"late_wakes", number_after(rt_text, "late wakes ")},
        {"safe_state_entries", number_after(rt_text, "safe-state entries ")},
        {"wake_p99_us", number_after(rt_text, "p99 ")},
        {"events", replay->events},
        {"cut_begins", replay->cut_begins},
        {"cut_progress", replay->cut_progress},
        {"cuts_completed", replay->cut_ends_completed},
        {"cuts_ended_otherwise", replay->cut_ends_other},
        {"body_moves", replay->body_moves},
        {"bodies_before", replay->bodies_before},
        {"bodies_after", replay->bodies_after},
        {"applied", replay->applied},
        {"refused", replay->refused},
        {"force_peak_n", forces.peak_n},
        {"force_mean_n", forces.mean_n},
        {"force_ticks", forces.pushing},
        {"display_restarts", display_restarts},
        {"pieces_mm3", pieces_mm3},
        {"pieces", pieces},
        {"hash", hash_hex(replay->hash)},
        {"display_hash", display_hash},
        {"hashes_equal", hashes_equal},
        {"out", out.string()},
        {"config", (o.config.empty() ? default_config() : fs::path(o.config)).string()}};
    const std::string js = report.dump();
    write_file(out / "report.json", js + "\n");
    if (o.json) {
        std::cout << js << "\n";
    } else {
        std::printf("kerf demo: done in %.1f s\n", elapsed());
        std::printf("  loop:    %s", rt_text.empty() ? "(no kerf-rt summary)\n" : rt_text.c_str());
        std::printf(
            "  events:  %llu (%llu cut begins, %llu progress, %llu cuts completed, %llu "
            "ended otherwise, %llu body moves); replay applied %llu, refused %llu\n",
            (unsigned long long)replay->events, (unsigned long long)replay->cut_begins,
            (unsigned long long)replay->cut_progress,
            (unsigned long long)replay->cut_ends_completed,
            (unsigned long long)replay->cut_ends_other, (unsigned long long)replay->body_moves,
            (unsigned long long)replay->applied, (unsigned long long)replay->refused);
        std::printf("  forces:  peak %.2f N, mean %.2f N over %llu of %llu ticks\n", forces.peak_n,
                    forces.mean_n, (unsigned long long)forces.pushing,
                    (unsigned long long)forces.ticks);
        std::printf("  bodies:  %zu -> %zu\n  pieces:  ", replay->bodies_before,
                    replay->bodies_after);
        for (const ReplayPiece& p : replay->pieces) {
            std::printf("body %u %.1f mm^3", p.body, p.volume_m3 * 1e9);
            if (p.severed_by_cut) std::printf(" (severed by cut %u)", p.severed_by_cut);
            const double moved_mm =
                std::sqrt(p.position_m[0] * p.position_m[0] + p.position_m[1] * p.position_m[1] +
                          p.position_m[2] * p.position_m[2]) *
                1e3;
            if (moved_mm > 0)
                std::printf(" moved (%.2f %.2f %.2f) mm", p.position_m[0] * 1e3,
                            p.position_m[1] * 1e3, p.position_m[2] * 1e3);
            std::printf("   ");
        }
        std::printf("\n  hash:    %s (journal replay), display %s: %s\n",
                    hash_hex(replay->hash).c_str(), display_hash.c_str(),
                    hashes_equal ? "equal" : "DIFFERENT");
        std::printf(
            "  output:  %s (1-before.png 2-mid-cut.png 3-after.png, report.json, "
            "session.journal, hand.csv, recording/ for kerf replay)\n",
            out.string().c_str());
    }
    if (!hashes_equal) throw CLI::RuntimeError(kExitFailure);
}

}  // namespace

void add_demo_command(CLI::App& app) {
    auto opts = std::make_shared<DemoOptions>();
    CLI::App* demo = app.add_subcommand(
        "demo",
        "The main job: kerf-hapsim's scripted hand cuts a chevron osteotomy of the first "
        "metatarsal through kerf-rt and shifts the freed head while kerf-display shows it; "
        "pictures and a report");
    demo->add_option("--triangles", opts->triangles, "approximate triangle count of the foot")
        ->capture_default_str()
        ->check(CLI::Range(std::size_t{10'000}, std::size_t{4'000'000}));
    demo->add_option("--seed", opts->seed, "foot generator seed")->capture_default_str();
    demo->add_option("-o,--out", opts->out_dir, "output folder")->capture_default_str();
    demo->add_option("--config", opts->config, "kerf.toml to start from")->check(CLI::ExistingFile);
    demo->add_flag("--window", opts->window, "show kerf-display in a window (X11)");
    demo->add_flag("--lockstep", opts->lockstep,
                   "kerf-rt paced by the emulator: deterministic (same hash every run)");
    demo->add_flag("--json", opts->json, "print report.json instead of text");
    demo->callback([opts] { run_demo(*opts); });
}

}  // namespace kerf::cli
