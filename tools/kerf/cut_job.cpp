#include "tools/kerf/cut_job.hpp"

#include <algorithm>
#include <cmath>

#include "display/cut/cut_context.hpp"
#include "display/cut/mesh_hash.hpp"
#include "display/cut/separate.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"

namespace kerf::cli {

std::string_view to_string(CutMode m) noexcept {
    switch (m) {
        case CutMode::kUniplanar:
            return "uniplanar";
        case CutMode::kBiplanar:
            return "biplanar";
        case CutMode::kSeparated:
            return "separated";
    }
    return "unknown";
}

std::optional<CutMode> parse_cut_mode(std::string_view text) noexcept {
    for (auto m : {CutMode::kUniplanar, CutMode::kBiplanar, CutMode::kSeparated}) {
        if (text == to_string(m)) return m;
    }
    return std::nullopt;
}

Status<CutJobError> check_cut_job(const CutJob& job) {
    if (job.planes.empty())
        return Err{CutJobError{0, cut::CutStatus::kInvalidArgument, "no plane"}};
    const std::size_t seeds = job.seeds_m.size();
    if (seeds > 1 && seeds != job.planes.size()) {
        return Err{CutJobError{0, cut::CutStatus::kInvalidArgument,
                               "give one --seed for all planes or one per plane (" +
                                   std::to_string(job.planes.size()) + " planes, " +
                                   std::to_string(seeds) + " seeds)"}};
    }
    if (job.mode != CutMode::kUniplanar && !(std::isfinite(job.kerf_m) && job.kerf_m > 0)) {
        return Err{CutJobError{
            0, cut::CutStatus::kInvalidArgument,
            std::string("mode ") + std::string(to_string(job.mode)) + " needs a positive --kerf"}};
    }
    if (job.mode == CutMode::kBiplanar && seeds == 0) {
        return Err{CutJobError{0, cut::CutStatus::kInvalidArgument,
                               "mode biplanar needs --seed (the slab is localised)"}};
    }
    for (std::size_t i = 0; i < job.planes.size(); ++i) {
        if (!cut::Plane::make(job.planes[i].point_m, job.planes[i].normal)) {
            return Err{
                CutJobError{i, cut::CutStatus::kInvalidPlane, "non-finite value or zero normal"}};
        }
    }
    return {};
}

namespace {

cut::CutResult cut_once(cut::CutContext& ctx, const cut::Plane& plane,
                        const std::optional<cut::Seed>& seed, const CutJob& job) {
    if (job.mode == CutMode::kBiplanar) {
        cut::SlabCut slab;
        return cut::subtract_slab(ctx, plane, job.kerf_m, *seed, slab);
    }
    cut::CrossSection cs;
    cut::CutResult r =
        seed ? cut::slice_by_plane(ctx, plane, *seed, cs) : cut::slice_by_plane(ctx, plane, cs);
    if (r.ok() && job.mode == CutMode::kSeparated) {
        auto sep = cut::Separator::make(ctx, cs, job.kerf_m);
        if (!sep) return cut::CutResult{sep.error(), r.stats};
        sep->sweep_all();
        // The separator leaves normals to whoever uses the mesh: refresh the faces it moved, so
        // later planes of the job split faces with current normals.
        mesh::TriMesh& m = ctx.mesh();
        for (const auto v : sep->moved_vertices())
            for (const auto f : m.vf_range(v)) m.set_normal(f, m.calc_face_normal(f));
    }
    return r;
}

}  // namespace

Result<CutReport, CutJobError> run_cut_job(mesh::TriMesh& mesh, const CutJob& job) {
    if (auto ok = check_cut_job(job); !ok) return Err{ok.error()};
    CutReport report;
    cut::CutContext ctx(mesh);
    for (std::size_t i = 0; i < job.planes.size(); ++i) {
        const auto plane = *cut::Plane::make(job.planes[i].point_m, job.planes[i].normal);
        std::optional<cut::Seed> seed;
        if (!job.seeds_m.empty()) {
            seed =
                cut::Seed{job.seeds_m[job.seeds_m.size() == 1 ? 0 : i], mesh::FaceHandle(), -1.0};
        }
        const cut::CutResult r = cut_once(ctx, plane, seed, job);
        if (!r.ok()) {
            return Err{
                CutJobError{i, r.status, "cut refused: " + std::string(to_string(r.status))}};
        }
        report.steps.push_back({i, r});
    }
    report.pieces = cut::group_cavities(cut::find_components(mesh));
    std::stable_sort(
        report.pieces.begin(), report.pieces.end(),
        [](const cut::Body& a, const cut::Body& b) { return a.volume_m3 > b.volume_m3; });
    report.mesh_hash = cut::mesh_hash(mesh);
    return report;
}

mesh::TriMesh extract_piece(const mesh::TriMesh& m, const cut::Body& piece) {
    mesh::TriMesh out = mesh::make_mesh();
    std::vector<int> renumber(m.n_vertices(), -1);
    for (const auto v : piece.vertices) {
        const auto w = out.add_vertex(m.point(v));
        out.set_normal(w, m.normal(v));
        out.set_texcoord2D(w, m.texcoord2D(v));
        out.set_color(w, m.color(v));
        out.data(w).set_material(m.data(v).material());
        renumber[static_cast<std::size_t>(v.idx())] = w.idx();
    }
    std::vector<mesh::VertexHandle> corners;
    for (const auto f : piece.faces) {
        corners.clear();
        for (const auto v : m.fv_range(f)) {
            corners.emplace_back(renumber[static_cast<std::size_t>(v.idx())]);
        }
        out.add_face(corners);
    }
    out.update_face_normals();
    return out;
}

}  // namespace kerf::cli
