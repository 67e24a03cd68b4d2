#include "display/cut/subtract_slab.hpp"

#include <chrono>
#include <cmath>
#include <vector>

#include "display/cut/apply_plan.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/section_plan.hpp"

namespace kerf::cut {

namespace {

using mesh::FaceHandle;
using mesh::TriMesh;
using mesh::VertexHandle;

std::int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// Faces around the planned lower loops' cut points (the faces the lower plane crosses).
std::vector<FaceHandle> lower_loop_faces(const detail::ContextState& s) {
    std::vector<FaceHandle> out;
    const TriMesh& m = s.mesh;
    for (const detail::PlanLoop& l : s.plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const detail::CutPointKey k = s.plan.points[i].key;
            if (k.edge) {
                for (int j = 0; j < 2; ++j)
                    out.push_back(m.face_handle(m.halfedge_handle(mesh::EdgeHandle(k.id), j)));
            } else {
                for (auto f : m.vf_range(VertexHandle(k.id))) out.push_back(f);
            }
        }
    }
    return out;
}

// Breadth-first over faces overlapping the slab (some vertex above lower - tol, some vertex
// below upper) from `start`; returns the faces that cross the upper plane.
std::vector<FaceHandle> upper_crossings(detail::ContextState& s, const Plane& lower,
                                        const Plane& upper, std::vector<FaceHandle> frontier) {
    TriMesh& m = s.mesh;
    const double tol = s.tolerance_m;
    s.next_generation();
    std::vector<FaceHandle> crossing;
    auto in_band = [&](FaceHandle f) {
        double lo_max = -1e300, up_min = 1e300, up_max = -1e300;
        for (auto v : m.fv_range(f)) {
            lo_max = std::max(lo_max, lower.signed_distance(m.point(v)));
            const double du = upper.signed_distance(m.point(v));
            up_min = std::min(up_min, du), up_max = std::max(up_max, du);
        }
        if (up_min < -tol && up_max > tol) crossing.push_back(f);
        return lo_max > tol && up_min < tol;
    };
    std::vector<FaceHandle> queue;
    for (FaceHandle f : frontier)
        if (f.is_valid() && !s.face_marked(f) && m.property(s.cap, f) == kCapNone) {
            s.mark_face(f);
            if (in_band(f)) queue.push_back(f);
        }
    for (std::size_t i = 0; i < queue.size(); ++i)
        for (auto g : m.ff_range(queue[i]))
            if (!s.face_marked(g)) {
                s.mark_face(g);
                if (in_band(g)) queue.push_back(g);
            }
    return crossing;
}

// Faces connected to `start` (the lower wall's inner cap): the slab piece(s).
std::vector<FaceHandle> slab_faces(detail::ContextState& s, const std::vector<FaceHandle>& start) {
    TriMesh& m = s.mesh;
    s.next_generation();
    std::vector<FaceHandle> out;
    for (FaceHandle f : start)
        if (!s.face_marked(f)) s.mark_face(f), out.push_back(f);
    for (std::size_t i = 0; i < out.size(); ++i)
        for (auto g : m.ff_range(out[i]))
            if (!s.face_marked(g)) s.mark_face(g), out.push_back(g);
    return out;
}

void add(CutStats& into, const CutStats& a) {
    into.faces_split += a.faces_split;
    into.vertices_added += a.vertices_added;
    into.triangles_added += a.triangles_added;
    into.loops += a.loops;
}

}  // namespace

CutResult subtract_slab(CutContext& ctx, const Plane& plane, double kerf_width_m, const Seed& seed,
                        SlabCut& out) {
    const std::int64_t t0 = now_ns();
    detail::ContextState& s = ctx.state();
    CutResult r;
    auto done = [&](CutStatus st) {
        r.status = st;
        r.stats.time_ns = now_ns() - t0;
        return r;
    };
    if (!std::isfinite(kerf_width_m) || !(kerf_width_m > 20.0 * s.tolerance_m))
        return done(CutStatus::kInvalidArgument);
    const Plane lower = plane.offset(-0.5 * kerf_width_m);
    const Plane upper = plane.offset(0.5 * kerf_width_m);
    // Dry run on the unedited mesh: both walls must plan and cap.
    CutStatus st = detail::plan_localised(s, lower, seed);
    if (st == CutStatus::kOk) st = detail::finish_plan(s, lower);
    if (st != CutStatus::kOk) return done(st);
    const std::vector<FaceHandle> upper_faces =
        upper_crossings(s, lower, upper, lower_loop_faces(s));
    if (!upper_faces.empty()) {
        st = detail::plan_from_faces(s, upper, upper_faces);
        if (st == CutStatus::kOk) st = detail::finish_plan(s, upper);
        if (st != CutStatus::kOk && st != CutStatus::kPlaneMissesMesh) return done(st);
    }
    // Lower wall.
    st = detail::plan_localised(s, lower, seed);
    if (st == CutStatus::kOk) st = detail::finish_plan(s, lower);
    if (st == CutStatus::kOk) st = detail::apply_plan(s, lower, out.lower, r.stats);
    if (st != CutStatus::kOk) return done(st == CutStatus::kOk ? st : CutStatus::kInternalError);
    // Upper wall: every loop reachable from the lower wall's positive side through the slab.
    std::vector<FaceHandle> frontier;
    for (const auto& loop : out.lower.positive.loops)
        for (VertexHandle v : loop)
            for (auto f : s.mesh.vf_range(v)) frontier.push_back(f);
    out.upper.clear();
    out.upper.plane = upper;
    const std::vector<FaceHandle> crossings = upper_crossings(s, lower, upper, frontier);
    if (!crossings.empty()) {
        CutStats upper_stats;
        st = detail::plan_from_faces(s, upper, crossings);
        if (st == CutStatus::kOk) st = detail::finish_plan(s, upper);
        if (st == CutStatus::kOk) st = detail::apply_plan(s, upper, out.upper, upper_stats);
        if (st != CutStatus::kOk && st != CutStatus::kPlaneMissesMesh)
            return done(CutStatus::kInternalError);
        add(r.stats, upper_stats);
        r.stats.cap_triangles += upper_stats.cap_triangles;
    }
    // Remove the slab: everything connected to the lower wall's inner cap.
    const std::vector<FaceHandle> slab = slab_faces(s, out.lower.positive.cap_faces);
    for (FaceHandle f : slab)
        for (auto v : s.mesh.fv_range(f))
            if (upper.signed_distance(s.mesh.point(v)) > s.tolerance_m)
                return done(CutStatus::kInternalError);
    for (FaceHandle f : slab) s.mesh.delete_face(f, true);
    r.stats.triangles_removed = static_cast<std::uint32_t>(slab.size());
    r.stats.cap_triangles /= 2;  // only one cap of each slice remains
    return done(CutStatus::kOk);
}

}  // namespace kerf::cut
