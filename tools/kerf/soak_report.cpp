#include "tools/kerf/soak_report.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config/file_io/file_io.hpp"
#include "tools/supervise/child_process.hpp"

namespace kerf::cli {
namespace {

namespace fs = std::filesystem;

/// Totals over the rounds.
struct Totals {
    std::uint64_t events = 0, cut_begins = 0, cuts_completed = 0, ticks = 0, overruns = 0,
                  late_wakes = 0, safe_state_entries = 0, telemetry = 0, telemetry_gaps = 0;
    std::uint64_t rejected = 0, display_restarts = 0;
    int hashes_equal = 0;
    std::map<std::string, int> injected;  ///< by fault name
    int device_ok = 0, device_unverified = 0, device_failed = 0, device_pushing = 0;
    double peak_force_n = 0, force_limit_n = 0, rt_growth_max_pct = 0, display_peak_mb = 0;
    double rt_rss_growth_max_pct = 0, rt_shmem_growth_max_pct = 0, rt_file_growth_max_pct = 0;
    double wake_max_us = 0;
    /// Peak tool penetration (mm) while the commanded force could reach the hand, and while it
    /// could not (e-stop, unplug, stale samples, safe state, not engaged: force_reaches_hand).
    double penetration_live_mm = 0, penetration_no_force_mm = 0;
    std::map<double, std::uint64_t> wake;  ///< merged histogram
};

Totals totals(const SoakRun& run) {
    Totals t;
    for (const RoundResult& r : run.rounds) {
        t.events += r.journal_events;
        t.cut_begins += r.cut_begins;
        t.cuts_completed += r.cuts_completed;
        t.ticks += std::uint64_t(std::max(0.0, r.ticks));
        t.overruns += std::uint64_t(std::max(0.0, r.overruns));
        t.late_wakes += std::uint64_t(std::max(0.0, r.late_wakes));
        t.safe_state_entries += std::uint64_t(std::max(0.0, r.safe_state_entries));
        t.telemetry += r.telemetry_samples;
        t.telemetry_gaps += r.telemetry_gaps;
        t.rejected += r.display_rejected + r.monitor_rejected;
        t.display_restarts += std::uint64_t(r.display_restarts);
        t.hashes_equal += !r.display_hash.empty() && r.display_hash == r.replay_hash;
        for (const InjectedFault& f : r.injected) ++t.injected[std::string(to_string(f.fault))];
        for (const FaultVerdict& v : r.device_faults) {
            if (!v.covered)
                ++t.device_unverified;
            else if (v.ok())
                ++t.device_ok;
            else
                ++t.device_failed;
            t.device_pushing += v.covered && v.pushing;
        }
        t.peak_force_n = std::max(t.peak_force_n, r.force.peak_n);
        t.force_limit_n = r.force.limit_n;
        const auto grow = [](double& most, const MemoryVerdict& m) {
            if (m.measured) most = std::max(most, m.growth_pct);
        };
        grow(t.rt_growth_max_pct, r.rt_memory);
        grow(t.rt_rss_growth_max_pct, r.rt_rss_memory);
        grow(t.rt_shmem_growth_max_pct, r.rt_shmem_memory);
        grow(t.rt_file_growth_max_pct, r.rt_file_memory);
        t.display_peak_mb = std::max(t.display_peak_mb, r.display_peak_mb);
        t.wake_max_us = std::max(t.wake_max_us, r.wake_max_us);
        for (const auto& [edge, n] : r.wake_histogram) t.wake[edge] += n;
        for (const PlotBin& b : r.plot_ticks) {
            t.penetration_live_mm =
                std::max(t.penetration_live_mm, double(b.penetration_live_m) * 1e3);
            t.penetration_no_force_mm =
                std::max(t.penetration_no_force_mm, double(b.penetration_no_force_m) * 1e3);
        }
    }
    return t;
}

/// Percentile of the merged histogram (the bin's upper edge, as kerf-rt reports).
double percentile_us(const std::map<double, std::uint64_t>& h, double q) {
    std::uint64_t n = 0;
    for (const auto& [edge, c] : h) n += c;
    if (!n) return -1;
    const auto rank = std::min(n - 1, std::uint64_t(q * double(n)));
    std::uint64_t seen = 0;
    for (const auto& [edge, c] : h) {
        seen += c;
        if (seen > rank) return edge;
    }
    return h.rbegin()->first;
}

nlohmann::json round_json(const RoundResult& r) {
    nlohmann::json faults = nlohmann::json::array(), cuts = nlohmann::json::array();
    for (const InjectedFault& f : r.injected)
        faults.push_back({{"fault", to_string(f.fault)},
                          {"on_s", f.on_s},
                          {"off_s", f.off_s},
                          {"note", f.note}});
    nlohmann::json device = nlohmann::json::array();
    for (const FaultVerdict& v : r.device_faults)
        device.push_back({{"fault", to_string(v.window.fault)},
                          {"telemetry_covered", v.covered},
                          {"seen_by_kerf_rt", v.seen},
                          {"force_before_n_gt_0", v.pushing},
                          {"ticks_to_zero_force", v.ticks_to_zero},
                          {"ticks_with_force_while_bad", v.nonzero_while_bad},
                          {"recovered", v.recovered},
                          {"recovery_s", v.recovery_s},
                          {"ok", v.ok()},
                          {"problem", v.problem}});
    for (const PlannedCut& c : r.cuts)
        cuts.push_back(
            {{"kind", c.kind}, {"tilt_deg", c.tilt_deg}, {"feed_mm_s", c.feed_m_s * 1e3}});
    const auto mem = [](const MemoryVerdict& m) {
        return nlohmann::json{{"measured", m.measured},
                              {"after_warmup_kb", m.warm_kb},
                              {"end_kb", m.end_kb},
                              {"peak_kb", m.peak_kb},
                              {"growth_pct", m.growth_pct}};
    };
    return {{"round", r.spec.index},
            {"scene", r.scene_name},
            {"seed", r.spec.seed},
            {"wall_s", r.wall_s},
            {"planned_cuts", cuts},
            {"cut_begins", r.cut_begins},
            {"cuts_completed", r.cuts_completed},
            {"replay_refused", r.refused},
            {"journal_events", r.journal_events},
            {"monitor_events_delivered", r.monitor_events.delivered},
            {"monitor_first_difference", r.monitor_events.first_difference},
            {"display_next_sequence", r.display_next_sequence},
            {"display_lost", r.display_lost},
            {"display_rejected", r.display_rejected},
            {"monitor_rejected", r.monitor_rejected},
            {"display_hash", r.display_hash},
            {"replay_hash", r.replay_hash},
            {"hashes_equal", !r.display_hash.empty() && r.display_hash == r.replay_hash},
            {"display_kills", r.display_kills},
            {"display_restarts", r.display_restarts},
            {"faults", faults},
            {"device_faults", device},
            {"force_peak_n", r.force.peak_n},
            {"force_limit_n", r.force.limit_n},
            {"force_ticks_over_limit", r.force.over},
            {"kerf_rt_memory", mem(r.rt_memory)},
            {"kerf_rt_memory_measure", "RssAnon"},
            {"kerf_rt_rss", mem(r.rt_rss_memory)},
            {"kerf_rt_rss_shmem", mem(r.rt_shmem_memory)},
            {"kerf_rt_rss_file", mem(r.rt_file_memory)},
            {"kerf_display_memory", mem(r.display_memory)},
            {"kerf_display_peak_mb", r.display_peak_mb},
            {"ticks", r.ticks},
            {"overruns", r.overruns},
            {"late_wakes", r.late_wakes},
            {"safe_state_entries", r.safe_state_entries},
            {"wake_p50_us", r.wake_p50_us},
            {"wake_p99_us", r.wake_p99_us},
            {"wake_p999_us", r.wake_p999_us},
            {"wake_max_us", r.wake_max_us},
            {"telemetry_samples", r.telemetry_samples},
            {"telemetry_gaps", r.telemetry_gaps},
            {"failures", r.failures}};
}

std::string report_json(const SoakRun& run) {
    const Totals t = totals(run);
    nlohmann::json rounds = nlohmann::json::array(), faults = nlohmann::json::array();
    for (const RoundResult& r : run.rounds) rounds.push_back(round_json(r));
    for (const SoakFault f : run.faults) faults.push_back(to_string(f));
    const nlohmann::json j = {{"passed", run.failures.empty()},
                              {"failures", run.failures},
                              {"requested_s", run.requested_s},
                              {"wall_s", run.wall_s},
                              {"seed", run.seed},
                              {"faults", faults},
                              {"events", t.events},
                              {"cut_begins", t.cut_begins},
                              {"cuts_completed", t.cuts_completed},
                              {"rounds_hash_equal", t.hashes_equal},
                              {"faults_injected", t.injected},
                              {"device_faults_ok", t.device_ok},
                              {"device_faults_failed", t.device_failed},
                              {"device_faults_unverified", t.device_unverified},
                              {"device_faults_while_force", t.device_pushing},
                              {"force_peak_n", t.peak_force_n},
                              {"force_limit_n", t.force_limit_n},
                              {"penetration_peak_with_force_mm", t.penetration_live_mm},
                              {"penetration_peak_without_force_mm", t.penetration_no_force_mm},
                              {"kerf_rt_memory_growth_max_pct", t.rt_growth_max_pct},
                              {"kerf_rt_memory_measure", "RssAnon"},
                              {"kerf_rt_rss_growth_max_pct", t.rt_rss_growth_max_pct},
                              {"kerf_rt_rss_shmem_growth_max_pct", t.rt_shmem_growth_max_pct},
                              {"kerf_rt_rss_file_growth_max_pct", t.rt_file_growth_max_pct},
                              {"kerf_display_peak_mb", t.display_peak_mb},
                              {"ticks", t.ticks},
                              {"overruns", t.overruns},
                              {"late_wakes", t.late_wakes},
                              {"safe_state_entries", t.safe_state_entries},
                              {"wake_p50_us", percentile_us(t.wake, 0.5)},
                              {"wake_p99_us", percentile_us(t.wake, 0.99)},
                              {"wake_p999_us", percentile_us(t.wake, 0.999)},
                              {"wake_max_us", t.wake_max_us},
                              {"telemetry_samples", t.telemetry},
                              {"telemetry_gaps", t.telemetry_gaps},
                              {"rejected_records", t.rejected},
                              {"rounds", rounds}};
    return j.dump(1) + "\n";
}

/// Seconds from the start of the run at which each round started (rounds run back to back).
std::vector<double> round_offsets(const SoakRun& run) {
    std::vector<double> out;
    double t = 0;
    for (const RoundResult& r : run.rounds) {
        out.push_back(t);
        t += r.wall_s;
    }
    return out;
}

struct PlotFiles {
    std::string latency, force, faults, memory, script;
};

PlotFiles plot_files(const SoakRun& run) {
    PlotFiles p;
    const Totals t = totals(run);
    char line[256];
    p.latency = "# kerf-rt wake latency: bin upper edge (us), ticks in the bin (all rounds)\n";
    for (const auto& [edge, n] : t.wake) {
        std::snprintf(line, sizeof line, "%.1f %llu\n", edge, (unsigned long long)n);
        p.latency += line;
    }
    const std::vector<double> offsets = round_offsets(run);
    p.force =
        "# time (s since the run started), per 100 ms: peak |force| (N), peak penetration (mm) "
        "of ticks whose force reached the hand, peak penetration (mm) of ticks whose force could "
        "not (safety reason or loop flag zeroing it: e-stop, unplug, stale, safe state, not "
        "engaged), and every safety-reason, loop-flag and contact-flag bit seen (hex)\n";
    p.faults = "# fault on (s), off (s), kind (1 device, 2 display kill/stop, 3 scribble), name\n";
    p.memory =
        "# time (s), kerf-rt VmRSS (MB), kerf-display VmRSS (MB), kerf-rt RssAnon, RssShmem, "
        "RssFile (MB); NaN: not running\n";
    for (std::size_t i = 0; i < run.rounds.size(); ++i) {
        const RoundResult& r = run.rounds[i];
        const std::uint64_t t0 = r.plot_ticks.empty() ? 0 : r.plot_ticks.front().time_ns;
        for (const PlotBin& b : r.plot_ticks) {
            std::snprintf(line, sizeof line, "%.2f %.4f %.4f %.4f 0x%x 0x%x 0x%x\n",
                          offsets[i] + double(b.time_ns - t0) * 1e-9, b.force_n,
                          b.penetration_live_m * 1e3, b.penetration_no_force_m * 1e3,
                          b.safety_reasons, b.loop_flags, b.contact_flags);
            p.force += line;
        }
        p.force += "\n";  // a break in the line between rounds
        for (const InjectedFault& f : r.injected) {
            const int kind = is_device_fault(f.fault) ? 1 : f.fault == SoakFault::kScribble ? 3 : 2;
            std::snprintf(line, sizeof line, "%.2f %.2f %d %s\n", offsets[i] + f.on_s,
                          offsets[i] + std::max(f.off_s, f.on_s + 0.2), kind,
                          std::string(to_string(f.fault)).c_str());
            p.faults += line;
        }
        for (const MemoryPoint& m : r.memory) {
            const auto mb = [](double v) { return v < 0 ? std::string("NaN") : std::to_string(v); };
            p.memory += std::to_string(offsets[i] + m.t_s) + " " + mb(m.rt_mb) + " " +
                        mb(m.display_mb) + " " + mb(m.rt_anon_mb) + " " + mb(m.rt_shmem_mb) + " " +
                        mb(m.rt_file_mb) + "\n";
        }
        p.memory += "\n";
    }
    p.script =
        "# gnuplot script of kerf soak (run in this folder: gnuplot plots.gp)\n"
        "set terminal pngcairo size 1200,500 font 'sans,10'\n"
        "set output 'wake-latency.png'\n"
        "set title 'kerf-rt wake latency (all rounds; " +
        std::to_string(t.ticks) +
        " ticks)'\n"
        "set xlabel 'wake latency (us, bin upper edge)'\nset ylabel 'ticks'\n"
        "set logscale xy\nset yrange [0.5:*]\nset grid\nset style fill solid 0.6\n"
        "plot 'latency.dat' using 1:2 with impulses lw 3 lc rgb '#1f77b4' title 'ticks per bin'\n"
        "unset logscale\nset autoscale\nset output 'force-penetration.png'\nset terminal pngcairo "
        "size 1400,800 "
        "font 'sans,10'\nset multiplot layout 2,1\nset xlabel 'time (s)'\n"
        "set title 'commanded force (peak per 100 ms); faults shaded: red device, blue display, "
        "green scribbler'\nset ylabel 'force (N)'\nset yrange [0:" +
        std::to_string(t.force_limit_n * 1.1 + 0.1) +
        "]\n"
        "plot 'faults.dat' using "
        "(($1+$2)/2):(0):(($2-$1)/2):(1e3):(($3==1)?0xd62728:(($3==2)?0x1f77b4:0x2ca02c)) "
        "with boxxyerror fs transparent solid 0.3 noborder lc rgb variable notitle, "
        "'force.dat' using 1:2 with lines lc rgb 'black' title '|F|', " +
        std::to_string(t.force_limit_n) +
        " with lines dt 2 lc rgb 'red' title 'limit'\n"
        "set title 'tool penetration (peak per 100 ms): brown while the force reached the hand, "
        "grey while it could not (e-stop, unplug, stale samples, safe state, not engaged)'\n"
        "set ylabel 'penetration (mm)'\n"
        "set yrange [0:" +
        std::to_string(std::max(t.penetration_live_mm, t.penetration_no_force_mm) * 1.1 + 0.1) +
        "]\n"
        "plot 'faults.dat' using "
        "(($1+$2)/2):(0):(($2-$1)/2):(1e3):(($3==1)?0xd62728:(($3==2)?0x1f77b4:0x2ca02c)) "
        "with boxxyerror fs transparent solid 0.3 noborder lc rgb variable notitle, "
        "'force.dat' using 1:4 with lines lc rgb '#b0b0b0' title 'penetration, no force', "
        "'force.dat' using 1:3 with lines lc rgb '#8c564b' title 'penetration, force on'\n"
        "unset multiplot\nset terminal pngcairo size 1200,500 font 'sans,10'\n"
        "set output 'memory.png'\nset title 'resident memory (sampled once a second)'\n"
        "set ylabel 'MB'\nset yrange [0:*]\n"
        "plot 'memory.dat' using 1:2 with lines lw 2 title 'kerf-rt VmRSS', "
        "'memory.dat' using 1:4 with lines lw 2 title 'kerf-rt RssAnon (checked)', "
        "'memory.dat' using 1:5 with lines lw 1 title 'kerf-rt RssShmem', "
        "'memory.dat' using 1:6 with lines lw 1 title 'kerf-rt RssFile', "
        "'memory.dat' using 1:3 with lines lw 2 title 'kerf-display VmRSS'\n";
    return p;
}

std::string read_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

}  // namespace

std::string soak_summary(const SoakRun& run, const fs::path& out) {
    const Totals t = totals(run);
    std::string s;
    char line[512];
    std::snprintf(line, sizeof line,
                  "kerf soak: %s — %zu rounds in %.0f s (asked %.0f s), seed %llu\n",
                  run.failures.empty() ? "PASSED" : "FAILED", run.rounds.size(), run.wall_s,
                  run.requested_s, (unsigned long long)run.seed);
    s += line;
    for (const RoundResult& r : run.rounds) {
        std::snprintf(line, sizeof line,
                      "  round %d: %s, %.0f s, %llu events, %llu cuts begun / %llu completed, "
                      "%zu faults, hash %s%s\n",
                      r.spec.index, r.scene_name.c_str(), r.wall_s,
                      (unsigned long long)r.journal_events, (unsigned long long)r.cut_begins,
                      (unsigned long long)r.cuts_completed, r.injected.size(),
                      r.replay_hash.c_str(),
                      r.display_hash == r.replay_hash ? " (display = replay)" : " (DIFFERENT)");
        s += line;
    }
    std::string injected;
    int n = 0;
    for (const auto& [name, c] : t.injected) {
        injected += (injected.empty() ? "" : ", ") + name + " " + std::to_string(c);
        n += c;
    }
    std::snprintf(line, sizeof line, "  faults:    %d injected (%s)\n", n, injected.c_str());
    s += line;
    std::snprintf(line, sizeof line,
                  "  device:    %d faults: %d zero force within 2 ticks and recovered, %d failed, "
                  "%d without telemetry; %d hit a pushing tool\n",
                  t.device_ok + t.device_failed + t.device_unverified, t.device_ok, t.device_failed,
                  t.device_unverified, t.device_pushing);
    s += line;
    std::snprintf(line, sizeof line,
                  "  events:    %llu journalled; display and monitor = journal: %s; %llu garbage "
                  "records rejected; display restarts %llu; hashes equal %d of %zu\n",
                  (unsigned long long)t.events,
                  std::none_of(run.rounds.begin(), run.rounds.end(),
                               [](const RoundResult& r) {
                                   return !r.monitor_events.ok() ||
                                          r.display_next_sequence != r.journal_events;
                               })
                      ? "yes"
                      : "NO",
                  (unsigned long long)t.rejected, (unsigned long long)t.display_restarts,
                  t.hashes_equal, run.rounds.size());
    s += line;
    std::snprintf(line, sizeof line,
                  "  force:     peak %.2f N (limit %.2f N); tool penetration peak %.1f mm while "
                  "force reached the hand, %.1f mm while it could not\n",
                  t.peak_force_n, t.force_limit_n, t.penetration_live_mm,
                  t.penetration_no_force_mm);
    s += line;
    std::snprintf(line, sizeof line,
                  "  memory:    kerf-rt growth after warm-up, most in a round: RssAnon %.2f %% "
                  "(limit %.2g %%), VmRSS %.2f %%, RssShmem %.2f %%, RssFile %.2f %%; "
                  "kerf-display peak %.0f MB\n",
                  t.rt_growth_max_pct,
                  run.rounds.empty() ? 1.0 : run.rounds.front().spec.rt_growth_limit_pct,
                  t.rt_rss_growth_max_pct, t.rt_shmem_growth_max_pct, t.rt_file_growth_max_pct,
                  t.display_peak_mb);
    s += line;
    std::snprintf(line, sizeof line,
                  "  loop:      %llu ticks, %llu overruns, %llu late wakes, %llu safe-state "
                  "entries; wake latency p50 %.0f  p99 %.0f  p99.9 %.0f  max %.0f us\n",
                  (unsigned long long)t.ticks, (unsigned long long)t.overruns,
                  (unsigned long long)t.late_wakes, (unsigned long long)t.safe_state_entries,
                  percentile_us(t.wake, 0.5), percentile_us(t.wake, 0.99),
                  percentile_us(t.wake, 0.999), t.wake_max_us);
    s += line;
    std::snprintf(line, sizeof line, "  telemetry: %llu samples, %llu missed by the monitor\n",
                  (unsigned long long)t.telemetry, (unsigned long long)t.telemetry_gaps);
    s += line;
    s += "  output:    " + out.string() +
         " (report.json, summary.txt, wake-latency.png, force-penetration.png, memory.png, "
         "rounds/)\n";
    for (const std::string& f : run.failures) s += "  FAILED: " + f + "\n";
    return s;
}

Status<std::string> write_soak_outputs(const SoakRun& run, const fs::path& out,
                                       const fs::path& scratch) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) return Err{out.string() + ": " + ec.message()};
    fs::create_directories(scratch, ec);
    const PlotFiles p = plot_files(run);
    const std::vector<std::pair<std::string, std::string>> data = {{"latency.dat", p.latency},
                                                                   {"force.dat", p.force},
                                                                   {"faults.dat", p.faults},
                                                                   {"memory.dat", p.memory},
                                                                   {"plots.gp", p.script}};
    files::AtomicFileSet set;
    for (const auto& [name, text] : data) {
        if (auto ok = files::write_file_atomically(scratch / name, text); !ok)
            return Err{ok.error().message()};
        set.add(out / name, text);
    }
    auto gnuplot = supervise::ChildProcess::spawn(
        {"gnuplot",
         {"/bin/sh", "-c", "cd \"$0\" && exec gnuplot plots.gp", scratch.string()},
         scratch / "gnuplot.log",
         {}});
    if (!gnuplot) return Err{"gnuplot: " + gnuplot.error().message()};
    const auto& done = gnuplot->wait_for(std::chrono::seconds(120));
    if (!done || !done->success())
        return Err{"gnuplot (apt-get install gnuplot-nox) failed: " +
                   read_bytes(scratch / "gnuplot.log")};
    for (const char* png : {"wake-latency.png", "force-penetration.png", "memory.png"}) {
        std::string bytes = read_bytes(scratch / png);
        if (bytes.size() < 8) return Err{std::string("gnuplot made no ") + png};
        set.add(out / png, std::move(bytes));
    }
    for (const RoundResult& r : run.rounds)
        for (const auto& [name, text] : r.keep)
            set.add(out / "rounds" / std::to_string(r.spec.index) / name, text);
    set.add(out / "report.json", report_json(run));
    set.add(out / "summary.txt", soak_summary(run, out));
    for (const RoundResult& r : run.rounds)
        fs::create_directories(out / "rounds" / std::to_string(r.spec.index), ec);
    if (auto ok = set.commit(); !ok) return Err{ok.error().message()};
    return {};
}

}  // namespace kerf::cli
