#include "display/cut/subtract_slab.hpp"

#include <chrono>
#include <cmath>
#include <vector>

#include "display/cut/apply_plan.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/edit_undo.hpp"
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

// Faces around the cut points of the plan's selected loops (the faces its plane crosses there).
std::vector<FaceHandle> loop_faces(const detail::ContextState& s) {
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

std::size_t selected_loops(const detail::ContextState& s) {
    std::size_t n = 0;
    for (const detail::PlanLoop& l : s.plan.loops) n += l.selected;
    return n;
}

// The faces of one slab component's walls: those touching the lower and the upper plane.
struct WallFaces {
    std::vector<FaceHandle> lower;
    std::vector<FaceHandle> upper;
};

// Breadth-first over the faces overlapping the slab (some vertex above lower + tol, some vertex
// not above upper + tol) from `frontier`: the surface of the slab component(s) it touches.
// Appends the faces that touch either plane with material on both sides of it. The search starts
// from the frontier's uncapped faces, then from its caps of earlier cuts not reached yet (where
// such caps alone bound the slab, the walls cross them). `frontier` holds none of this cut's caps.
void band_walls(detail::ContextState& s, const Plane& lower, const Plane& upper,
                const std::vector<FaceHandle>& frontier, WallFaces& out) {
    TriMesh& m = s.mesh;
    const double tol = s.tolerance_m;
    s.next_generation();
    auto in_band = [&](FaceHandle f) {
        double lo_min = 1e300, lo_max = -1e300, up_min = 1e300, up_max = -1e300;
        for (auto v : m.fv_range(f)) {
            const double dl = lower.signed_distance(m.point(v));
            const double du = upper.signed_distance(m.point(v));
            lo_min = std::min(lo_min, dl), lo_max = std::max(lo_max, dl);
            up_min = std::min(up_min, du), up_max = std::max(up_max, du);
        }
        if (lo_min < tol && lo_max > tol) out.lower.push_back(f);
        if (up_min < -tol && up_max > -tol) out.upper.push_back(f);
        return lo_max > tol && up_min < tol;
    };
    std::vector<FaceHandle> queue;
    std::size_t next = 0;
    auto search = [&](bool caps) {
        for (FaceHandle f : frontier)
            if (f.is_valid() && !s.face_marked(f) && (m.property(s.cap, f) != kCapNone) == caps) {
                s.mark_face(f);
                if (in_band(f)) queue.push_back(f);
            }
        for (; next < queue.size(); ++next)
            for (auto g : m.ff_range(queue[next]))
                if (!s.face_marked(g)) {
                    s.mark_face(g);
                    if (in_band(g)) queue.push_back(g);
                }
    };
    search(false);
    search(true);
}

// Finds every loop bounding the slab component that holds the seed, on both walls, on the
// unedited mesh: a loop of the seed's component and its nested loops, then (until nothing new is
// found) every wall loop the slab surface reaches from the loops found so far, with the loops
// nested in them. The first loop is one the slab surface reaches from the seed's face: on the
// lower wall, or on the upper wall when the component does not reach the lower one (a tip
// ending inside the slab; the crossing nearest the seed on the lower plane then lay on another
// component, which was removed instead). A seed face outside the slab starts from the lower
// plane's crossing nearest the seed, as a localised slice does.
CutStatus find_walls(detail::ContextState& s, const Plane& lower, const Plane& upper,
                     const Seed& seed, WallFaces& walls) {
    const FaceHandle seed_face = detail::find_seed_face(s, seed);
    if (!seed_face.is_valid()) return CutStatus::kSeedNotOnSurface;
    WallFaces reached;
    band_walls(s, lower, upper, {seed_face}, reached);
    CutStatus st = CutStatus::kPlaneMissesMesh;
    if (!reached.lower.empty()) st = detail::plan_localised_on(s, lower, reached.lower);
    std::size_t lower_loops = 0, upper_loops = 0;
    if (st == CutStatus::kPlaneMissesMesh && !reached.upper.empty()) {
        st = detail::plan_localised_on(s, upper, reached.upper);
        if (st != CutStatus::kOk) return st;
        walls.upper = loop_faces(s);
        upper_loops = selected_loops(s);
    } else {
        if (st == CutStatus::kPlaneMissesMesh) st = detail::plan_localised(s, lower, seed);
        if (st != CutStatus::kOk) return st;
        walls.lower = loop_faces(s);
        lower_loops = selected_loops(s);
    }
    for (int round = 0; round < 16; ++round) {
        std::vector<FaceHandle> frontier = walls.lower;
        frontier.insert(frontier.end(), walls.upper.begin(), walls.upper.end());
        WallFaces found;
        band_walls(s, lower, upper, frontier, found);
        found.lower.insert(found.lower.end(), walls.lower.begin(), walls.lower.end());
        found.upper.insert(found.upper.end(), walls.upper.begin(), walls.upper.end());
        std::size_t up = 0;
        if (!found.upper.empty()) {
            st = detail::plan_wall(s, upper, found.upper);
            if (st != CutStatus::kOk && st != CutStatus::kPlaneMissesMesh) return st;
            walls.upper = st == CutStatus::kOk ? loop_faces(s) : std::vector<FaceHandle>{};
            up = st == CutStatus::kOk ? selected_loops(s) : 0;
        }
        std::size_t lo = 0;
        if (!found.lower.empty()) {
            st = detail::plan_wall(s, lower, found.lower);
            if (st != CutStatus::kOk && st != CutStatus::kPlaneMissesMesh) return st;
            walls.lower = st == CutStatus::kOk ? loop_faces(s) : std::vector<FaceHandle>{};
            lo = st == CutStatus::kOk ? selected_loops(s) : 0;
        }
        if (lo == 0 && up == 0) return CutStatus::kInternalError;
        if (lo == lower_loops && up == upper_loops) return CutStatus::kOk;
        lower_loops = lo, upper_loops = up;
    }
    return CutStatus::kInternalError;
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

// Trades diagonal e of the quad its two faces form for the other diagonal, when OpenMesh allows
// it and both new triangles keep the first face's orientation and are not too small; otherwise
// the mesh is left as it was.
bool try_flip(detail::ContextState& s, mesh::EdgeHandle e) {
    TriMesh& m = s.mesh;
    if (!m.is_flip_ok(e)) return false;
    const mesh::HalfedgeHandle h = m.halfedge_handle(e, 0);
    const FaceHandle f = m.face_handle(h), g = m.face_handle(m.opposite_halfedge_handle(h));
    const Vec3 n = m.normal(f);
    m.flip(e);
    auto fine = [&](FaceHandle t) {
        auto it = m.cfv_iter(t);
        const Vec3 a = m.point(*it++), b = m.point(*it++), c = m.point(*it);
        const Vec3 x = OpenMesh::cross(b - a, c - a);
        return OpenMesh::dot(x, n) > 0 && !s.too_small(a, b, c, x.sqrnorm());
    };
    if (fine(f) && fine(g)) return true;
    m.flip(e);
    return false;
}

// A needle the first wall's split can leave on the slab side: a face (x, a, b) with a, b
// consecutive vertices of `rim` (that wall's rim on the slab side, a few tolerances apart) and x
// beyond the other wall (`beyond`: that wall's plane facing away from the slab),
// made where a crossed face (often a thin cap triangle of an earlier cut) was split with its quad
// part's diagonal from x. Where the upper plane crosses such a face more than kSnapTolerances
// tolerances from x, the corner it cuts off is a sliver no snap mends, though the quad's other
// diagonal leaves none (the dry run, on the unsplit face, saw none). Flips that diagonal (an edge
// x-a or x-b whose other face is a piece of the same original face: the same cap tag and normal)
// for every such face, when both new triangles keep the orientation and are not too small, and
// returns how many it flipped; the flipped faces go into the face tree again (their boxes
// changed; queries skip a face met twice). Geometry and volume are unchanged: the two triangles
// still tile the same planar quad. O(rim vertices of the lower wall).
int flip_rim_needles(detail::ContextState& s, const Plane& beyond,
                     const std::vector<std::vector<VertexHandle>>& rim) {
    TriMesh& m = s.mesh;
    const double tol = s.tolerance_m;
    int flipped = 0;
    for (const auto& loop : rim)
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const VertexHandle a = loop[i], b = loop[(i + 1) % loop.size()];
            for (mesh::HalfedgeHandle h : {m.find_halfedge(a, b), m.find_halfedge(b, a)}) {
                if (!h.is_valid()) continue;
                const FaceHandle f = m.face_handle(h);
                if (!f.is_valid()) continue;
                const mesh::HalfedgeHandle hx = m.next_halfedge_handle(h);  // to x
                if (!(beyond.signed_distance(m.point(m.to_vertex_handle(hx))) > tol)) continue;
                for (mesh::HalfedgeHandle d : {hx, m.next_halfedge_handle(hx)}) {
                    const FaceHandle g = m.opposite_face_handle(d);
                    if (!g.is_valid() || m.property(s.cap, g) != m.property(s.cap, f) ||
                        m.normal(g) != m.normal(f) || !try_flip(s, m.edge_handle(d)))
                        continue;
                    s.tree.insert(m, f);
                    s.tree.insert(m, g);
                    ++flipped;
                    break;
                }
            }
        }
    return flipped;
}

void add(CutStats& into, const CutStats& a) {
    into.faces_split += a.faces_split;
    into.vertices_added += a.vertices_added;
    into.vertices_merged += a.vertices_merged;
    into.vertices_snapped += a.vertices_snapped;
    into.triangles_added += a.triangles_added;
    into.loops += a.loops;
}

// One wall of the slab.
struct Wall {
    Plane plane;                        ///< its plane
    Plane outward;                      ///< the same plane facing away from the slab
    bool slab_positive;                 ///< whether the slab lies on the positive side of `plane`
    std::vector<FaceHandle> faces;      ///< the faces the dry run found on it
    std::vector<std::int32_t> snapped;  ///< vertices plan_snapped takes as on it
    CrossSection* cut;                  ///< its slice
};

// Cuts wall `first` with the current plan (s.plan, made on the unedited mesh), then plans wall
// `second` again on the edited mesh and cuts it. The faces the first cut split are reached again
// through the slab from the first wall's rim on the slab side (not through its caps). The second
// plan can meet a needle the first split left, a face whose far corner lies just beyond the
// second plane, of which that plane would cut a corner too small to keep and too far to snap: on
// such a refusal the needles' diagonals are flipped and the plan made once more. Every edit is
// recorded in `undo`; on a refusal (its status) or a failure the caller restores it.
CutStatus cut_walls(detail::ContextState& s, const Plane& lower, const Plane& upper, Wall& first,
                    Wall& second, detail::EditUndo& undo, CutStats& stats) {
    undo.record(s);
    if (detail::apply_plan(s, first.plane, *first.cut, stats) != CutStatus::kOk)
        return CutStatus::kInternalError;
    const auto& rim = first.slab_positive ? first.cut->positive.loops : first.cut->negative.loops;
    s.next_generation();
    for (FaceHandle f : first.cut->positive.cap_faces) s.mark_face(f);
    for (FaceHandle f : first.cut->negative.cap_faces) s.mark_face(f);
    std::vector<FaceHandle> frontier;
    for (const auto& loop : rim)
        for (VertexHandle v : loop)
            for (auto f : s.mesh.vf_range(v))
                if (!s.face_marked(f)) frontier.push_back(f);
    WallFaces after;
    band_walls(s, lower, upper, frontier, after);
    std::vector<FaceHandle>& faces = second.slab_positive ? after.lower : after.upper;
    faces.insert(faces.end(), second.faces.begin(), second.faces.end());
    second.cut->clear();
    second.cut->plane = second.plane;
    if (faces.empty()) return CutStatus::kOk;
    // The merges first (plan_snapped's last resort) only after the needles' diagonals are flipped.
    auto plan = [&](bool merges_first_last) {
        return detail::plan_snapped(
            s, second.plane, second.snapped,
            [&] { return detail::plan_wall(s, second.plane, faces); }, merges_first_last);
    };
    CutStatus st = plan(false);
    if ((st == CutStatus::kSliverSplit || st == CutStatus::kCapTriangulationFailed) &&
        flip_rim_needles(s, second.outward, rim) > 0)
        st = plan(false);
    if (st == CutStatus::kSliverSplit) st = plan(true);
    if (st == CutStatus::kPlaneMissesMesh) return CutStatus::kOk;
    if (st != CutStatus::kOk) return st;
    CutStats second_stats;
    second_stats.vertices_snapped = static_cast<std::uint32_t>(second.snapped.size());
    undo.record(s);
    if (detail::apply_plan(s, second.plane, *second.cut, second_stats) != CutStatus::kOk)
        return CutStatus::kInternalError;
    add(stats, second_stats);
    stats.cap_triangles += second_stats.cap_triangles;
    return CutStatus::kOk;
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
    // Dry run on the unedited mesh: every loop of both walls is found, planned and capped.
    WallFaces walls;
    CutStatus st = find_walls(s, lower, upper, seed, walls);
    Wall lo{lower, lower, true, std::move(walls.lower), {}, &out.lower};
    Wall up{upper, upper, false, std::move(walls.upper), {}, &out.upper};
    if (st == CutStatus::kOk && !lo.faces.empty() && !up.faces.empty())
        st = detail::plan_snapped(s, upper, up.snapped,
                                  [&] { return detail::plan_wall(s, upper, up.faces); });
    // The wall cut first is planned last, so that its plan is the current one: the lower one, or
    // the upper one when the component does not reach the lower plane.
    Wall& first = lo.faces.empty() ? up : lo;
    Wall& second = lo.faces.empty() ? lo : up;
    if (st == CutStatus::kOk)
        st = detail::plan_snapped(s, first.plane, first.snapped,
                                  [&] { return detail::plan_wall(s, first.plane, first.faces); });
    if (st != CutStatus::kOk) return done(st);
    lo.outward = *Plane::make(lower.point(), -lower.normal());
    // The lower wall first (planned last, so the plan is current), then the upper wall planned
    // again on the edited mesh. That re-plan can still refuse; every edit is undone then, and the
    // walls are cut the other way round (the upper wall's split leaves no needle where the lower
    // one did). A refusal either way leaves the mesh as it was.
    detail::EditUndo undo;
    r.stats.vertices_snapped = static_cast<std::uint32_t>(first.snapped.size());
    const std::vector<std::int32_t> lower_snapped = lo.snapped, upper_snapped = up.snapped;
    st = cut_walls(s, lower, upper, first, second, undo, r.stats);
    if (st != CutStatus::kOk && st != CutStatus::kInternalError && !lo.faces.empty() &&
        !up.faces.empty()) {
        undo.restore(s);
        lo.snapped = lower_snapped, up.snapped = upper_snapped;
        r.stats = CutStats{};
        r.stats.vertices_snapped = static_cast<std::uint32_t>(up.snapped.size());
        const CutStatus again = detail::plan_snapped(
            s, upper, up.snapped, [&] { return detail::plan_wall(s, upper, up.faces); });
        if (again == CutStatus::kOk &&
            cut_walls(s, lower, upper, up, lo, undo, r.stats) == CutStatus::kOk)
            st = CutStatus::kOk;
    }
    auto refuse = [&](CutStatus why) {
        undo.restore(s);
        out.lower.clear();
        out.upper.clear();
        r.stats = CutStats{};
        return done(why);
    };
    if (st != CutStatus::kOk) return refuse(st);
    // Remove the slab: everything connected to the walls' inner caps, all of it between the walls.
    std::vector<FaceHandle> inner = out.lower.positive.cap_faces;
    inner.insert(inner.end(), out.upper.negative.cap_faces.begin(),
                 out.upper.negative.cap_faces.end());
    const std::vector<FaceHandle> slab = slab_faces(s, inner);
    const double reach = kSnapTolerances * s.tolerance_m;  // a snapped rim vertex
    for (FaceHandle f : slab)
        for (auto v : s.mesh.fv_range(f))
            if (upper.signed_distance(s.mesh.point(v)) > reach ||
                lower.signed_distance(s.mesh.point(v)) < -reach)
                return refuse(CutStatus::kInternalError);
    for (FaceHandle f : slab) s.mesh.delete_face(f, true);
    r.stats.triangles_removed = static_cast<std::uint32_t>(slab.size());
    r.stats.cap_triangles /= 2;  // only one cap of each slice remains
    return done(CutStatus::kOk);
}

}  // namespace kerf::cut
