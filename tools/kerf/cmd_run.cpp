// `kerf run` — the long-running form a kiosk uses: starts and supervises the simulator's
// processes from kerf.toml until SIGTERM (or --duration):
//
//   kerf-hapsim   only when the configured device is the emulator (a real device otherwise)
//   kerf-display  restarted (1 s back-off, doubling to 8 s) whenever it dies; kerf-rt never
//                 restarts because of it and keeps the force safe (the display owns no force)
//   kerf-rt       essential: if it ends, everything stops and kerf run fails
//
// At start it removes what dead sessions left (session sockets nobody listens on, work folders
// of kerf runs whose process is gone) and prunes the journal folder to [journal] max_files /
// max_total_mb (oldest first; the running session's journal is never removed), again every 30 s
// and at exit. The journal goes to disk: when [journal] dir is in RAM (tmpfs), a folder on disk
// is used instead and named. SIGTERM: kerf-rt is stopped first (zero force), then the display
// and the emulator; exit 0 with nothing left behind. --record DIR keeps the device input stream,
// the journal and the config for `kerf replay DIR`.
#include <linux/magic.h>
#include <sys/statfs.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/data_dir.hpp"
#include "config/load_config.hpp"
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

struct RunOptions {
    std::string config;       ///< empty: config::data_file("kerf.toml")
    std::string device;       ///< empty: kerf.toml's; simulated | falcon | hid[:SERIAL]
    std::string session;      ///< empty: kerf.toml's [shm] session_name
    std::string journal_dir;  ///< empty: kerf.toml's [journal] dir (if on disk)
    std::string script;       ///< emulator only: a hand script to play
    std::string record_dir;   ///< keep a recording for kerf replay
    double duration_s = 0;    ///< 0: until SIGTERM / SIGINT
    bool window = false;
};

[[noreturn]] void fail(const std::string& what, int code = kExitFailure) {
    std::cerr << "kerf run: " << what << "\n";
    throw CLI::RuntimeError(code);
}

void say(const std::string& what) { std::cout << "kerf run: " << what << std::endl; }

bool in_ram(const fs::path& dir) {
    struct statfs s {};
    for (fs::path p = dir; !p.empty(); p = p.parent_path()) {
        if (statfs(p.c_str(), &s) == 0) return s.f_type == TMPFS_MAGIC || s.f_type == RAMFS_MAGIC;
        if (p == p.parent_path()) break;
    }
    return false;
}

/// A folder on disk for journals: $XDG_STATE_HOME/kerf/journal, ~/.local/state/kerf/journal,
/// or /var/lib/kerf/journal.
fs::path disk_journal_dir() {
    if (const char* s = std::getenv("XDG_STATE_HOME"); s && s[0] == '/')
        return fs::path(s) / "kerf" / "journal";
    if (const char* h = std::getenv("HOME"); h && h[0] == '/' && std::string(h) != "/")
        return fs::path(h) / ".local" / "state" / "kerf" / "journal";
    return "/var/lib/kerf/journal";
}

/// Work folders /tmp/kerf-run-PID-* of kerf runs whose process is gone.
std::vector<fs::path> remove_stale_work_dirs() {
    std::vector<fs::path> removed;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::temp_directory_path(), ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("kerf-run-", 0) != 0 || !e.is_directory()) continue;
        const long pid = std::strtol(name.c_str() + 9, nullptr, 10);
        if (pid <= 0 || pid == getpid() || fs::exists("/proc/" + std::to_string(pid))) continue;
        fs::remove_all(e.path(), ec);
        if (!ec) removed.push_back(e.path());
    }
    return removed;
}

/// The `kerf-rt --device` value for the configured (or given) device.
std::string device_arg(const RunOptions& o, const config::Config& cfg) {
    if (!o.device.empty()) return o.device;
    switch (cfg.device.kind) {
        case config::DeviceKind::kSimulated:
            return "simulated";
        case config::DeviceKind::kFalcon:
            return "falcon";
        case config::DeviceKind::kKerfHid:
            return "hid";
    }
    return "simulated";
}

void run_kiosk(const RunOptions& o) {
    const fs::path bin = supervise::executable_dir();
    for (const char* exe : {"kerf-hapsim", "kerf-rt", "kerf-display"})
        if (access((bin / exe).c_str(), X_OK) != 0)
            fail((bin / exe).string() + ": not found (build it: cmake --build build)");
    const fs::path src = o.config.empty() ? config::data_file("kerf.toml") : fs::path(o.config);
    auto base = config::load_config(src);
    if (!base) fail(base.error().message());
    const std::string session = o.session.empty() ? base->main.shm.session_name : o.session;
    const std::string device = device_arg(o, *base);

    Supervisor sup;  // from here SIGTERM / SIGINT are stop requests
    for (const std::string& name : remove_stale_sessions())
        say("removed stale session " + name + " (its kerf-rt had died)");
    for (const fs::path& dir : remove_stale_work_dirs())
        say("removed the work folder of a dead kerf run: " + dir.string());

    fs::path journal_dir = o.journal_dir.empty() ? base->journal_dir : fs::path(o.journal_dir);
    if (in_ram(journal_dir)) {
        const fs::path disk = disk_journal_dir();
        say("journal folder " + journal_dir.string() + " is in RAM (tmpfs): using " +
            disk.string());
        journal_dir = disk;
    }
    std::error_code ec;
    fs::create_directories(journal_dir, ec);
    if (ec) fail("journal folder " + journal_dir.string() + ": " + ec.message());
    journal_dir = fs::canonical(journal_dir, ec);
    const auto started = fs::file_time_type::clock::now() - std::chrono::seconds(1);
    const JournalBound bound{base->main.journal.max_files,
                             std::uint64_t(base->main.journal.max_total_mb) << 20};
    const auto prune = [&] {
        const JournalPrune p = prune_journals(journal_dir, bound, started);
        if (p.removed) say("journal: removed " + std::to_string(p.removed) + " old journals");
    };
    prune();

    auto work_dir = WorkDir::create("kerf-run");
    if (!work_dir) fail(work_dir.error());
    const fs::path work = work_dir->path();
    fs::copy(src.parent_path(), work / "config", fs::copy_options::recursive, ec);
    if (ec) fail("copy of " + src.parent_path().string() + ": " + ec.message());
    const fs::path toml = work / "config" / "kerf.toml";
    std::string text = slurp(work / "config" / src.filename());
    text = set_key(text, "session_name", "\"" + session + "\"");
    text = set_key(text, "dir", "\"" + journal_dir.string() + "\"");
    text =
        set_key(text, "shared", "\"" + (src.parent_path() / base->main.shared_dir).string() + "\"");
    if (!write_file(toml, text)) fail("cannot write " + toml.string());
    auto cfg = config::load_config(toml);
    if (!cfg) fail(cfg.error().message());

    const fs::path sock = work / "hapsim.sock", status = work / "display.json";
    const bool simulated = device == "simulated";
    if (simulated) {
        std::vector<std::string> args = {
            (bin / "kerf-hapsim").string(),
            "--profile",
            (work / "config/devices" / (cfg->main.profiles.device + ".toml")).string(),
            "--socket",
            sock.string(),
            "--realtime"};
        if (!o.script.empty())
            args.insert(args.end(), {"--script", fs::absolute(o.script).string()});
        auto h = sup.add({{"kerf-hapsim", args, work / "kerf-hapsim.log", {}}, Policy::kEssential},
                         [&] { return fs::exists(sock); });
        if (!h) fail(h.error().message());
    }
    // The display mode is kerf.toml's (a kiosk's KMS) unless --window; no hash: a kiosk runs for
    // days and the hash is for tests.
    const std::vector<std::string> display_argv =
        display_args(bin, {toml, session, status, o.window ? "window" : "", false, {}});
    const fs::path display_log = work / "kerf-display.log";
    auto display = sup.add(
        {{"kerf-display", display_argv, display_log, {}}, Policy::kRestart},
        [&] { return number_after(slurp(status), "\"frames\": ") >= 1; },
        std::chrono::seconds(120));
    if (!display) fail(display.error().message() + "\n" + slurp(display_log));
    const fs::path rt_log = work / "kerf-rt.log", input = work / "input.rec",
                   trace = work / "trace.csv";
    std::vector<std::string> rt_args = {(bin / "kerf-rt").string(),
                                        "--config",
                                        toml.string(),
                                        "--device",
                                        device,
                                        "--session",
                                        session};
    if (simulated) rt_args.insert(rt_args.end(), {"--socket", sock.string()});
    if (o.duration_s > 0)
        rt_args.insert(rt_args.end(), {"--duration", std::to_string(o.duration_s)});
    if (!o.record_dir.empty()) {
        rt_args.insert(rt_args.end(), {"--record", input.string()});
        if (o.duration_s > 0) rt_args.insert(rt_args.end(), {"--trace", trace.string()});
    }
    auto rt = sup.add({{"kerf-rt", rt_args, rt_log, {}},
                       o.duration_s > 0 ? Policy::kMayFinish : Policy::kEssential},
                      [&] { return slurp(rt_log).find("kerf-rt: session") != std::string::npos; });
    if (!rt) fail(rt.error().message() + "\n" + slurp(rt_log));
    say("running: session " + session + ", device " + device + ", journal " + journal_dir.string() +
        " (pids: kerf-rt " + std::to_string((*rt)->pid()) + ", kerf-display " +
        std::to_string(sup.find("kerf-display")->pid()) + ")");

    auto last_prune = std::chrono::steady_clock::now();
    const auto outcome = sup.run(
        [&] {
            if (std::chrono::steady_clock::now() - last_prune > std::chrono::seconds(30)) {
                prune();
                last_prune = std::chrono::steady_clock::now();
            }
            return !sup.find("kerf-rt")->running();
        },
        [&](const std::string& name, int count) {
            say(name + " restarted (" + std::to_string(count) + "); kerf-rt pid " +
                std::to_string(sup.find("kerf-rt")->pid()) + " still running");
        });
    sup.stop_all();  // reverse start order: kerf-rt first (zero force), display, emulator
    const auto& rt_exit = sup.find("kerf-rt")->exit_info();
    const std::string rt_text = slurp(rt_log);
    if (const auto at = rt_text.find("kerf-rt summary"); at != std::string::npos)
        std::cout << rt_text.substr(at) << std::flush;
    int code = kExitOk;
    if (outcome.reason == supervise::RunOutcome::Reason::kStopSignal) {
        say("stopped by signal " + std::to_string(Supervisor::stop_signal()));
        code = Supervisor::stop_signal() == SIGTERM ? kExitOk : 128 + Supervisor::stop_signal();
    } else if (!rt_exit || !rt_exit->success()) {
        std::cerr << "kerf run: kerf-rt " << (rt_exit ? rt_exit->describe() : outcome.detail)
                  << "\n--- kerf-rt log\n"
                  << rt_text;
        code = kExitFailure;
    }
    if (!o.record_dir.empty() && code != kExitFailure) {
        fs::path journal;
        for (const auto& e : fs::directory_iterator(journal_dir, ec))
            if (e.is_regular_file() && e.path().extension() == ".kjournal" &&
                e.last_write_time() >= started &&
                (journal.empty() || e.last_write_time() > fs::last_write_time(journal)))
                journal = e.path();
        auto replayed = journal.empty()
                            ? Result<ReplayResult, std::string>(Err{std::string("no journal")})
                            : replay_journal(*cfg, journal, {});
        if (!replayed) fail("recording: " + replayed.error());
        const nlohmann::json meta = {
            {"source", "kerf run"},
            {"device", device},
            {"lockstep", false},
            {"ticks",
             std::uint64_t(std::max(0.0, number_after(rt_text, "kerf-rt summary: ticks ")))},
            {"events", replayed->events},
            {"hash", hash_hex(replayed->hash)}};
        if (auto saved = save_recording(o.record_dir, work / "config", input, journal, trace, meta);
            !saved)
            fail(saved.error());
        say("recorded into " + o.record_dir + " (kerf replay " + o.record_dir + ")");
        if (!fs::exists(input))
            say("warning: the recording is incomplete, kerf-rt left no input stream (it did not "
                "exit on its own: killed?), so it cannot be replayed");
        else if (const std::string gap = recording_gap(input, meta["ticks"].get<std::uint64_t>());
                 !gap.empty())
            say("warning: the recording is incomplete, " + gap);
    }
    prune();
    if (code != kExitOk) throw CLI::RuntimeError(code);
}

}  // namespace

void add_run_command(CLI::App& app) {
    auto opts = std::make_shared<RunOptions>();
    CLI::App* run = app.add_subcommand(
        "run",
        "The kiosk form: supervise kerf-rt, kerf-display (restarted if it dies) and the device "
        "or emulator from kerf.toml until SIGTERM");
    run->add_option("--config", opts->config, "kerf.toml (default: the installed or in-tree one)")
        ->check(CLI::ExistingFile);
    run->add_option("--device", opts->device,
                    "simulated | falcon | hid[:SERIAL] (default: kerf.toml)");
    run->add_option("--session", opts->session, "session name (default: kerf.toml [shm])");
    run->add_option("--journal-dir", opts->journal_dir,
                    "journal folder (default: kerf.toml [journal])");
    run->add_option("--script", opts->script, "emulator: a hand script to play")
        ->check(CLI::ExistingFile);
    run->add_option("--record", opts->record_dir, "keep a recording in this folder (kerf replay)");
    run->add_option("--duration", opts->duration_s, "stop after this many seconds (0: on SIGTERM)")
        ->check(CLI::Range(0.0, 1e7));
    run->add_flag("--window", opts->window, "kerf-display in a window (X11)");
    run->callback([opts] { run_kiosk(*opts); });
}

}  // namespace kerf::cli
