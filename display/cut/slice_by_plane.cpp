#include "display/cut/slice_by_plane.hpp"

#include <chrono>

#include "display/cut/apply_plan.hpp"
#include "display/cut/cap_chords.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/section_plan.hpp"

namespace kerf::cut {

namespace {

std::int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// Plans with `plan` (snapping vertices next to slivers, see plan_snapped), then edits.
CutResult finish(detail::ContextState& s, const Plane& plane,
                 const std::function<CutStatus()>& plan, CrossSection& out, std::int64_t t0) {
    CutResult r;
    std::vector<std::int32_t> snapped;
    detail::EditUndo chords;  // the chords put into earlier caps: kept on success
    const auto vertices_before = static_cast<std::uint32_t>(s.mesh.n_vertices());
    const auto faces_before = static_cast<std::uint32_t>(s.mesh.n_faces());
    r.status = detail::plan_through_caps(s, plane, snapped, plan, chords, r.stats.cap_chords);
    r.stats.vertices_added = static_cast<std::uint32_t>(s.mesh.n_vertices()) - vertices_before;
    r.stats.triangles_added = static_cast<std::uint32_t>(s.mesh.n_faces()) - faces_before;
    if (r.ok()) r.status = detail::apply_plan(s, plane, out, r.stats);
    r.stats.vertices_snapped = static_cast<std::uint32_t>(snapped.size());
    r.stats.time_ns = now_ns() - t0;
    return r;
}

}  // namespace

CutResult slice_by_plane(CutContext& ctx, const Plane& plane, CrossSection& out) {
    const std::int64_t t0 = now_ns();
    detail::ContextState& s = ctx.state();
    return finish(
        s, plane, [&] { return detail::plan_full(s, plane); }, out, t0);
}

CutResult slice_by_plane(CutContext& ctx, const Plane& plane, const Seed& seed, CrossSection& out) {
    const std::int64_t t0 = now_ns();
    detail::ContextState& s = ctx.state();
    return finish(
        s, plane, [&] { return detail::plan_localised(s, plane, seed); }, out, t0);
}

}  // namespace kerf::cut
