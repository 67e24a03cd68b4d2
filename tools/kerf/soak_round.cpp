#include "tools/kerf/soak_round.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "config/file_io/file_io.hpp"
#include "config/load_config.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/mesh/foot_generator.hpp"
#include "rt_core/ipc/journal_reader.hpp"
#include "tools/kerf/demo_replay.hpp"
#include "tools/kerf/session_files.hpp"
#include "tools/kerf/soak_scribbler.hpp"
#include "tools/supervise/supervisor.hpp"

namespace kerf::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using supervise::Policy;
using supervise::Supervisor;

std::uint64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::uint64_t(ts.tv_sec) * 1'000'000'000ull + std::uint64_t(ts.tv_nsec);
}

/// The round's configuration: a copy of the shipped one with this round's session, journal and
/// scene. Returns the kerf.toml to use.
Result<fs::path, std::string> prepare_config(const RoundSpec& s, const std::string& session,
                                             const std::optional<mesh::Point>& centre) {
    const fs::path dst = s.work / "config";
    std::error_code ec;
    if (!fs::exists(dst)) fs::copy(s.config.parent_path(), dst, fs::copy_options::recursive, ec);
    if (ec) return Err{"copy of " + s.config.parent_path().string() + ": " + ec.message()};
    const bool foot = s.scene == "builtin_foot";
    std::string toml = slurp(s.config);
    toml = set_key(toml, "session_name", "\"" + session + "\"");
    toml = set_key(toml, "dir", "\"" + (s.work / "journal").string() + "\"");
    toml = set_key(toml, "scene", foot ? "\"builtin_foot\"" : "\"soak_mesh\"");
    toml = set_key(toml, "device", "\"simulated\"");
    toml = set_key(toml, "shared", "\"" + s.work.string() + "\"");
    std::string scene;
    if (foot) {
        scene = slurp(dst / "scenes" / "builtin_foot.toml");
        scene = set_key(scene, "target_triangles", std::to_string(s.triangles));
        scene = set_key(scene, "seed", std::to_string(s.seed));
    } else {
        const mesh::Point c = centre.value_or(mesh::Point{0, 0, 0});
        char t[160];
        std::snprintf(t, sizeof t, "[%.6f, %.6f, %.6f]", -c[0], -c[1], -c[2]);
        scene = "name = \"soak_mesh\"\ndescription = \"kerf soak: " + s.scene +
                "\"\n[[bodies]]\nname = \"bone\"\nmaterial = \"cortical\"\n[bodies.mesh]\n"
                "source = \"file\"\npath = \"" +
                s.scene + "\"\nunits = \"mm\"\n[bodies.transform]\ntranslation_m = " + t +
                "\nrotation_quaternion_wxyz = [1.0, 0.0, 0.0, 0.0]\n";
    }
    files::AtomicFileSet out;
    out.add(dst / "kerf.toml", toml);
    out.add(dst / "scenes" / (foot ? "builtin_foot.toml" : "soak_mesh.toml"), scene);
    if (auto ok = out.commit(); !ok) return Err{ok.error().message()};
    return dst / "kerf.toml";
}

/// Where the cuts go: over the foot's long bones, or a 3 x 3 grid over the mesh's box.
std::vector<CutTarget> cut_targets(const RoundSpec& s, const mesh::Point& lo,
                                   const mesh::Point& hi) {
    std::vector<CutTarget> out;
    if (s.scene == "builtin_foot") {
        auto foot = mesh::generate_foot({s.triangles, s.seed});
        if (foot) {
            for (const mesh::BoneInfo& b : foot->bones) {
                if (b.length_m < 0.015) continue;
                for (const double f : {0.35, 0.5, 0.65}) {
                    const mesh::Point p = b.base_m + (b.head_m - b.base_m) * f;
                    out.push_back({p[0], p[2], p[1] + b.shaft_radius_m, p[1] - b.max_radius_m});
                }
            }
        }
        return out;
    }
    for (const double fx : {0.3, 0.5, 0.7})
        for (const double fz : {0.3, 0.5, 0.7})
            out.push_back(
                {lo[0] + fx * (hi[0] - lo[0]), lo[2] + fz * (hi[2] - lo[2]), hi[1], lo[1]});
    return out;
}

/// kerf-hapsim's command pipe: a FIFO its stdin is redirected from.
class CommandPipe {
public:
    explicit CommandPipe(fs::path path) : path_(std::move(path)) {}
    ~CommandPipe() {
        if (fd_ >= 0) ::close(fd_);
    }
    bool create() { return ::mkfifo(path_.c_str(), 0600) == 0; }
    /// Opens the writing end once kerf-hapsim's shell opened the reading end (<= 30 s).
    bool open_writer() {
        for (int i = 0; i < 3000 && fd_ < 0; ++i) {
            fd_ = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
            if (fd_ < 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return fd_ >= 0;
    }
    bool send(const std::string& line) {
        const std::string text = line + "\n";
        return fd_ >= 0 && ::write(fd_, text.data(), text.size()) == ssize_t(text.size());
    }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
    int fd_ = -1;
};

/// A fault to inject at `due_s` (round time).
struct Slot {
    SoakFault fault;
    double due_s = 0;
    bool done = false;
};

/// The display and segment faults, one every 8 s in turn from 5 s until 20 s before the end (the
/// display must be up and attached when kerf-rt stops).
std::vector<Slot> host_schedule(const RoundSpec& s, double script_s) {
    std::vector<SoakFault> host;
    for (const SoakFault f : s.faults)
        if (!is_device_fault(f)) host.push_back(f);
    std::vector<Slot> out;
    int k = s.host_rotation;
    for (double t = 5; !host.empty() && t < script_s - 20; t += 8)
        out.push_back({host[std::size_t(k++) % host.size()], t});
    return out;
}

/// The device faults, injected one after another while the tool pushes on the bone (|F| > 0.5 N;
/// at the latest 5 % of the script's length after the previous one allowed it, 1.5..6 s),
/// 1 % of it apart (1..3 s) — short rounds still get every fault; an unplug last, 12 s before
/// the end of the script (kerf-hapsim's script stops while no host is connected).
class DeviceFaultQueue {
public:
    DeviceFaultQueue(const RoundSpec& s, double script_s) : script_s_(script_s) {
        for (const SoakFault f : s.faults)
            if (is_device_fault(f) && f != SoakFault::kUnplug) list_.push_back(f);
        unplug_ = std::find(s.faults.begin(), s.faults.end(), SoakFault::kUnplug) != s.faults.end();
        next_ = std::size_t(s.device_rotation);
    }
    /// The fault to inject now, if any.
    std::optional<SoakFault> due(double t, float force_n) {
        if (unplug_ && t >= script_s_ - 12) {
            unplug_ = false;
            return SoakFault::kUnplug;
        }
        if (list_.empty() || t < ready_at_ || t >= script_s_ - 13) return std::nullopt;
        if (force_n <= 0.5f && t < ready_at_ + std::clamp(0.05 * script_s_, 1.5, 6.0))
            return std::nullopt;
        return list_[next_++ % list_.size()];
    }
    /// The previous fault was cleared at `t`.
    void cleared(double t) { ready_at_ = t + std::clamp(0.01 * script_s_, 1.0, 3.0); }

private:
    std::vector<SoakFault> list_;
    bool unplug_ = false;
    std::size_t next_ = 0;
    double ready_at_ = 6;
    double script_s_;
};

/// kerf-rt's exit summary figures into `r`.
void read_rt_summary(const std::string& log, RoundResult& r) {
    const auto at = log.find("kerf-rt summary");
    const std::string s = at == std::string::npos ? std::string() : log.substr(at);
    r.ticks = number_after(s, "ticks ");
    r.overruns = number_after(s, "overruns ");
    r.late_wakes = number_after(s, "late wakes ");
    r.safe_state_entries = number_after(s, "safe-state entries ");
    const auto wake = s.find("wake latency us:");
    if (wake != std::string::npos) {
        const std::string w = s.substr(wake);
        r.wake_p50_us = number_after(w, "p50 ");
        r.wake_p99_us = number_after(w, "p99 ");
        r.wake_p999_us = number_after(w, "p99.9 ");
        r.wake_max_us = number_after(w, "max ");
    }
}

void read_histogram(const fs::path& csv, RoundResult& r) {
    std::ifstream f(csv);
    std::string line;
    std::getline(f, line);
    while (std::getline(f, line)) {
        double edge = 0;
        unsigned long long wake = 0, work = 0;
        if (std::sscanf(line.c_str(), "%lf,%llu,%llu", &edge, &wake, &work) == 3 && wake)
            r.wake_histogram[edge] += wake;
    }
}

/// The journal's records as the monitor keeps them.
std::vector<SeenEvent> read_journal(const fs::path& path) {
    std::vector<SeenEvent> out;
    auto reader = ipc::JournalReader::open(path.string(), 0);
    if (!reader) return out;
    ipc::EventRecord e{};
    for (std::uint64_t s = 0; s < reader->record_count(); ++s) {
        if (reader->try_read(s, e) != ipc::JournalRead::kOk) break;
        out.push_back({e.header.sequence, e.header.checksum, std::uint16_t(e.header.type)});
    }
    return out;
}

/// Max force and penetration per 100 ms, OR of the flags: what the plots draw.
std::vector<PlotBin> decimate(const std::vector<TickSample>& ticks, std::uint64_t t0_ns) {
    std::vector<PlotBin> out;
    std::uint64_t last_bin = 0;
    for (const TickSample& s : ticks) {
        if (s.time_ns < t0_ns) continue;
        const std::uint64_t bin = (s.time_ns - t0_ns) / 100'000'000;
        if (out.empty() || last_bin != bin) {
            out.emplace_back();
            out.back().time_ns = t0_ns + bin * 100'000'000;
            last_bin = bin;
        }
        PlotBin& b = out.back();
        b.force_n = std::max(b.force_n, s.force_n);
        float& penetration =
            force_reaches_hand(s) ? b.penetration_live_m : b.penetration_no_force_m;
        penetration = std::max(penetration, s.penetration_m);
        b.safety_reasons |= s.safety_reasons;
        b.loop_flags |= s.loop_flags;
        b.contact_flags |= s.contact_flags;
    }
    return out;
}

}  // namespace

Result<RoundResult, std::string> run_round(const RoundSpec& spec, bool quiet) {
    RoundResult r;
    r.spec = spec;
    const fs::path bin = supervise::executable_dir();
    for (const char* exe : {"kerf-hapsim", "kerf-rt", "kerf-display"})
        if (access((bin / exe).c_str(), X_OK) != 0)
            return Err{(bin / exe).string() + ": not found (build it: cmake --build build)"};
    std::error_code ec;
    fs::create_directories(spec.work / "journal", ec);
    if (ec) return Err{spec.work.string() + ": " + ec.message()};
    const std::string session =
        "kerf-soak-" + std::to_string(getpid()) + "-" + std::to_string(spec.index);

    // The scene: a file mesh is centred on the origin (its box centre) like config/scenes/.
    auto toml = prepare_config(spec, session, std::nullopt);
    if (!toml) return Err{toml.error()};
    auto cfg = config::load_config(*toml);
    if (!cfg) return Err{cfg.error().message()};
    auto scene = display::build_scene_mesh(*cfg);
    if (!scene) return Err{"scene " + spec.scene + ": " + scene.error()};
    mesh::Point lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (const auto v : scene->vertices()) {
        lo.minimize(scene->point(v));
        hi.maximize(scene->point(v));
    }
    if (spec.scene != "builtin_foot") {
        const mesh::Point centre = (lo + hi) * 0.5;
        toml = prepare_config(spec, session, centre);
        if (!toml) return Err{toml.error()};
        cfg = config::load_config(*toml);
        if (!cfg) return Err{cfg.error().message()};
        lo -= centre;
        hi -= centre;
    }
    r.scene_name = spec.scene == "builtin_foot"
                       ? "builtin foot (" + std::to_string(scene->n_faces()) + " triangles, seed " +
                             std::to_string(spec.seed) + ")"
                       : fs::path(spec.scene).filename().string() + " (" +
                             std::to_string(scene->n_faces()) + " triangles)";
    scene = Err{std::string()};
    const mesh::Point origin{(lo[0] + hi[0]) / 2, hi[1] + 0.02, (lo[2] + hi[2]) / 2};
    RoundScriptParams params;
    params.duration_s = spec.duration_s;
    auto script = make_round_script(cut_targets(spec, lo, hi), origin, spec.seed, params);
    if (!script) return Err{"hand script: " + script.error()};
    r.cuts = script->cuts;
    const fs::path hand = spec.work / "hand.csv";
    if (auto ok = files::write_file_atomically(hand, script->csv); !ok)
        return Err{ok.error().message()};

    // The processes.
    Supervisor sup;
    const fs::path sock = spec.work / "hapsim.sock", status = spec.work / "display.json";
    const fs::path rt_log = spec.work / "kerf-rt.log", display_log = spec.work / "display.log";
    const fs::path hapsim_log = spec.work / "hapsim.log", hist = spec.work / "histogram.csv";
    CommandPipe pipe(spec.work / "hapsim.commands");
    if (!pipe.create()) return Err{"cannot create the FIFO " + pipe.path().string()};
    const std::vector<std::string> hapsim_args = {
        "/bin/sh",
        "-c",
        "exec \"$@\" < '" + pipe.path().string() + "'",
        "kerf-hapsim",
        (bin / "kerf-hapsim").string(),
        "--profile",
        (toml->parent_path() / "devices/simulated.toml").string(),
        "--socket",
        sock.string(),
        "--script",
        hand.string(),
        "--realtime",
        "--commands"};
    auto hapsim = sup.add({{"kerf-hapsim", hapsim_args, hapsim_log, {}}, Policy::kMayFinish});
    if (!hapsim) return Err{hapsim.error().message()};
    if (!pipe.open_writer()) return Err{"kerf-hapsim never opened its command pipe"};
    const auto wait_for = [&](const std::function<bool()>& ok, double s) {
        const auto until = Clock::now() + std::chrono::milliseconds(std::int64_t(s * 1000));
        while (!ok() && Clock::now() < until && !Supervisor::stop_requested())
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return ok();
    };
    if (!wait_for([&] { return fs::exists(sock); }, 30))
        return Err{"kerf-hapsim did not listen: " + slurp(hapsim_log)};
    const std::vector<std::string> display_argv =
        display_args(bin, {*toml, session, status, "headless", true, {}});
    auto display = sup.add(
        {{"kerf-display", display_argv, display_log, {}}, Policy::kRestart},
        [&] { return number_after(slurp(status), "\"frames\": ") >= 1; },
        std::chrono::seconds(180));
    if (!display) return Err{display.error().message() + "\n" + slurp(display_log)};
    const std::vector<std::string> rt_args = {(bin / "kerf-rt").string(),
                                              "--config",
                                              toml->string(),
                                              "--device",
                                              "simulated",
                                              "--socket",
                                              sock.string(),
                                              "--session",
                                              session,
                                              "--histogram",
                                              hist.string()};
    auto rt = sup.add({{"kerf-rt", rt_args, rt_log, {}}, Policy::kMayFinish},
                      [&] { return slurp(rt_log).find("kerf-rt: session") != std::string::npos; });
    if (!rt) return Err{rt.error().message() + "\n" + slurp(rt_log)};
    Result<std::unique_ptr<SessionMonitor>, std::string> monitor = Err{std::string()};
    wait_for(
        [&] {
            if (!monitor) monitor = SessionMonitor::start(session);
            return bool(monitor);
        },
        10);
    if (!monitor) return Err{monitor.error()};
    const auto t0 = Clock::now();
    const std::uint64_t t0_ns = monotonic_ns();
    const auto now_s = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

    // The round: faults on their schedule while the hand cuts.
    std::vector<Slot> slots = host_schedule(spec, script->duration_s);
    DeviceFaultQueue device_queue(spec, script->duration_s);
    std::vector<FaultWindow> windows;
    struct Active {
        SoakFault fault;
        double off_at_s;
        std::size_t injected;
    };
    std::optional<Active> device_active, host_active;
    std::atomic<bool> scribble_stop{false};
    std::uint64_t scribbles = 0;
    std::string scribble_error;
    std::thread scribbler;
    double last_memory = -1, last_print = 0;
    const auto sample_memory = [&] {
        if (now_s() - last_memory < 1.0) return;
        last_memory = now_s();
        MemoryPoint m;
        m.t_s = last_memory;
        const auto* rt_p = sup.find("kerf-rt");
        const auto* d_p = sup.find("kerf-display");
        if (rt_p && rt_p->running()) {
            const MemorySample s = read_memory(rt_p->pid());
            if (s.ok) {
                m.rt_mb = double(s.rss_kb) / 1024.0;
                m.rt_anon_mb = double(s.anon_kb) / 1024.0;
                m.rt_shmem_mb = double(s.shmem_kb) / 1024.0;
                m.rt_file_mb = double(s.file_kb) / 1024.0;
            }
        }
        if (d_p && d_p->running()) {
            const MemorySample s = read_memory(d_p->pid());
            if (s.ok) m.display_mb = double(s.rss_kb) / 1024.0;
        }
        r.memory.push_back(m);
    };
    const auto start_fault = [&](Slot& slot) {
        const double t = now_s();
        r.injected.push_back({slot.fault, t, t, {}});
        if (is_device_fault(slot.fault)) {
            pipe.send(hapsim_on_command(slot.fault));
            windows.push_back({slot.fault, monotonic_ns(), 0});
            device_active = Active{slot.fault, t + 0.8, r.injected.size() - 1};
            return;
        }
        auto* d = sup.find("kerf-display");
        if (slot.fault == SoakFault::kDisplayKill) {
            if (d && d->running()) d->signal(SIGKILL);
            ++r.display_kills;
            r.injected.back().note = "SIGKILL";
        } else if (slot.fault == SoakFault::kDisplayStop) {
            if (d && d->running()) d->signal(SIGSTOP);
            host_active = Active{slot.fault, t + 2.0, r.injected.size() - 1};
        } else {
            scribble_stop = false;
            scribbler = std::thread([&, seed = spec.seed * 1000 + r.injected.size()] {
                auto n = scribble_segment(session, 2.0, seed, scribble_stop);
                if (n)
                    scribbles += *n;
                else
                    scribble_error = n.error();
            });
            host_active = Active{slot.fault, t + 2.0, r.injected.size() - 1};
        }
    };
    const auto end_faults = [&](bool all) {
        const double t = now_s();
        if (device_active && (all || t >= device_active->off_at_s)) {
            pipe.send(hapsim_off_command(device_active->fault));
            windows.back().off_ns = monotonic_ns();
            r.injected[device_active->injected].off_s = t;
            device_active.reset();
            device_queue.cleared(t);
        }
        if (host_active && (all || t >= host_active->off_at_s)) {
            if (host_active->fault == SoakFault::kDisplayStop) {
                if (auto* d = sup.find("kerf-display")) d->signal(SIGCONT);
            } else if (scribbler.joinable()) {
                scribble_stop = true;
                scribbler.join();
            }
            r.injected[host_active->injected].off_s = t;
            host_active.reset();
        }
    };
    supervise::RunOutcome outcome = sup.run([&] {
        const double t = now_s();
        sample_memory();
        end_faults(false);
        for (Slot& slot : slots) {
            if (slot.done || t < slot.due_s || host_active) continue;
            slot.done = true;
            start_fault(slot);
        }
        if (!device_active) {
            if (const auto fault = device_queue.due(t, monitor.value()->force_n())) {
                Slot slot{*fault, t};
                start_fault(slot);
            }
        }
        if (!quiet && t - last_print >= 5) {
            last_print = t;
            const std::string st = slurp(status);
            std::printf("  round %d  %5.0f / %.0f s: %zu faults injected, display applied %.0f\n",
                        spec.index, t, script->duration_s, r.injected.size(),
                        number_after(st, "\"applied\": "));
            std::fflush(stdout);
        }
        return t >= script->duration_s + 1 && !device_active && !host_active;
    });
    end_faults(true);
    if (scribbler.joinable()) scribbler.join();
    if (!scribble_error.empty()) r.failures.push_back(scribble_error);
    if (outcome.reason == supervise::RunOutcome::Reason::kStopSignal)
        return Err{"stopped by signal " + std::to_string(Supervisor::stop_signal())};
    if (!outcome.ok()) r.failures.push_back("round ended early: " + outcome.detail);

    // The display catches up while kerf-rt runs; then kerf-rt stops and the display applies the
    // journal's last events.
    std::string st;
    const auto display_at = [&](std::uint64_t n) {
        st = slurp(status);
        return number_after(st, "\"next_sequence\": ") >= double(n) &&
               st.find("\"hash_valid\": true") != std::string::npos &&
               number_after(st, "\"hash_sequence\": ") >= double(n);
    };
    const auto wait_display = [&](std::uint64_t n, double s) {
        const auto until = Clock::now() + std::chrono::milliseconds(std::int64_t(s * 1000));
        return sup.run([&] {
            sample_memory();
            return display_at(n) || Clock::now() > until;
        });
    };
    if (outcome.ok()) wait_display(monitor.value()->published_events(), 120);
    if (auto* p = sup.find("kerf-rt"); p && p->running()) {
        p->signal(SIGTERM);
        p->wait_for(std::chrono::seconds(20));
    }
    const auto* rt_exit = &sup.find("kerf-rt")->exit_info();
    if (!*rt_exit || !(*rt_exit)->success())
        r.failures.push_back("kerf-rt " + (*rt_exit ? (*rt_exit)->describe() : "did not stop"));
    MonitorData seen = monitor.value()->stop();
    fs::path journal;
    for (const auto& e : fs::directory_iterator(spec.work / "journal", ec))
        if (e.is_regular_file()) journal = e.path();
    const std::vector<SeenEvent> journalled = read_journal(journal);
    r.journal_events = journalled.size();
    const bool caught_up = wait_display(r.journal_events, 120).ok() && display_at(r.journal_events);
    r.display_restarts = sup.restarts("kerf-display");
    sup.stop_all();
    r.wall_s = now_s();

    // The checks.
    const std::string rt_text = slurp(rt_log);
    read_rt_summary(rt_text, r);
    read_histogram(hist, r);
    if (rt_text.find("FAULT: check") != std::string::npos)
        r.failures.push_back("kerf-rt latched a failed check (see its log)");
    r.telemetry_samples = seen.stats.telemetry;
    r.telemetry_gaps = seen.stats.telemetry_gaps;
    r.monitor_rejected = seen.stats.rejected_records + seen.stats.rejected_indices;
    r.monitor_events = compare_sequences(journalled, seen.events);
    if (!r.monitor_events.ok())
        r.failures.push_back(
            "events: the soak monitor was delivered " + std::to_string(r.monitor_events.delivered) +
            " events, the journal has " + std::to_string(r.monitor_events.journal) +
            " (first difference at " + std::to_string(r.monitor_events.first_difference) + ")");
    r.display_next_sequence = std::uint64_t(std::max(0.0, number_after(st, "\"next_sequence\": ")));
    r.display_lost = std::uint64_t(std::max(0.0, number_after(st, "\"lost\": ")));
    r.display_rejected = std::uint64_t(std::max(0.0, number_after(st, "\"rejected_records\": "))) +
                         std::uint64_t(std::max(0.0, number_after(st, "\"rejected_indices\": ")));
    r.display_hash = json_string(st, "hash");
    if (!caught_up || r.display_next_sequence != r.journal_events || r.display_lost)
        r.failures.push_back("events: kerf-display applied " +
                             std::to_string(r.display_next_sequence) + " of the journal's " +
                             std::to_string(r.journal_events) + " events (lost " +
                             std::to_string(r.display_lost) + ")");
    if (!journal.empty()) {
        auto replay = replay_journal(*cfg, journal, {});
        if (!replay) {
            r.failures.push_back("replay: " + replay.error());
        } else {
            r.replay_hash = hash_hex(replay->hash);
            r.cut_begins = replay->cut_begins;
            r.cuts_completed = replay->cut_ends_completed;
            r.refused = replay->refused;
        }
    } else {
        r.failures.push_back("kerf-rt left no journal");
    }
    if (r.display_hash.empty() || r.display_hash != r.replay_hash)
        r.failures.push_back("hash: kerf-display " +
                             (r.display_hash.empty() ? std::string("none") : r.display_hash) +
                             ", journal replay " + r.replay_hash);
    if (r.display_restarts != r.display_kills)
        r.failures.push_back("kerf-display restarted " + std::to_string(r.display_restarts) +
                             " times, killed " + std::to_string(r.display_kills) +
                             " times (it crashed)");
    const double limit = std::min(cfg->force.limits.max_force_n, cfg->device.limits.peak_force_n);
    r.force = check_force_limit(seen.ticks, limit);
    if (!r.force.ok())
        r.failures.push_back("force: " + std::to_string(r.force.over) + " ticks above " +
                             std::to_string(limit) + " N (peak " + std::to_string(r.force.peak_n) +
                             " N)");
    r.device_faults = check_device_faults(seen.ticks, windows);
    for (const FaultVerdict& v : r.device_faults) {
        if (v.ok()) continue;
        char buf[256];
        std::snprintf(buf, sizeof buf, "fault %s at %.1f s: %s",
                      std::string(to_string(v.window.fault)).c_str(),
                      double(v.window.on_ns - t0_ns) * 1e-9, v.problem.c_str());
        r.failures.push_back(buf);
    }
    std::vector<double> t_s, td_s;
    std::vector<std::uint64_t> rt_kb, anon_kb, shmem_kb, file_kb, display_kb;
    const auto kb = [](double mb) { return std::uint64_t(mb * 1024); };
    for (const MemoryPoint& m : r.memory) {
        if (m.rt_mb >= 0) {
            t_s.push_back(m.t_s);
            rt_kb.push_back(kb(m.rt_mb));
            anon_kb.push_back(kb(m.rt_anon_mb));
            shmem_kb.push_back(kb(m.rt_shmem_mb));
            file_kb.push_back(kb(m.rt_file_mb));
        }
        if (m.display_mb >= 0) td_s.push_back(m.t_s), display_kb.push_back(kb(m.display_mb));
        r.display_peak_mb = std::max(r.display_peak_mb, m.display_mb);
    }
    const double warmup_s = std::min(30.0, 0.3 * spec.duration_s);
    // The rule is on RssAnon, what kerf-rt itself allocates (heap, stacks, private maps). VmRSS
    // adds the session segment (RssShmem: fixed by the layout, all of it faulted in and locked
    // at start) and the executable and libraries (RssFile); they dilute a heap leak in a larger
    // total, so they are reported beside the check, not in it.
    r.rt_memory = memory_growth(t_s, anon_kb, warmup_s);
    r.rt_rss_memory = memory_growth(t_s, rt_kb, warmup_s);
    r.rt_shmem_memory = memory_growth(t_s, shmem_kb, warmup_s);
    r.rt_file_memory = memory_growth(t_s, file_kb, warmup_s);
    r.display_memory = memory_growth(td_s, display_kb, warmup_s);
    if (!r.rt_memory.measured)
        r.failures.push_back("kerf-rt memory: too few samples after warm-up");
    else if (r.rt_memory.growth_pct > spec.rt_growth_limit_pct)
        r.failures.push_back("kerf-rt memory (RssAnon) grew " +
                             std::to_string(r.rt_memory.growth_pct) + " % after warm-up (limit " +
                             std::to_string(spec.rt_growth_limit_pct) + " %)");
    if (r.display_peak_mb > spec.display_rss_limit_mb)
        r.failures.push_back("kerf-display resident memory peaked at " +
                             std::to_string(int(r.display_peak_mb)) + " MB (limit " +
                             std::to_string(int(spec.display_rss_limit_mb)) + " MB)");
    for (InjectedFault& f : r.injected)
        if (f.fault == SoakFault::kScribble)
            f.note = "scribbles so far " + std::to_string(scribbles);
    r.plot_ticks = decimate(seen.ticks, t0_ns);

    for (const auto& [name, path] :
         std::vector<std::pair<std::string, fs::path>>{{"hand.csv", hand},
                                                       {"kerf-rt.log", rt_log},
                                                       {"kerf-display.log", display_log},
                                                       {"kerf-hapsim.log", hapsim_log},
                                                       {"display-status.json", status},
                                                       {"kerf-rt-histogram.csv", hist}})
        r.keep.emplace_back(name, slurp(path));
    if (!journal.empty()) r.keep.emplace_back("session.kjournal", slurp(journal));
    return r;
}

}  // namespace kerf::cli
