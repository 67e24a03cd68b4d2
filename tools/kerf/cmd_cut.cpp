// `kerf cut IN --plane px,py,pz,nx,ny,nz [--plane ...] [--seed x,y,z ...] [--kerf W]
//  [--units mm] [--mode uniplanar|biplanar|separated] -o OUT [--json]`
//
// Cuts a mesh file plane by plane (several planes = sequential cuts, e.g. a chevron osteotomy)
// and writes each piece to its own file: OUT with the piece number before the extension
// (out.stl -> out_1.stl, out_2.stl, ...; piece 1 is the largest). Every number on the command line
// is in the file's units (--units). A --seed localises the cut to the bone it touches.
// Errors: `kerf cut: <what>: <where>: <why>`; bad arguments exit 2, a refused cut or bad file 1.
// Output is all-or-nothing: an output that is the input is refused, every piece is written to a
// temp file beside its target and renamed only when all are written, and pieces an earlier run
// left beyond this run's count are removed, so the folder never mixes two runs.
#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "config/file_io/file_io.hpp"
#include "display/mesh/bone_size.hpp"
#include "display/mesh/mesh_io.hpp"
#include "tools/kerf/commands.hpp"
#include "tools/kerf/cut_job.hpp"

namespace kerf::cli {
namespace {

struct CutOptions {
    std::string input;
    std::vector<std::string> planes;
    std::vector<std::string> seeds;
    std::string kerf;
    std::string units = "mm";
    std::string mode = "uniplanar";
    std::string output;
    bool json = false;
};

[[noreturn]] void fail(int code, std::string_view what, std::string_view where,
                       std::string_view why) {
    std::cerr << "kerf cut: " << what << ": " << where << ": " << why << "\n";
    throw CLI::RuntimeError(code);
}

/// Parses exactly `count` comma-separated finite numbers, or explains why not.
Result<std::vector<double>, std::string> parse_numbers(const std::string& text, std::size_t count) {
    std::vector<double> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        // strtod, not stod: a denormal like 4e-320 is a number (stod throws out_of_range).
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        const std::size_t used = std::size_t(end - item.c_str());
        if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos) {
            return Err{"'" + item + "' is not a number"};
        }
        if (!std::isfinite(v)) return Err{"'" + item + "' is not finite"};
        out.push_back(v);
    }
    if (out.size() != count || (!text.empty() && text.back() == ',')) {
        return Err{"expected " + std::to_string(count) + " comma-separated numbers, got '" + text +
                   "'"};
    }
    return out;
}

CutJob job_from(const CutOptions& o, double metres_per_unit) {
    CutJob job;
    const auto mode = parse_cut_mode(o.mode);
    if (!mode) fail(kExitUsage, "--mode", o.mode, "expected uniplanar, biplanar or separated");
    job.mode = *mode;
    for (std::size_t i = 0; i < o.planes.size(); ++i) {
        auto v = parse_numbers(o.planes[i], 6);
        if (!v)
            fail(kExitUsage, "--plane #" + std::to_string(i + 1), "px,py,pz,nx,ny,nz", v.error());
        const auto& p = *v;
        job.planes.push_back(
            {cut::Vec3(p[0], p[1], p[2]) * metres_per_unit, cut::Vec3(p[3], p[4], p[5])});
    }
    for (std::size_t i = 0; i < o.seeds.size(); ++i) {
        auto v = parse_numbers(o.seeds[i], 3);
        if (!v) fail(kExitUsage, "--seed #" + std::to_string(i + 1), "x,y,z", v.error());
        job.seeds_m.push_back(cut::Vec3((*v)[0], (*v)[1], (*v)[2]) * metres_per_unit);
    }
    if (!o.kerf.empty()) {
        auto v = parse_numbers(o.kerf, 1);
        if (!v || (*v)[0] <= 0) {
            fail(kExitUsage, "--kerf", o.kerf, v ? "must be positive" : v.error());
        }
        job.kerf_m = (*v)[0] * metres_per_unit;
    }
    if (auto ok = check_cut_job(job); !ok) {
        const auto& e = ok.error();
        if (e.code == cut::CutStatus::kInvalidPlane) {
            fail(kExitUsage, "--plane #" + std::to_string(e.plane + 1), o.planes[e.plane], e.what);
        }
        if (e.argument == "--kerf")
            fail(kExitUsage, "--kerf", o.kerf + " (--mode " + o.mode + ")", e.what);
        if (e.argument.rfind("--seed #", 0) == 0) {
            const std::size_t k = std::stoul(e.argument.substr(8)) - 1;
            fail(kExitUsage, e.argument, o.seeds[k], e.what);
        }
        fail(kExitUsage, "arguments", "--mode " + o.mode, e.what);
    }
    return job;
}

std::filesystem::path piece_path(const std::filesystem::path& out, std::size_t k) {
    std::filesystem::path p = out;
    p.replace_filename(out.stem().string() + "_" + std::to_string(k) + out.extension().string());
    return p;
}

void print_text(const CutOptions& o, const CutReport& r, const std::vector<std::string>& files,
                double unit) {
    const double u3 = unit * unit * unit;
    for (const auto& s : r.steps) {
        const auto& st = s.result.stats;
        std::cout << "cut " << s.plane + 1 << " (" << o.mode << "): " << st.loops << " loops, "
                  << st.faces_split << " faces split, " << st.vertices_added << " vertices added, "
                  << st.triangles_added << " triangles added (" << st.cap_triangles << " cap), "
                  << st.triangles_removed << " removed, " << static_cast<double>(st.time_ns) * 1e-6
                  << " ms\n";
    }
    std::cout << r.pieces.size() << " pieces:\n";
    for (std::size_t k = 0; k < r.pieces.size(); ++k) {
        const auto& b = r.pieces[k];
        std::cout << "  " << files[k] << ": " << b.faces.size() << " triangles, volume "
                  << b.volume_m3 / u3 << " " << o.units << "^3\n";
    }
    char hash[24];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(r.mesh_hash));
    std::cout << "mesh hash " << hash << "\n";
}

void print_json(const CutOptions& o, const CutReport& r, const std::vector<std::string>& files,
                double unit) {
    const double u3 = unit * unit * unit;
    nlohmann::ordered_json doc = {{"input", o.input}, {"units", o.units}, {"mode", o.mode}};
    doc["cuts"] = nlohmann::ordered_json::array();
    for (const auto& step : r.steps) {
        const auto& st = step.result.stats;
        doc["cuts"].push_back({{"plane", step.plane + 1},
                               {"loops", st.loops},
                               {"faces_split", st.faces_split},
                               {"vertices_added", st.vertices_added},
                               {"triangles_added", st.triangles_added},
                               {"cap_triangles", st.cap_triangles},
                               {"triangles_removed", st.triangles_removed},
                               {"time_ms", static_cast<double>(st.time_ns) * 1e-6}});
    }
    doc["pieces"] = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < r.pieces.size(); ++k) {
        doc["pieces"].push_back({{"file", files[k]},
                                 {"triangles", r.pieces[k].faces.size()},
                                 {"volume", r.pieces[k].volume_m3 / u3}});
    }
    char hash[24];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(r.mesh_hash));
    doc["mesh_hash"] = hash;
    // Paths are bytes, not always UTF-8: replace what JSON cannot carry instead of throwing.
    std::cout << doc.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
}

/// Pieces NAME_k.EXT with k > `count` left in the output folder by an earlier run.
std::vector<std::filesystem::path> stale_pieces(const std::filesystem::path& out,
                                                std::size_t count) {
    std::vector<std::filesystem::path> stale;
    const std::filesystem::path dir = out.parent_path().empty() ? "." : out.parent_path();
    const std::string prefix = out.stem().string() + "_", ext = out.extension().string();
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= prefix.size() + ext.size() || name.rfind(prefix, 0) != 0 ||
            name.compare(name.size() - ext.size(), ext.size(), ext) != 0) {
            continue;
        }
        const std::string number =
            name.substr(prefix.size(), name.size() - prefix.size() - ext.size());
        if (number.empty() || number.size() > 9 ||
            number.find_first_not_of("0123456789") != std::string::npos || number[0] == '0') {
            continue;
        }
        if (std::stoul(number) > count && entry.is_regular_file(ec)) {
            stale.push_back(piece_path(out, std::stoul(number)));
        }
    }
    return stale;
}

/// `kerf cut` runs once and exits: freed memory stays in the heap (no mmap per large block, no
/// trim), so the mesh, cut context and pieces built after loading reuse the pages that the file
/// buffer and the parse freed instead of faulting in fresh zeroed ones (on the 1M-triangle foot
/// this halves the page faults). Outputs do not depend on it; only where blocks lie does.
void keep_freed_memory_in_heap() {
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

void run_cut(const CutOptions& o) {
    keep_freed_memory_in_heap();
    const auto units = parse_length_unit(o.units);
    if (!units) fail(kExitUsage, "--units", o.units, "expected mm, m, cm, in or um");
    if (!mesh::format_from_path(o.output)) {
        fail(kExitUsage, "-o", o.output, "unknown extension (expected .stl .obj .ply .off)");
    }
    const double unit = metres_per_unit(*units);
    const CutJob job = job_from(o, unit);
    auto loaded = mesh::load_mesh_owned(o.input, *units);  // no copy of a large mesh
    if (!loaded) fail(kExitFailure, "cannot load mesh", o.input, loaded.error().message());
    const mesh::TriMesh& input = **loaded;
    if (input.n_vertices() > 0) {  // a metres file read as mm is a 0.2 mm "bone": say so
        mesh::Point lo = input.point(*input.vertices_begin()), hi = lo;
        for (const auto v : input.vertices()) {
            lo.minimize(input.point(v));
            hi.maximize(input.point(v));
        }
        const mesh::Point size = hi - lo;
        const std::string w =
            mesh::bone_size_warning(std::max({size[0], size[1], size[2]}), *units);
        if (!w.empty()) std::cerr << "kerf cut: warning: " << o.input << ": " << w << "\n";
    }
    auto report = run_cut_job(*loaded, job);
    if (!report) {
        const auto& e = report.error();
        fail(kExitFailure, "--plane #" + std::to_string(e.plane + 1), o.planes[e.plane], e.what);
    }
    // All pieces or none: every piece goes to a temp file first; the renames come last; pieces
    // of an earlier run beyond this run's count are removed once the new set is in place.
    std::vector<std::string> files;
    files::AtomicFileSet set;
    const auto format = *mesh::format_from_path(o.output);
    for (std::size_t k = 0; k < report->pieces.size(); ++k) {
        const auto path = piece_path(o.output, k + 1);
        const auto piece = extract_piece(**loaded, report->pieces[k]);
        set.add(path, mesh::serialize_mesh(piece, format, *units));
        files.push_back(path.string());
    }
    for (const auto& stale : stale_pieces(o.output, report->pieces.size()))
        set.remove_after_commit(stale);
    if (auto refused = set.refuse_inputs({o.input}); !refused) {
        fail(kExitFailure, "cannot write pieces", refused.error().where, refused.error().what);
    }
    if (auto written = set.commit(); !written) {
        fail(kExitFailure, "cannot write pieces", written.error().where, written.error().what);
    }
    if (o.json)
        print_json(o, *report, files, unit);
    else
        print_text(o, *report, files, unit);
}

}  // namespace

void add_cut_command(CLI::App& app) {
    auto o = std::make_shared<CutOptions>();
    CLI::App* cmd = app.add_subcommand(
        "cut", "Cut a mesh by one or more planes (sequential cuts) and write each piece");
    cmd->add_option("IN", o->input, "mesh file (.stl .obj .ply .off)")->required();
    cmd->add_option("--plane", o->planes,
                    "px,py,pz,nx,ny,nz: a point on the plane and its normal (file units); "
                    "repeat for sequential cuts")
        ->required();
    cmd->add_option("--seed", o->seeds,
                    "x,y,z: a surface point where the blade touches; localises the cut to that "
                    "bone; one for all planes or one per plane");
    cmd->add_option("--kerf", o->kerf, "blade width (file units); needed by biplanar, separated");
    cmd->add_option("--units", o->units,
                    "length unit of the file and of every number: mm, m, "
                    "cm, in, um")
        ->capture_default_str();
    cmd->add_option("--mode", o->mode,
                    "uniplanar (one plane), biplanar (remove a kerf-wide "
                    "slab) or separated (one plane, then the kerf opened)")
        ->capture_default_str();
    cmd->add_option("-o,--output", o->output,
                    "output file; piece k goes to NAME_k.EXT (.stl .obj .ply .off)")
        ->required();
    cmd->add_flag("--json", o->json, "print one JSON object instead of text");
    cmd->callback([o] { run_cut(*o); });
}

}  // namespace kerf::cli
