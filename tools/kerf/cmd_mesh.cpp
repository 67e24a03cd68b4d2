// `kerf mesh info FILE` (the validation report of a mesh file) and `kerf gen foot` (write the
// built-in synthetic forefoot to a file).
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "display/mesh/bone_size.hpp"
#include "display/mesh/coincidence.hpp"
#include "display/mesh/foot_generator.hpp"
#include "display/mesh/mesh_io.hpp"
#include "display/mesh/validate.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/safe_text.hpp"

namespace kerf::cli {
namespace {

constexpr const char* kUnitsHelp =
    "length unit of the file: mm (default: STL carries no unit, and bone meshes are "
    "usually in millimetres), m, cm, in, um";

struct MeshInfoOptions {
    std::string file;
    std::string units = "mm";
    bool json = false;
};

struct GenFootOptions {
    std::size_t triangles = 200'000;
    std::uint64_t seed = 1;
    std::string output;
    std::string units = "mm";
};

[[noreturn]] void fail(std::string_view command, std::string_view what, std::string_view why) {
    std::cerr << "kerf " << command << ": " << what << ": " << why << "\n";
    throw CLI::RuntimeError(kExitFailure);  // CLI11's way to leave with an exit code, silently
}

const CLI::Validator kUnitsValidator(
    [](std::string& value) {
        return parse_length_unit(value) ? std::string{}
                                        : "'" + value + "' is not one of mm, m, cm, in, um";
    },
    "UNIT", "units");

nlohmann::ordered_json point_json(const mesh::Point& p) {
    return nlohmann::ordered_json::array({p[0], p[1], p[2]});
}

/// The validation report as JSON (SI units: keys end in _m, _m2, _m3).
nlohmann::ordered_json report_json(const mesh::ValidationReport& r) {
    nlohmann::ordered_json shells = nlohmann::ordered_json::array();
    for (const auto& s : r.shells) {
        shells.push_back({{"triangles", s.triangles},
                          {"vertices", s.vertices},
                          {"edges", s.edges},
                          {"boundary_edges", s.boundary_edges},
                          {"closed", s.closed},
                          {"euler_characteristic", s.euler_characteristic},
                          {"area_m2", s.area_m2},
                          {"volume_m3", s.volume_m3}});
    }
    nlohmann::ordered_json boundary = nlohmann::ordered_json::array();
    for (const auto& e : r.boundary_samples_m)
        boundary.push_back({point_json(e[0]), point_json(e[1])});
    return {{"vertices", r.vertices},
            {"unreferenced_vertices", r.unreferenced_vertices},
            {"triangles", r.triangles},
            {"edges", r.edges},
            {"closed", r.closed},
            {"boundary_edges", r.boundary_edges},
            {"non_manifold_edges", r.non_manifold_edges},
            {"non_manifold_vertices", r.non_manifold_vertices},
            {"oriented", r.oriented},
            {"misoriented_edges", r.misoriented_edges},
            {"degenerate_triangles", r.degenerate_triangles},
            {"detached_triangles", r.detached_triangles},
            {"bbox_min_m", point_json(r.bbox_min_m)},
            {"bbox_max_m", point_json(r.bbox_max_m)},
            {"area_m2", r.area_m2},
            {"volume_m3", r.volume_m3},
            {"shells", shells},
            {"boundary_samples_m", boundary}};
}

nlohmann::ordered_json coincidence_json(const mesh::CoincidenceReport& c) {
    nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
    for (const auto& p : c.vertex_samples) {
        pairs.push_back({{"vertices", {p.first, p.second}},
                         {"positions_m", {point_json(p.first_m), point_json(p.second_m)}},
                         {"distance_m", p.distance_m}});
    }
    nlohmann::ordered_json triangles = nlohmann::ordered_json::array();
    for (const auto& t : c.triangle_samples) triangles.push_back({t[0], t[1]});
    return {{"tolerance_m", c.tolerance_m},
            {"relative_tolerance", mesh::kCoincidenceRelativeTolerance},
            {"coincident_vertex_pairs", c.coincident_vertex_pairs},
            {"vertex_samples", pairs},
            {"repeated_triangles", c.repeated_triangles},
            {"triangle_samples", triangles},
            {"complete", c.complete}};
}

std::string point_text(const mesh::Point& p, double scale) {
    char b[96];
    std::snprintf(b, sizeof b, "(%.6g, %.6g, %.6g)", p[0] / scale, p[1] / scale, p[2] / scale);
    return b;
}

std::string coincidence_text(const mesh::CoincidenceReport& c, const mesh::ValidationReport& r,
                             const std::string& units) {
    const double s = metres_per_unit(*parse_length_unit(units));
    char b[160];
    std::string out;
    std::snprintf(b, sizeof b,
                  "coincident vertices:   %zu pairs closer than %.3g %s (%g of the bounding-box "
                  "diagonal)%s\n",
                  c.coincident_vertex_pairs, c.tolerance_m / s, units.c_str(),
                  mesh::kCoincidenceRelativeTolerance,
                  c.complete ? "" : " (search stopped early: at least this many)");
    out += b;
    for (const auto& p : c.vertex_samples) {
        std::snprintf(b, sizeof b, "  vertex %u and vertex %u, %.3g %s apart: ", p.first, p.second,
                      p.distance_m / s, units.c_str());
        out += b + point_text(p.first_m, s) + " and " + point_text(p.second_m, s) + "\n";
    }
    out += "repeated triangles:    " + std::to_string(c.repeated_triangles) +
           " (the same three vertices as an earlier triangle)\n";
    for (const auto& t : c.triangle_samples) {
        out += "  triangle " + std::to_string(t[0]) + " repeats triangle " + std::to_string(t[1]) +
               "\n";
    }
    if (r.closed && c.repeated_triangles > 0) {
        out +=
            "warning: 'closed' pairs repeated triangles with each other; coincident triangles "
            "enclose no volume, so the mesh is not a sound solid\n";
    }
    return out;
}

/// "warning: ..." when the mesh is implausibly small or large for a bone in `units`; "" if not.
std::string size_warning(const mesh::ValidationReport& r, LengthUnit units) {
    const mesh::Point size = r.bbox_max_m - r.bbox_min_m;
    const double largest = std::max({size[0], size[1], size[2]});
    const std::string w = r.vertices > 0 ? mesh::bone_size_warning(largest, units) : "";
    return w.empty() ? w : "warning: " + w + "\n";
}

void run_mesh_info(const MeshInfoOptions& o) {
    const LengthUnit units = *parse_length_unit(o.units);
    auto loaded = mesh::load_mesh_file(o.file, units);
    if (!loaded) fail("mesh info", "cannot load mesh", loaded.error().message());
    mesh::ValidationReport report = mesh::validate(loaded->indexed);
    report.detached_triangles = loaded->detached_triangles;
    const mesh::CoincidenceReport coincidence = mesh::find_coincidences(loaded->indexed);
    const auto format = mesh::format_from_path(o.file);
    const std::string warning = size_warning(report, units);
    if (!warning.empty()) std::cerr << "kerf mesh info: " << safe_text(o.file) << ": " << warning;
    if (o.json) {
        const nlohmann::ordered_json doc = {{"file", o.file},
                                            {"format", mesh::to_string(*format)},
                                            {"units", o.units},
                                            {"report", report_json(report)},
                                            {"coincidence", coincidence_json(coincidence)}};
        // Paths are bytes, not always UTF-8: replace what JSON cannot carry instead of throwing.
        std::cout << doc.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace)
                  << "\n";
        return;
    }
    std::cout << "file:                  " << safe_text(o.file) << " (" << mesh::to_string(*format)
              << ", read as " << o.units << ")\n"
              << mesh::format_report_text(report, units)
              << coincidence_text(coincidence, report, o.units);
}

void run_gen_foot(const GenFootOptions& o) {
    auto foot = mesh::generate_foot({o.triangles, o.seed});
    if (!foot) fail("gen foot", "--triangles", foot.error());
    auto saved = mesh::save_mesh(foot->mesh, o.output, *parse_length_unit(o.units));
    if (!saved) fail("gen foot", "cannot write mesh", saved.error().message());
    const mesh::BoneInfo& m1 = foot->first_metatarsal();
    const double s = 1.0 / metres_per_unit(*parse_length_unit(o.units));
    std::cout << "wrote " << o.output << ": " << foot->mesh.n_faces() << " triangles, "
              << foot->mesh.n_vertices() << " vertices, " << foot->bones.size()
              << " bones (38 shells), seed " << o.seed << ", units " << o.units << "\n"
              << "first metatarsal axis: (" << m1.base_m[0] * s << ", " << m1.base_m[1] * s << ", "
              << m1.base_m[2] * s << ") to (" << m1.head_m[0] * s << ", " << m1.head_m[1] * s
              << ", " << m1.head_m[2] * s << ") " << o.units << "\n";
}

}  // namespace

/// A whole number that fits 64 bits unsigned, written as plain digits: "-1" and 2^64 are usage
/// errors instead of wrapping to 18446744073709551615 or 0.
std::string plain_unsigned(const std::string& text) {
    std::uint64_t v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos ||
        r.ec != std::errc{} || r.ptr != text.data() + text.size()) {
        return "'" + text + "' is not a whole number 0 .. 18446744073709551615";
    }
    return {};
}

void add_mesh_commands(CLI::App& app) {
    CLI::App* mesh_cmd = app.add_subcommand("mesh", "Inspect mesh files");
    mesh_cmd->require_subcommand(1);
    auto info_opts = std::make_shared<MeshInfoOptions>();
    CLI::App* info = mesh_cmd->add_subcommand(
        "info",
        "Validation report of a mesh file (.stl .obj .ply .off): counts, closedness, "
        "manifoldness, orientation, shells, bounding box, area, volume");
    info->add_option("FILE", info_opts->file, "mesh file")->required();
    info->add_option("--units", info_opts->units, kUnitsHelp)
        ->check(kUnitsValidator)
        ->capture_default_str();
    info->add_flag("--json", info_opts->json, "print one JSON object (SI units) instead of text");
    info->callback([info_opts] { run_mesh_info(*info_opts); });

    CLI::App* gen = app.add_subcommand("gen", "Generate built-in meshes");
    gen->require_subcommand(1);
    auto foot_opts = std::make_shared<GenFootOptions>();
    CLI::App* foot = gen->add_subcommand(
        "foot",
        "Write the built-in synthetic forefoot (19 bones, cortical shell + medullary canal)");
    foot->add_option("--triangles", foot_opts->triangles,
                     "approximate triangle count (10000 .. 4000000)")
        ->check(plain_unsigned)
        ->capture_default_str();
    foot->add_option("--seed", foot_opts->seed, "seed of the small per-bone shape variation")
        ->check(plain_unsigned)
        ->capture_default_str();
    foot->add_option("-o,--output", foot_opts->output, "output file (.stl .obj .ply .off)")
        ->required();
    foot->add_option("--units", foot_opts->units,
                     "length unit to write: mm (default), m, cm, in, um")
        ->check(kUnitsValidator)
        ->capture_default_str();
    foot->callback([foot_opts] { run_gen_foot(*foot_opts); });
}

}  // namespace kerf::cli
