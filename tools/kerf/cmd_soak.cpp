// `kerf soak` — the soak-test engineer's tool: rounds of random cutting scenarios (planes,
// chevrons, slabs; soak_plan.*) on the built-in foot (a new seed each round) and on the meshes of
// the shared folder, each round a fresh session of kerf-hapsim, kerf-rt and kerf-display with
// faults injected while the hand cuts (soak_round.*), until the asked duration is spent. Every
// check is named in the summary when it fails, and the exit status is 1; report.json, the summary,
// the plots and each round's logs and journal go into the output folder (soak_report.*). Ctrl-C:
// the processes are stopped (kerf-rt first), nothing is written, exit 130.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "config/data_dir.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/session_files.hpp"
#include "tools/kerf/soak_report.hpp"
#include "tools/kerf/soak_round.hpp"
#include "tools/supervise/child_process.hpp"
#include "tools/supervise/supervisor.hpp"

namespace kerf::cli {
namespace {

namespace fs = std::filesystem;

struct SoakOptions {
    std::string duration;
    std::string round = "60s";
    std::string faults = "all";
    std::uint64_t seed = 1;
    std::string out_dir;
    std::size_t triangles = 50'000;
    std::string meshes;  ///< shared mesh folder; empty: $KERF_SHARED_MESHES or kerf.toml's
    std::string config;
    std::string scenes = "all";  ///< all (foot and shared meshes in turn), foot, shared
    double display_rss_limit_mb = 1024;
    double rt_growth_limit_pct = 1;
    bool quiet = false;
};

[[noreturn]] void fail(const std::string& what, int code = kExitFailure) {
    std::cerr << "kerf soak: " << what << "\n";
    throw CLI::RuntimeError(code);
}

/// "90", "90s", "2m", "1.5h" -> seconds; Err names the text.
Result<double, std::string> parse_duration(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    const std::string unit = end ? std::string(end) : std::string();
    const double scale = unit.empty() || unit == "s" ? 1
                         : unit == "m"               ? 60
                         : unit == "h"               ? 3600
                                                     : 0;
    if (end == text.c_str() || scale == 0 || !std::isfinite(v) || v <= 0)
        return Err{"'" + text + "' is not a duration (e.g. 120, 90s, 2m, 1.5h)"};
    return v * scale;
}

/// The closed meshes of the shared folder (the deliberately open one is left out), sorted.
std::vector<std::string> shared_meshes(const SoakOptions& o) {
    fs::path dir = o.meshes;
    if (dir.empty()) {
        const char* env = std::getenv("KERF_SHARED_MESHES");
        // kerf.toml's [paths] shared is "../../shared", relative to the configuration folder.
        dir = env && *env ? fs::path(env) : config::data_dir() / ".." / ".." / "shared" / "meshes";
    }
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        if (e.path().extension() == ".stl" && name.find("OPEN") == std::string::npos)
            out.push_back(fs::absolute(e.path()).string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

void run_soak(const SoakOptions& o) {
    const auto duration = parse_duration(o.duration);
    if (!duration) fail("--duration: " + duration.error(), kExitUsage);
    const auto round = parse_duration(o.round);
    if (!round) fail("--round: " + round.error(), kExitUsage);
    const auto faults = parse_fault_list(o.faults);
    if (!faults) fail("--faults: " + faults.error(), kExitUsage);
    const fs::path config_file =
        o.config.empty() ? config::data_file("kerf.toml") : fs::path(o.config);
    if (!fs::is_regular_file(config_file))
        fail("configuration " + config_file.string() + ": not found");
    const fs::path out = fs::absolute(o.out_dir);
    const std::vector<std::string> meshes = shared_meshes(o);
    if (o.scenes == "shared" && meshes.empty()) fail("--scenes shared: no shared meshes found");

    supervise::Supervisor guard;               // Ctrl-C is a stop request from here on
    auto work = WorkDir::create("kerf-soak");  // removed with everything in it at the end
    if (!work) fail(work.error());
    const auto t0 = std::chrono::steady_clock::now();
    const auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    SoakRun run;
    run.requested_s = *duration;
    run.seed = o.seed;
    run.faults = *faults;
    if (!o.quiet)
        std::printf(
            "kerf soak: %.0f s, rounds of %.0f s, faults %s, seed %llu, %zu shared meshes\n",
            *duration, *round, o.faults.c_str(), (unsigned long long)o.seed, meshes.size());
    int device_rotation = 0, host_rotation = 0;
    // A fixed number of rounds (not "until the time is spent"), so a loaded machine that starts
    // the processes slowly still gets every round and every fault; each round's own start-up and
    // checks take ~15 s of its share.
    const int rounds = std::max(1, static_cast<int>(std::lround(*duration / *round)));
    const double cutting_s = std::max(40.0, *duration / rounds - 15);
    for (int i = 0; i < rounds; ++i) {
        RoundSpec spec;
        spec.index = i;
        // The foot on even rounds, the shared meshes in turn on odd ones (or only one kind).
        const bool foot = o.scenes == "foot" || meshes.empty() || (o.scenes == "all" && i % 2 == 0);
        const std::size_t turn = o.scenes == "all" ? std::size_t(i / 2) : std::size_t(i);
        spec.scene = foot ? "builtin_foot" : meshes[turn % meshes.size()];
        spec.triangles = o.triangles;
        spec.seed = o.seed * 1000 + std::uint64_t(i);
        spec.duration_s = cutting_s;
        spec.faults = *faults;
        spec.device_rotation = device_rotation;
        spec.host_rotation = host_rotation;
        spec.config = config_file;
        spec.work = work->path() / ("round-" + std::to_string(i));
        spec.display_rss_limit_mb = o.display_rss_limit_mb;
        spec.rt_growth_limit_pct = o.rt_growth_limit_pct;
        if (!o.quiet) {
            std::printf("kerf soak: round %d on %s, %.0f s of cutting\n", i, spec.scene.c_str(),
                        spec.duration_s);
            std::fflush(stdout);
        }
        auto result = run_round(spec, o.quiet);
        if (supervise::Supervisor::stop_requested())
            fail("stopped by signal " + std::to_string(supervise::Supervisor::stop_signal()), 130);
        if (!result) fail("round " + std::to_string(i) + ": " + result.error());
        for (const InjectedFault& f : result->injected)
            ++(is_device_fault(f.fault) ? device_rotation : host_rotation);
        for (const std::string& f : result->failures)
            run.failures.push_back("round " + std::to_string(i) + ": " + f);
        run.rounds.push_back(std::move(*result));
        std::error_code ec;
        fs::remove_all(spec.work, ec);  // the journal and logs are kept in the result
    }
    run.wall_s = elapsed();
    if (auto ok = write_soak_outputs(run, out, work->path() / "plots"); !ok)
        fail("output: " + ok.error());
    std::cout << soak_summary(run, out);
    if (!run.failures.empty()) throw CLI::RuntimeError(kExitFailure);
}

}  // namespace

void add_soak_command(CLI::App& app) {
    auto opts = std::make_shared<SoakOptions>();
    CLI::App* soak = app.add_subcommand(
        "soak",
        "Soak test: random cuts through the foot and the shared meshes with faults injected "
        "(device, display, segment); checks events, hashes, forces, memory and the loop");
    soak->add_option("--duration", opts->duration, "how long: 120, 90s, 30m, 2h")->required();
    soak->add_option("--faults", opts->faults,
                     "all, none, or a list of drop, delay, corrupt, short, unplug, estop, "
                     "stuck-encoder, display-kill, display-stop, scribble")
        ->capture_default_str();
    soak->add_option("--seed", opts->seed, "random seed (scenarios, foot, scribbles)")
        ->capture_default_str();
    soak->add_option("-o,--out", opts->out_dir, "output folder")->required();
    soak->add_option("--round", opts->round,
                     "about how long a round lasts (one scene per round): --duration / --round "
                     "rounds, rounded")
        ->capture_default_str();
    soak->add_option("--triangles", opts->triangles, "the built-in foot's triangle count")
        ->capture_default_str()
        ->check(CLI::Range(std::size_t{10'000}, std::size_t{4'000'000}));
    soak->add_option("--meshes", opts->meshes,
                     "folder of shared meshes (default: $KERF_SHARED_MESHES, else "
                     "../../shared/meshes from the configuration folder)");
    soak->add_option("--scenes", opts->scenes,
                     "all (the foot and the shared meshes in turn), foot, or shared")
        ->capture_default_str()
        ->check(CLI::IsMember({"all", "foot", "shared"}));
    soak->add_option("--config", opts->config, "kerf.toml to start from")->check(CLI::ExistingFile);
    soak->add_option("--display-rss-limit-mb", opts->display_rss_limit_mb,
                     "kerf-display's resident memory bound (MB)")
        ->capture_default_str()
        ->check(CLI::Range(16.0, 1e6));
    soak->add_option("--rt-growth-limit-pct", opts->rt_growth_limit_pct,
                     "kerf-rt's own memory (RssAnon) growth allowed after warm-up (%)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    soak->add_flag("--quiet", opts->quiet, "no progress lines (the summary still prints)");
    soak->callback([opts] { run_soak(*opts); });
}

}  // namespace kerf::cli
