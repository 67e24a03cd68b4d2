// `kerf demo` — the README's main job. Today it builds the default scene (the built-in
// synthetic forefoot), validates it and says where the first metatarsal is. Each later stage
// is one named step in `run_demo()`: the cutting issue adds a chevron osteotomy of the first
// metatarsal between building and reporting; later issues add the simulated device, the
// real-time process and the display.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "display/mesh/foot_generator.hpp"
#include "display/mesh/validate.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/demo_chevron.hpp"

namespace kerf::cli {
namespace {

struct DemoOptions {
    std::size_t triangles = 200'000;
    std::uint64_t seed = 1;
    bool json = false;
};

/// Everything the demo works on.
struct DemoScene {
    mesh::Foot foot;
    double generate_ms = 0.0;
};

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

std::string mm(const mesh::Point& p) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f) mm", p[0] * 1e3, p[1] * 1e3, p[2] * 1e3);
    return buf;
}

Result<DemoScene, std::string> build_scene(const DemoOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    auto foot = mesh::generate_foot({o.triangles, o.seed});
    if (!foot) return Err{foot.error()};
    return DemoScene{std::move(*foot), ms_since(start)};
}

void print_first_metatarsal(const mesh::BoneInfo& m1) {
    std::cout << "first metatarsal:      axis " << mm(m1.base_m) << " to " << mm(m1.head_m)
              << ", length " << m1.length_m * 1e3 << " mm, shaft radius " << m1.shaft_radius_m * 1e3
              << " mm, canal radius " << m1.canal_radius_m * 1e3 << " mm\n";
}

void report_scene(const DemoScene& scene, const DemoOptions& o, nlohmann::ordered_json& doc) {
    const auto start = std::chrono::steady_clock::now();
    const mesh::ValidationReport report = mesh::validate(scene.foot.mesh);
    const double validate_ms = ms_since(start);
    if (o.json) {
        doc["scene"] = "builtin_foot";
        doc["seed"] = o.seed;
        doc["generate_ms"] = scene.generate_ms;
        doc["validate_ms"] = validate_ms;
        doc["report"] = nlohmann::ordered_json::parse(mesh::format_report_json(report));
        return;
    }
    std::cout << "kerf demo: built-in synthetic forefoot (seed " << o.seed << ", target "
              << o.triangles << " triangles), generated in " << scene.generate_ms
              << " ms, validated in " << validate_ms << " ms\n";
    print_first_metatarsal(scene.foot.first_metatarsal());
    std::cout << mesh::format_report_text(report, mesh::Units::kMillimetres);
}

/// The chevron osteotomy of the first metatarsal and its pieces (after the intact scene's report).
void report_chevron(DemoScene& scene, const DemoOptions& o, nlohmann::ordered_json& doc) {
    auto chevron = cut_chevron(scene.foot);
    if (!chevron) {
        std::cerr << "kerf demo: chevron osteotomy: first metatarsal: " << chevron.error() << "\n";
        throw CLI::RuntimeError(kExitFailure);
    }
    const ChevronReport& c = *chevron;
    if (o.json) {
        nlohmann::ordered_json out = {
            {"apex_mm", {c.apex_m[0] * 1e3, c.apex_m[1] * 1e3, c.apex_m[2] * 1e3}},
            {"ms", c.elapsed_ms},
            {"bodies", c.cuts.pieces.size()},
            {"fragments_mm3", nlohmann::ordered_json::array()}};
        for (const std::size_t k : c.fragments)
            out["fragments_mm3"].push_back(c.cuts.pieces[k].volume_m3 * 1e9);
        doc["chevron"] = out;
        return;
    }
    std::cout << "chevron osteotomy:     first metatarsal, apex " << mm(c.apex_m)
              << ", 60-degree V, seed " << mm(c.seed_m) << ", " << c.elapsed_ms << " ms\n";
    for (const auto& step : c.cuts.steps) {
        const auto& st = step.result.stats;
        std::cout << "  cut " << step.plane + 1 << ": " << st.loops << " loops, " << st.faces_split
                  << " faces split, " << st.triangles_added << " triangles added ("
                  << st.cap_triangles << " cap), " << static_cast<double>(st.time_ns) * 1e-6
                  << " ms\n";
    }
    std::cout << "  first metatarsal now " << c.fragments.size() << " pieces:";
    for (const std::size_t k : c.fragments) {
        std::cout << " " << c.cuts.pieces[k].volume_m3 * 1e9 << " mm^3";
    }
    std::cout << "; " << c.cuts.pieces.size() << " bodies in the scene\n";
}

void run_demo(const DemoOptions& o) {
    auto scene = build_scene(o);
    if (!scene) {
        std::cerr << "kerf demo: --triangles: " << scene.error() << "\n";
        throw CLI::RuntimeError(kExitFailure);
    }
    // Next stage (cutting issue): cut a chevron osteotomy of scene->foot.first_metatarsal().
    nlohmann::ordered_json doc;  // --json: one document, as the help promises
    report_scene(*scene, o, doc);
    report_chevron(*scene, o, doc);
    if (o.json) std::cout << doc.dump() << "\n";
}

}  // namespace

void add_demo_command(CLI::App& app) {
    auto opts = std::make_shared<DemoOptions>();
    CLI::App* demo = app.add_subcommand(
        "demo", "The main job: build the built-in forefoot and print its validation report");
    demo->add_option("--triangles", opts->triangles,
                     "approximate triangle count (10000 .. 4000000)")
        ->capture_default_str();
    demo->add_option("--seed", opts->seed, "generator seed")->capture_default_str();
    demo->add_flag("--json", opts->json, "print one JSON object instead of text");
    demo->callback([opts] { run_demo(*opts); });
}

}  // namespace kerf::cli
