#include "tools/kerf/cut_job.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "display/cut/cut_context.hpp"
#include "display/cut/cut_session.hpp"
#include "display/cut/mesh_hash.hpp"
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

CutJobError cut_job_error(std::size_t plane, cut::CutStatus code, std::string what, bool whole_job,
                          std::string argument) {
    CutJobError e;
    e.code = code;
    if (!argument.empty())
        e.where = argument;
    else
        e.where = whole_job ? std::string("cut job") : "plane #" + std::to_string(plane + 1);
    e.what = std::move(what);
    e.plane = plane;
    e.argument = std::move(argument);
    return e;
}

Status<CutJobError> check_cut_job(const CutJob& job) {
    if (job.planes.empty())
        return Err{cut_job_error(0, cut::CutStatus::kInvalidArgument, "no plane", true)};
    const std::size_t seeds = job.seeds_m.size();
    if (seeds > 1 && seeds != job.planes.size()) {
        return Err{cut_job_error(0, cut::CutStatus::kInvalidArgument,
                                 "give one --seed for all planes or one per plane (" +
                                     std::to_string(job.planes.size()) + " planes, " +
                                     std::to_string(seeds) + " seeds)",
                                 true)};
    }
    if (job.mode != CutMode::kUniplanar && !(std::isfinite(job.kerf_m) && job.kerf_m > 0)) {
        return Err{cut_job_error(
            0, cut::CutStatus::kInvalidArgument,
            std::string("mode ") + std::string(to_string(job.mode)) + " needs a positive --kerf",
            true)};
    }
    if (job.mode == CutMode::kUniplanar && job.kerf_m != 0.0) {
        return Err{cut_job_error(0, cut::CutStatus::kInvalidArgument,
                                 "mode uniplanar cuts along one plane and has no use for a blade "
                                 "width: leave --kerf out, or use --mode separated (one plane, "
                                 "then the kerf opened) or --mode biplanar (a kerf-wide slab)",
                                 true, "--kerf")};
    }
    if (job.mode == CutMode::kBiplanar && seeds == 0) {
        return Err{cut_job_error(0, cut::CutStatus::kInvalidArgument,
                                 "mode biplanar needs --seed (the slab is localised)", true)};
    }
    for (std::size_t i = 0; i < job.planes.size(); ++i) {
        if (!cut::Plane::make(job.planes[i].point_m, job.planes[i].normal)) {
            return Err{
                cut_job_error(i, cut::CutStatus::kInvalidPlane, "non-finite value or zero normal")};
        }
    }
    // A seed is where the blade touches the bone: on its plane (every mode; biplanar used to be
    // the only one to notice, through the cut library).
    for (std::size_t i = 0; i < job.planes.size() && seeds > 0; ++i) {
        const std::size_t k = seeds == 1 ? 0 : i;
        const auto plane = *cut::Plane::make(job.planes[i].point_m, job.planes[i].normal);
        const double off = std::abs(plane.signed_distance(job.seeds_m[k]));
        if (!(off <= kSeedPlaneTolerance_m)) {
            char why[200];
            std::snprintf(why, sizeof why,
                          "%.4g mm from plane #%zu (more than %.2g mm): a seed is where the "
                          "blade touches the bone, so it lies on the blade's plane",
                          off * 1e3, i + 1, kSeedPlaneTolerance_m * 1e3);
            return Err{cut_job_error(i, cut::CutStatus::kInvalidArgument, why, false,
                                     "--seed #" + std::to_string(k + 1))};
        }
    }
    return {};
}

std::string refusal_text(cut::CutStatus status) {
    std::string words;
    switch (status) {
        case cut::CutStatus::kOk:
            words = "the mesh was cut";
            break;
        case cut::CutStatus::kPlaneMissesMesh:
            words =
                "the plane crosses no triangle of the mesh: check the plane's point and "
                "normal (and --units)";
            break;
        case cut::CutStatus::kSeedNotOnSurface:
            words =
                "the seed is not on the mesh's surface: give a point where the blade touches "
                "the bone";
            break;
        case cut::CutStatus::kSeedFarFromCut:
            words =
                "no part of the cross-section is reachable from the seed near the plane: put "
                "the seed where the plane meets the bone";
            break;
        case cut::CutStatus::kSeedOnInnerBoundary:
            words =
                "the seed's cross-section loop is a hole with no outer boundary around it (an "
                "inward-facing shell): check the mesh's orientation, or seed on the outer surface";
            break;
        case cut::CutStatus::kNonManifoldInput:
            words =
                "the mesh is not a closed manifold where the plane passes (an open edge or a "
                "broken fan; see kerf mesh info): repair the mesh or move the plane";
            break;
        case cut::CutStatus::kInvalidPlane:
            words = "the plane has a non-finite value or a zero normal";
            break;
        case cut::CutStatus::kInvalidArgument:
            words = "an argument is out of range (e.g. a kerf width that is not positive)";
            break;
        case cut::CutStatus::kDegenerateCrossSection:
            words =
                "the cross-section pinches at a vertex or along an edge: move or tilt the "
                "plane slightly";
            break;
        case cut::CutStatus::kCapTriangulationFailed:
            words =
                "the cut face could not be filled without sliver triangles: move or tilt the "
                "plane slightly";
            break;
        case cut::CutStatus::kSliverSplit:
            words =
                "the plane passes so near a vertex of a thin triangle that a piece would have "
                "almost no area: move the plane by a fraction of a millimetre";
            break;
        case cut::CutStatus::kInternalError:
            words = "an internal check failed; please report this with the mesh and the command";
            break;
    }
    return words + " [" + std::string(cut::to_string(status)) + "]";
}

namespace {

/// A slab or a whole-plane cut: not something a blade event does, so not a CutSession edit.
cut::CutResult cut_directly(cut::CutContext& ctx, const cut::Plane& plane,
                            const std::optional<cut::Seed>& seed, const CutJob& job) {
    if (job.mode == CutMode::kBiplanar) {
        cut::SlabCut slab;
        return cut::subtract_slab(ctx, plane, job.kerf_m, *seed, slab);
    }
    cut::CrossSection cs;
    return cut::slice_by_plane(ctx, plane, cs);
}

/// Biplanar cuts and cuts without a seed, plane by plane.
Status<CutJobError> run_directly(mesh::TriMesh& mesh, const CutJob& job, CutReport& report) {
    cut::CutContext ctx(mesh);
    for (std::size_t i = 0; i < job.planes.size(); ++i) {
        const auto plane = *cut::Plane::make(job.planes[i].point_m, job.planes[i].normal);
        std::optional<cut::Seed> seed;
        if (!job.seeds_m.empty()) {
            seed = cut::Seed{job.seeds_m[job.seeds_m.size() == 1 ? 0 : i], mesh::FaceHandle(), -1};
        }
        const cut::CutResult r = cut_directly(ctx, plane, seed, job);
        if (!r.ok()) {
            return Err{cut_job_error(i, r.status, "cut refused: " + refusal_text(r.status))};
        }
        report.steps.push_back({i, r});
    }
    return {};
}

/// Seeded uniplanar and separated cuts: the blade events a CutSession applies (begin, then a
/// completed end, but for the last uniplanar cut; the kerf opens fully in separated mode), so the
/// CLI cuts as the display does.
Status<CutJobError> run_in_session(std::unique_ptr<mesh::TriMesh>& mesh, const CutJob& job,
                                   CutReport& report) {
    cut::CutSession session(std::move(mesh));
    Status<CutJobError> status;
    for (std::size_t i = 0; i < job.planes.size(); ++i) {
        const auto plane = *cut::Plane::make(job.planes[i].point_m, job.planes[i].normal);
        cut::CutBegin begin;
        begin.cut_id = static_cast<std::uint32_t>(i + 1);
        begin.blade = cut::BladeFrame{plane.point(), plane.normal(), plane.u()};
        begin.seed_m = job.seeds_m[job.seeds_m.size() == 1 ? 0 : i];
        begin.body_id = session.body_at(begin.seed_m);
        begin.kerf_width_m = job.mode == CutMode::kSeparated ? job.kerf_m : 0.0;
        const cut::ApplyReport r = session.begin(begin);
        if (r.outcome != cut::EventOutcome::kApplied) {
            status = Err{cut_job_error(i, r.status, "cut refused: " + refusal_text(r.status))};
            break;
        }
        // Ending a cut opens a separated cut's kerf (the mesh changes) and finds the pieces the
        // cut severed, for the bodies the next plane's seed is looked up in. After the last
        // uniplanar cut nothing reads those bodies (the pieces are found over the whole mesh
        // below), so that cut is left open: the same mesh without a second search for pieces.
        if (job.mode == CutMode::kSeparated || i + 1 < job.planes.size())
            (void)session.end({begin.cut_id, cut::CutEndKind::kCompleted});
        report.steps.push_back({i, cut::CutResult{cut::CutStatus::kOk, r.slice}});
    }
    mesh = std::move(session).release_owned();
    return status;
}

}  // namespace

Result<CutReport, CutJobError> run_cut_job(std::unique_ptr<mesh::TriMesh>& mesh,
                                           const CutJob& job) {
    if (auto ok = check_cut_job(job); !ok) return Err{ok.error()};
    CutReport report;
    const bool in_session = job.mode != CutMode::kBiplanar && !job.seeds_m.empty();
    auto done = in_session ? run_in_session(mesh, job, report) : run_directly(*mesh, job, report);
    if (!done) return Err{done.error()};
    report.pieces = cut::group_cavities(cut::find_components(*mesh));
    std::stable_sort(
        report.pieces.begin(), report.pieces.end(),
        [](const cut::Body& a, const cut::Body& b) { return a.volume_m3 > b.volume_m3; });
    report.mesh_hash = cut::mesh_hash(*mesh);
    return report;
}

mesh::IndexedMesh extract_piece(const mesh::TriMesh& m, const cut::Body& piece) {
    mesh::IndexedMesh out;
    // Only the entries of this piece's vertices are written and read: no need to clear the rest.
    const auto renumber = std::make_unique_for_overwrite<std::uint32_t[]>(m.n_vertices());
    out.positions_m.reserve(piece.vertices.size());
    out.materials.reserve(piece.vertices.size());
    for (const auto v : piece.vertices) {
        renumber[static_cast<std::size_t>(v.idx())] =
            static_cast<std::uint32_t>(out.positions_m.size());
        out.positions_m.push_back(m.point(v));
        out.materials.push_back(m.data(v).material());
    }
    out.triangles.reserve(piece.faces.size());
    for (const auto f : piece.faces) {
        // The corners as fv_range() gives them (from the face's half-edge, following next, until
        // back at it; none without a half-edge), straight from the half-edge arrays.
        mesh::Triangle t{};
        std::size_t k = 0;
        const mesh::HalfedgeHandle first = m.halfedge_handle(f);
        for (mesh::HalfedgeHandle h = first; h.is_valid();) {
            if (k < 3) t[k] = renumber[static_cast<std::size_t>(m.to_vertex_handle(h).idx())];
            ++k;
            h = m.next_halfedge_handle(h);
            if (h == first) break;
        }
        if (k == 3) out.triangles.push_back(t);
    }
    return out;
}

}  // namespace kerf::cli
