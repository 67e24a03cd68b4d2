// Event -> pixels latency of kerf-display for a CutBegin on the built-in foot (default 1M
// triangles), with real processes: a test producer (standing in for kerf-rt) publishes one
// CutBegin (then its withdrawn CutEnd) every --period-ms; kerf-display applies it on its worker,
// uploads the dirty ranges and draws. Per CutBegin the display records the latency (the event's
// CLOCK_MONOTONIC stamp -> end of the first frame showing it), the worker's time for the cut, and
// the bytes that frame uploaded; this tool prints median and min-max of each, the frame time, and
// (latency - cut) in frames: the target is <= 1 frame plus the cut's own time.
//
//   bench_display_latency [--triangles 1000000] [--cuts 5] [--period-ms 2500]
//                         [--producer-cpu 0] [--display-cpu 1] [--size 1280x720] [--on-demand 1]
//
// Processes are pinned with taskset (say where in the figures you report). A CTest smoke run
// (label bench) uses a small foot and three cuts so the tool never rots.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "config/base/main_guard.hpp"
#include "display/app/session_events_ipc.hpp"
#include "display/cut/cut_session.hpp"
#include "display/mesh/foot_generator.hpp"
#include "tests/display/process_support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace kerf;

std::vector<double> json_numbers(const std::string& text, const std::string& key) {
    std::vector<double> out;
    const auto at = text.find("\"" + key + "\": [");
    if (at == std::string::npos) return out;
    const char* p = text.c_str() + at + key.size() + 5;
    while (*p && *p != ']') {
        char* end = nullptr;
        const double v = std::strtod(p, &end);
        if (end == p) break;
        out.push_back(v);
        p = end;
        while (*p == ',' || *p == ' ') ++p;
    }
    return out;
}

double json_number(const std::string& text, const std::string& key) {
    const auto at = text.find("\"" + key + "\": ");
    return at == std::string::npos ? NAN : std::atof(text.c_str() + at + key.size() + 4);
}

struct Summary {
    double median = NAN, min = NAN, max = NAN;
};
Summary summarize(std::vector<double> v) {
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    return {v[v.size() / 2], v.front(), v.back()};
}

std::string arg(int argc, char** argv, const char* key, const char* fallback) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::string(argv[i]) == key) return argv[i + 1];
    return fallback;
}

}  // namespace

static int program_main(int argc, char** argv) {
    const std::size_t triangles = std::stoul(arg(argc, argv, "--triangles", "1000000"));
    const int cuts = std::stoi(arg(argc, argv, "--cuts", "5"));
    const std::string period = arg(argc, argv, "--period-ms", "2500");
    const std::string producer_cpu = arg(argc, argv, "--producer-cpu", "0");
    const std::string display_cpu = arg(argc, argv, "--display-cpu", "1");
    const std::string size = arg(argc, argv, "--size", "1280x720");
    const bool on_demand = arg(argc, argv, "--on-demand", "0") == std::string("1");

    char tmpl[] = "/tmp/kerf-bench-display-XXXXXX";
    const fs::path dir = mkdtemp(tmpl);
    const fs::path config = fs::path(KERF_SOURCE_DIR) / "config";
    fs::create_directories(dir / "devices");
    fs::create_directories(dir / "force");
    fs::create_directories(dir / "scenes");
    fs::copy_file(config / "devices/simulated.toml", dir / "devices/simulated.toml");
    fs::copy_file(config / "force/default.toml", dir / "force/default.toml");
    const std::string session = "kerfbench_" + std::to_string(getpid());
    std::string toml = display::test::read_file((config / "kerf.toml").string());
    toml = std::regex_replace(toml, std::regex("session_name = \"kerf\""),
                              "session_name = \"" + session + "\"");
    std::ofstream(dir / "kerf.toml") << toml;
    std::string scene = display::test::read_file((config / "scenes/builtin_foot.toml").string());
    scene = std::regex_replace(scene, std::regex("target_triangles = [0-9_]+"),
                               "target_triangles = " + std::to_string(triangles));
    std::ofstream(dir / "scenes/builtin_foot.toml") << scene;

    // The cuts: across the first metatarsal's shaft at evenly spaced points, each seeded at the
    // mesh vertex nearest to the shaft surface there; checked here with CutSession.
    auto foot = mesh::generate_foot({triangles, 1});
    if (!foot) {
        std::fprintf(stderr, "bench_display_latency: %s\n", foot.error().c_str());
        return 1;
    }
    const mesh::BoneInfo bone = foot->first_metatarsal();
    const cut::Vec3 axis = (bone.head_m - bone.base_m).normalized();
    const cut::Vec3 side = OpenMesh::cross(axis, cut::Vec3(0, 1, 0)).normalized();
    cut::CutSession check(foot->mesh);
    std::vector<ipc::EventRecord> records;
    for (int k = 0; k < cuts; ++k) {
        const double t = 0.35 + 0.3 * k / std::max(1, cuts - 1);
        const cut::Vec3 point = bone.base_m + (bone.head_m - bone.base_m) * t;
        const cut::Vec3 target = point + side * bone.shaft_radius_m;
        double best = 1e300;
        cut::Vec3 seed;
        for (const auto v : check.mesh().vertices()) {
            const double d = (check.mesh().point(v) - target).sqrnorm();
            if (d < best) best = d, seed = check.mesh().point(v);
        }
        cut::CutBegin begin;
        begin.cut_id = static_cast<std::uint32_t>(k + 1);
        begin.blade = cut::BladeFrame{seed, axis, side};
        begin.seed_m = seed;
        begin.body_id = check.body_at(seed);
        begin.kerf_width_m = 0.0006;
        records.push_back(display::make_record(begin));
        records.push_back(
            display::make_record(cut::CutEnd{begin.cut_id, cut::CutEndKind::kWithdrawn}, begin));
        const auto applied = display::apply_record(check, records[records.size() - 2]);
        display::apply_record(check, records.back());
        if (applied.report.outcome != cut::EventOutcome::kApplied) {
            std::fprintf(stderr, "bench_display_latency: cut %d refused (%s)\n", k + 1,
                         std::string(cut::to_string(applied.report.status)).c_str());
            return 1;
        }
    }
    {
        std::ofstream out(dir / "events.bin", std::ios::binary);
        out.write(reinterpret_cast<const char*>(records.data()),
                  static_cast<std::streamsize>(records.size() * sizeof(ipc::EventRecord)));
    }

    using display::test::Child;
    Child producer({"/usr/bin/taskset", "-c", producer_cpu,
                    display::test::bin("display_test_producer"), "--segment", session,
                    "--journal-dir", dir.string(), "--records", (dir / "events.bin").string(),
                    "--hold-after", "0", "--go", (dir / "go").string(), "--period-ms", period},
                   (dir / "producer.out").string());
    if (!producer.wait_output("ready", 120)) {
        std::fprintf(stderr, "bench_display_latency: producer: %s\n", producer.output().c_str());
        return 1;
    }
    const std::string status = (dir / "status.json").string();
    std::vector<std::string> display_args{"/usr/bin/taskset",
                                          "-c",
                                          display_cpu,
                                          display::test::bin("kerf-display"),
                                          "--config",
                                          (dir / "kerf.toml").string(),
                                          "--size",
                                          size,
                                          "--status",
                                          status,
                                          "--exit-after-events",
                                          std::to_string(records.size())};
    if (on_demand) display_args.push_back("--on-demand");
    Child display(display_args, (dir / "display.out").string());
    // Start the cuts once the display is attached and drawing the scene.
    if (!display::test::wait_for(
            [&] {
                const std::string s = display::test::read_file(status);
                return s.find("\"attached\": true") != std::string::npos &&
                       json_number(s, "frames") >= 3;
            },
            600)) {
        std::fprintf(stderr, "bench_display_latency: display: %s\n", display.output().c_str());
        return 1;
    }
    std::ofstream(dir / "go") << "go\n";
    const auto rc = display.wait_exit(60.0 + cuts * 2 * std::stod(period) / 1000.0 * 4);
    producer.kill(SIGTERM);
    const std::string s = display::test::read_file(status);
    if (rc != 0) {
        std::fprintf(stderr, "bench_display_latency: display exit %d: %s\n", rc.value_or(-1),
                     display.output().c_str());
        return 1;
    }
    const Summary lat = summarize(json_numbers(s, "latency_samples_ms"));
    const Summary edit = summarize(json_numbers(s, "edit_ms"));
    const Summary up = summarize(json_numbers(s, "upload_bytes_samples"));
    const double frame = json_number(s, "frame_median_ms");
    const double joins = json_number(s, "frame_joins"), restarts = json_number(s, "frame_restarts");
    const double whole = json_number(s, "whole_buffer_bytes");
    std::printf(
        "scene: built-in foot, %zu triangles target; %d CutBegin events; producer on CPU %s, "
        "kerf-display on CPU %s; %s; frames %s\n",
        triangles, cuts, producer_cpu.c_str(), display_cpu.c_str(), size.c_str(),
        on_demand ? "on demand" : "continuous");
    std::printf("frame time (median over the run)      %8.2f ms\n", frame);
    std::printf("  of which upload + draw calls        %8.2f ms (then glFinish: rasterisation)\n",
                json_number(s, "issue_median_ms"));
    std::printf("cut on the worker (CutBegin slice)    %8.2f ms  (min %.2f, max %.2f)\n",
                edit.median, edit.min, edit.max);
    std::printf("event -> pixels                       %8.2f ms  (min %.2f, max %.2f)\n",
                lat.median, lat.min, lat.max);
    std::printf("(event -> pixels - cut) / frame       %8.2f frames (median)\n",
                (lat.median - edit.median) / frame);
    std::printf("edits that came mid-frame             %8.0f joined the frame, %.0f restarted it\n",
                joins, restarts);
    std::printf("event -> pixels, each edit (ms):     ");
    for (const double v : json_numbers(s, "latency_samples_ms")) std::printf(" %.0f", v);
    std::printf("\n");
    std::printf(
        "bytes uploaded by that frame          %8.0f  (min %.0f, max %.0f); whole buffers "
        "%.0f bytes: %.4f of a full upload\n",
        up.median, up.min, up.max, whole, up.median / whole);
    std::error_code ec;
    fs::remove_all(dir, ec);
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_display_latency", [&] { return program_main(argc, argv); });
}
