// `kerf mesh info FILE` (the validation report of a mesh file) and `kerf gen foot` (write the
// built-in synthetic forefoot to a file).
#include <charconv>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "display/mesh/foot_generator.hpp"
#include "display/mesh/mesh_io.hpp"
#include "display/mesh/validate.hpp"
#include "tools/kerf/commands.hpp"

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

std::string json_string(std::string_view s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
            out += buf;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

[[noreturn]] void fail(std::string_view command, std::string_view what, std::string_view why) {
    std::cerr << "kerf " << command << ": " << what << ": " << why << "\n";
    throw CLI::RuntimeError(kExitFailure);  // CLI11's way to leave with an exit code, silently
}

const CLI::Validator kUnitsValidator(
    [](std::string& value) {
        return mesh::parse_units(value) ? std::string{}
                                        : "'" + value + "' is not one of mm, m, cm, in, um";
    },
    "UNIT", "units");

void run_mesh_info(const MeshInfoOptions& o) {
    const mesh::Units units = *mesh::parse_units(o.units);
    auto loaded = mesh::load_mesh_file(o.file, units);
    if (!loaded) fail("mesh info", "cannot load mesh", loaded.error().to_string());
    mesh::ValidationReport report = mesh::validate(loaded->indexed);
    report.detached_triangles = loaded->detached_triangles;
    const auto format = mesh::format_from_path(o.file);
    if (o.json) {
        std::cout << "{\"file\": " << json_string(o.file) << ", \"format\": \""
                  << mesh::to_string(*format) << "\", \"units\": \"" << o.units
                  << "\", \"report\": " << mesh::format_report_json(report) << "}\n";
        return;
    }
    std::cout << "file:                  " << o.file << " (" << mesh::to_string(*format)
              << ", read as " << o.units << ")\n"
              << mesh::format_report_text(report, units);
}

void run_gen_foot(const GenFootOptions& o) {
    auto foot = mesh::generate_foot({o.triangles, o.seed});
    if (!foot) fail("gen foot", "--triangles", foot.error());
    auto saved = mesh::save_mesh(foot->mesh, o.output, *mesh::parse_units(o.units));
    if (!saved) fail("gen foot", "cannot write mesh", saved.error().to_string());
    const mesh::BoneInfo& m1 = foot->first_metatarsal();
    const double s = 1.0 / mesh::metres_per_unit(*mesh::parse_units(o.units));
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
