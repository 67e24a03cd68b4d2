#include "display/cut/section_plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "display/cut/context_state.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/vec_ops.hpp"

namespace kerf::cut::detail {
namespace {

using mesh::EdgeHandle;
using mesh::FaceHandle;
using mesh::HalfedgeHandle;
using mesh::TriMesh;
using mesh::VertexHandle;

constexpr std::size_t kMaxSeedSearchFaces = 20000;

// Where a face's segment starts and ends, for the sides sg[0..2] (-1, 0, +1) of its vertices
// read round the face: the positive run's first vertex k (its predecessor not positive) and last
// vertex `last`; between vertices i and i + 1 lies edge h[i], a cut point when they are on
// opposite sides, else the non-positive vertex is on the plane and is the cut point. The segment
// runs from the cut point after the run (edge h[last], or vertex `after`) to the one before it
// (edge or vertex `before`). Indexed by 9 (sg[0] + 1) + 3 (sg[1] + 1) + (sg[2] + 1).
struct SegmentEnds {
    bool crosses = false;  ///< vertices on both sides
    std::uint8_t before = 0, last = 0, after = 0;
    bool to_edge = false, from_edge = false;
};

constexpr std::array<SegmentEnds, 27> make_segment_table() {
    std::array<SegmentEnds, 27> table{};
    for (int i = 0; i < 27; ++i) {
        const int sg[3] = {i / 9 - 1, i / 3 % 3 - 1, i % 3 - 1};
        if (!((sg[0] > 0 || sg[1] > 0 || sg[2] > 0) && (sg[0] < 0 || sg[1] < 0 || sg[2] < 0)))
            continue;
        int k = 0;
        while (!(sg[k] > 0 && sg[(k + 2) % 3] <= 0)) ++k;
        int j = k;
        while (sg[(j + 1) % 3] > 0) j = (j + 1) % 3;
        const int before = (k + 2) % 3, after = (j + 1) % 3;
        SegmentEnds& e = table[static_cast<std::size_t>(i)];
        e.crosses = true;
        e.before = static_cast<std::uint8_t>(before);
        e.last = static_cast<std::uint8_t>(j);
        e.after = static_cast<std::uint8_t>(after);
        e.to_edge = sg[before] < 0;
        e.from_edge = sg[after] < 0;
    }
    return table;
}

constexpr std::array<SegmentEnds, 27> kSegments = make_segment_table();

// Walks cross-section loops on the unedited mesh.
class Walker {
public:
    Walker(ContextState& s, const Plane& plane)
        : s_(s),
          m_(s.mesh),
          plane_(plane),
          tol_(s.tolerance_m),
          any_snapped_(s.snapped != nullptr && !s.snapped->empty()) {}

    // -1, 0 (within tol, or snapped) or +1.
    int side(VertexHandle v) const {
        const int sd = plane_.side(m_.point(v), tol_);
        if (sd == 0 || !any_snapped_) return sd;
        return snapped(v) ? 0 : sd;
    }
    // Whether v is one of the snapped vertices (out of line: side() stays small enough to be
    // inlined in segment()).
    [[gnu::noinline]] bool snapped(VertexHandle v) const {
        return std::binary_search(s_.snapped->begin(), s_.snapped->end(), v.idx());
    }

    // +1 / -1 for a face that does not cross the plane (an in-plane face by its normal).
    int label(FaceHandle f) const {
        int pos = 0, neg = 0;
        Vec3 p[3];
        int k = 0;
        for (auto v : m_.fv_range(f)) {
            const int sd = side(v);
            pos += sd > 0;
            neg += sd < 0;
            p[k++] = m_.point(v);
        }
        if (pos > 0) return 1;
        if (neg > 0) return -1;
        return OpenMesh::dot(OpenMesh::cross(p[1] - p[0], p[2] - p[0]), plane_.normal()) < 0 ? 1
                                                                                             : -1;
    }

    // For a face with vertices on both sides: its segment, directed along the positive part's
    // halfedge. False when the face does not cross. Read round the face from h[0] as vertices
    // and the cut points between them (on-plane vertices and crossing edges), the positive
    // vertices form one run (a triangle has at most two, and then they are neighbours): the
    // segment runs from the cut point after that run to the one before it (kSegments: per side
    // pattern, those two places).
    bool segment(FaceHandle f, CutPointKey& from, CutPointKey& to) const {
        HalfedgeHandle h[3];
        h[0] = m_.halfedge_handle(f);
        h[1] = m_.next_halfedge_handle(h[0]);
        h[2] = m_.next_halfedge_handle(h[1]);
        VertexHandle v[3];
        int sg[3];
        for (int k = 0; k < 3; ++k) v[k] = m_.from_vertex_handle(h[k]), sg[k] = side(v[k]);
        return segment_ends(h, v, sg, from, to);
    }

    // segment() of the face of halfedge `hp`, which runs from a vertex on the positive side to
    // one on the negative side (a halfedge of an edge cut point's edge, from its positive end:
    // segment() makes a cut point on an edge only between a +1 and a -1 vertex), so that only
    // the third corner's side is computed.
    bool segment_from(HalfedgeHandle hp, CutPointKey& from, CutPointKey& to) const {
        HalfedgeHandle h[3];
        h[0] = m_.halfedge_handle(m_.face_handle(hp));
        h[1] = m_.next_halfedge_handle(h[0]);
        h[2] = m_.next_halfedge_handle(h[1]);
        VertexHandle v[3];
        for (int k = 0; k < 3; ++k) v[k] = m_.from_vertex_handle(h[k]);
        // hp is h[k]: its two ends are corners k and k + 1, the third corner k + 2.
        const int k = h[0] == hp ? 0 : (h[1] == hp ? 1 : 2);
        static constexpr int kNext[3] = {1, 2, 0}, kThird[3] = {2, 0, 1};
        int sg[3];
        sg[k] = 1;
        sg[kNext[k]] = -1;
        sg[kThird[k]] = side(v[kThird[k]]);
        return segment_ends(h, v, sg, from, to);
    }

    // The segment of the face with halfedges h, their from-vertices v and those vertices' sides
    // sg (segment()).
    bool segment_ends(const HalfedgeHandle (&h)[3], const VertexHandle (&v)[3], const int (&sg)[3],
                      CutPointKey& from, CutPointKey& to) const {
        const SegmentEnds& c = kSegments[9 * (sg[0] + 1) + 3 * (sg[1] + 1) + (sg[2] + 1)];
        if (!c.crosses) return false;
        to = c.to_edge ? CutPointKey{m_.edge_handle(h[c.before]).idx(), true}
                       : CutPointKey{v[c.before].idx(), false};
        from = c.from_edge ? CutPointKey{m_.edge_handle(h[c.last]).idx(), true}
                           : CutPointKey{v[c.after].idx(), false};
        return true;
    }

    // Outgoing segments at on-plane vertex v: how many, and the last one's end (with its face,
    // or an invalid face for a step along an in-plane edge).
    int outgoing(VertexHandle v, CutPointKey& next, FaceHandle& via) const {
        int count = 0;
        const CutPointKey self{v.idx(), false};
        for (auto g : m_.voh_range(v)) {
            const FaceHandle f = m_.face_handle(g);
            CutPointKey a, b;
            if (segment(f, a, b)) {
                if (a == self) next = b, via = f, ++count;
                continue;
            }
            const VertexHandle w = m_.to_vertex_handle(g);
            if (side(w) != 0) continue;
            const FaceHandle o = m_.face_handle(m_.opposite_halfedge_handle(g));
            CutPointKey c, d;
            if (segment(o, c, d)) continue;
            if (label(f) > 0 && label(o) < 0)
                next = CutPointKey{w.idx(), false}, via = FaceHandle(), ++count;
        }
        return count;
    }

    // The cut point after k on its loop, and the face the step crosses (invalid along an
    // in-plane edge).
    CutStatus next(const CutPointKey& k, CutPointKey& out, FaceHandle& via) const {
        if (k.edge) {
            const EdgeHandle e(k.id);
            // The loop leaves edge k through the face whose halfedge runs from k's positive end
            // (k starts that face's segment): try it first, one segment() instead of up to two.
            // When it fails, the search below gives what it always gave.
            const int first = side(m_.from_vertex_handle(m_.halfedge_handle(e, 0))) > 0 ? 0 : 1;
            const FaceHandle f0 = m_.face_handle(m_.halfedge_handle(e, 0));
            const FaceHandle ff = m_.face_handle(m_.halfedge_handle(e, first));
            if (f0.is_valid() && ff.is_valid()) {
                CutPointKey a, b;
                if (segment_from(m_.halfedge_handle(e, first), a, b) && a == k) {
                    out = b;
                    via = ff;
                    return CutStatus::kOk;
                }
            }
            for (int i = 0; i < 2; ++i) {
                const FaceHandle f = m_.face_handle(m_.halfedge_handle(e, i));
                if (!f.is_valid()) return CutStatus::kNonManifoldInput;
                CutPointKey a, b;
                if (segment(f, a, b) && a == k) {
                    out = b;
                    via = f;
                    return CutStatus::kOk;
                }
            }
            return CutStatus::kInternalError;
        }
        const VertexHandle v(k.id);
        if (m_.is_boundary(v)) return CutStatus::kNonManifoldInput;
        const int count = outgoing(v, out, via);
        return count == 1 ? CutStatus::kOk : CutStatus::kDegenerateCrossSection;
    }

    bool marked(const CutPointKey& k) const {
        return k.edge ? s_.edge_marked(EdgeHandle(k.id)) : s_.vertex_marked(VertexHandle(k.id));
    }

    void mark(const CutPointKey& k) {
        if (k.edge)
            m_.property(s_.e_stamp, EdgeHandle(k.id)) = s_.generation;
        else
            m_.property(s_.v_stamp, VertexHandle(k.id)) = s_.generation;
    }

    PlanPoint make_point(const CutPointKey& k) const {
        PlanPoint p;
        p.key = k;
        if (!k.edge) {
            p.position = m_.point(VertexHandle(k.id));
            p.a = p.b = k.id;
        } else {
            const EdgeHandle e(k.id);
            VertexHandle a = m_.to_vertex_handle(m_.halfedge_handle(e, 0));
            VertexHandle b = m_.to_vertex_handle(m_.halfedge_handle(e, 1));
            if (b.idx() < a.idx()) std::swap(a, b);
            const Vec3& pa = m_.point(a);
            const Vec3& pb = m_.point(b);
            const double da = plane_.signed_distance(pa);
            const double db = plane_.signed_distance(pb);
            p.t = da / (da - db);
            p.position = lerp(pa, pb, p.t);
            p.a = a.idx();
            p.b = b.idx();
        }
        p.uv = plane_.to_2d(p.position);
        return p;
    }

    // Walks the loop through `start` and appends it to the plan (not selected yet). Every face
    // a step crosses is marked: its segment starts at a point of this loop, which is marked, so
    // start_on() would find nothing new on it, and the face-tree queries for more loops
    // (add_nested_loops, select_loop_around_hole) skip marked faces before they ask.
    CutStatus walk(const CutPointKey& start) {
        SectionPlan& plan = s_.plan;
        PlanLoop loop;
        loop.first = static_cast<std::uint32_t>(plan.points.size());
        std::uint32_t faces = 0;
        CutPointKey k = start;
        const std::size_t limit = 3 * m_.n_faces() + 3;
        while (!marked(k)) {
            mark(k);
            plan.points.push_back(make_point(k));
            FaceHandle via;
            CutPointKey nx;
            const CutStatus st = next(k, nx, via);
            if (st != CutStatus::kOk) return st;
            if (via.is_valid()) ++faces, s_.mark_face(via);
            k = nx;
            if (plan.points.size() - loop.first > limit) return CutStatus::kInternalError;
        }
        if (!(k == start)) return CutStatus::kDegenerateCrossSection;
        loop.count = static_cast<std::uint32_t>(plan.points.size()) - loop.first;
        double area = 0;
        for (std::uint32_t i = 0; i < loop.count; ++i) {
            const Vec2& p = plan.points[loop.first + i].uv;
            const Vec2& q = plan.points[loop.first + (i + 1) % loop.count].uv;
            area += p[0] * q[1] - p[1] * q[0];
        }
        loop.area_m2 = 0.5 * area;
        loop.faces = faces;
        plan.loops.push_back(loop);
        return CutStatus::kOk;
    }

    // A loop start on face f, if f carries a segment whose start is not yet walked.
    bool start_on(FaceHandle f, CutPointKey& start) const {
        CutPointKey a, b;
        if (segment(f, a, b)) {
            start = a;
            return !marked(a);
        }
        for (auto v : m_.fv_range(f)) {
            if (side(v) != 0 || s_.vertex_marked(v) || m_.is_boundary(v)) continue;
            CutPointKey nx;
            FaceHandle via;
            if (outgoing(v, nx, via) > 0) {
                start = CutPointKey{v.idx(), false};
                return true;
            }
        }
        return false;
    }

private:
    ContextState& s_;
    TriMesh& m_;
    const Plane& plane_;
    double tol_;
    bool any_snapped_;  // s.snapped holds vertices (it does not change while a plan is made)
};

bool inside(const SectionPlan& plan, const PlanLoop& loop, const Vec2& q) {
    bool in = false;
    for (std::uint32_t i = 0, j = loop.count - 1; i < loop.count; j = i++) {
        const Vec2& a = plan.points[loop.first + i].uv;
        const Vec2& b = plan.points[loop.first + j].uv;
        if ((a[1] > q[1]) != (b[1] > q[1]) &&
            q[0] < (b[0] - a[0]) * (q[1] - a[1]) / (b[1] - a[1]) + a[0])
            in = !in;
    }
    return in;
}

// Whether `inner` lies inside `outer`: a majority of up to 9 sample points (robust to loops of
// two pieces of an earlier cut that touch along that cut's line).
}  // namespace

bool loop_nested(const SectionPlan& plan, const PlanLoop& inner, const PlanLoop& outer) {
    for (const SectionPlan::Nesting& n : plan.nesting)
        if (n.inner_first == inner.first && n.inner_count == inner.count &&
            n.outer_first == outer.first && n.outer_count == outer.count)
            return n.nested;
    const std::uint32_t samples = std::min<std::uint32_t>(9, inner.count);
    std::uint32_t votes = 0;
    // Until the majority is settled either way.
    for (std::uint32_t k = 0; k < samples && 2 * votes <= samples && 2 * (k - votes) < samples; ++k)
        votes += inside(plan, outer, plan.points[inner.first + k * inner.count / samples].uv);
    const bool nested = 2 * votes > samples;
    // A cut has a few loops; one through many shells has thousands of pairs, which a list
    // searched on every call would make quadratic in them: only the first few are remembered.
    constexpr std::size_t kRemembered = 32;
    if (plan.nesting.size() < kRemembered)
        plan.nesting.push_back(
            SectionPlan::Nesting{inner.first, inner.count, outer.first, outer.count, nested});
    return nested;
}

namespace {

FaceHandle seed_face_near(ContextState& s, const Seed& seed) {
    const TriMesh& m = s.mesh;
    const double tol =
        seed.tolerance_m >= 0 ? seed.tolerance_m : kSeedRelativeTolerance * s.scale_m;
    const auto n = static_cast<int>(m.n_faces());
    const auto accepted = [&](FaceHandle f) { return !seed.accepts || seed.accepts(f); };
    if (seed.face_hint.is_valid() && seed.face_hint.idx() < n &&
        !m.status(seed.face_hint).deleted() && accepted(seed.face_hint)) {
        if (distance_to_face(m, seed.face_hint, seed.point_m) <= tol) return seed.face_hint;
        // A hint on an earlier cap whose diagonals a chord flipped (cap_chords.hpp: the plan is
        // made again after the chords are put in) may no longer hold the point; the face of the
        // same cap that does is the seed's (the point lies on that cap's twin as well, so the
        // nearest face of the mesh could be on the other piece). The cap is searched from the
        // hint across its inner edges (same tag, same stored normal).
        const std::uint8_t tag = m.property(s.cap, seed.face_hint);
        if (tag != kCapNone) {
            const Vec3 normal = m.normal(seed.face_hint);
            std::vector<FaceHandle> queue{seed.face_hint};
            s.mark_face(seed.face_hint);
            for (std::size_t i = 0; i < queue.size() && i < 4096; ++i) {
                const FaceHandle f = queue[i];
                if (accepted(f) && distance_to_face(m, f, seed.point_m) <= tol) return f;
                for (auto h : m.fh_range(f)) {
                    const FaceHandle g = m.opposite_face_handle(h);
                    if (!g.is_valid() || s.face_marked(g) || m.property(s.cap, g) != tag ||
                        m.normal(g) != normal)
                        continue;
                    s.mark_face(g);
                    queue.push_back(g);
                }
            }
        }
    }
    FaceHandle best;
    double best_d = tol;
    auto consider = [&](std::int32_t fi) {
        const FaceHandle f(fi);
        if (fi >= n || m.status(f).deleted() || s.face_marked(f) || !accepted(f)) return;
        s.mark_face(f);
        const double d = distance_to_face(m, f, seed.point_m);
        if (d <= best_d) best_d = d, best = f;
    };
    // Growing radii up to tol: the first radius that holds a face within it finds the nearest
    // face (every face nearer lies within it), the one a query of radius tol finds, at the cost
    // of the faces near the point rather than of every face within tol (thousands on a dense
    // mesh: tol is relative to the mesh's size, not to its triangles).
    for (double r = tol / 4096;; r = std::min(tol, 8 * r)) {
        s.next_generation();
        best_d = r;
        s.tree.for_each_near_point(seed.point_m, r, consider);
        if (best.is_valid() || r >= tol) break;
    }
    // Cap faces are not in the tree: a seed on a cap lies within a few micrometres of the sides'
    // faces along the cap's rim, so a cap nearer than the tree's best face wins (ties keep the
    // tree's). Only seeds without a usable face hint get here (the display passes one).
    if (best_d > 0) {
        const FaceHandle tree_best = best;
        const double tree_d = best.is_valid() ? best_d : tol;
        best = FaceHandle();
        best_d = tree_d;
        for (FaceHandle f : s.cap_faces) {
            if (m.status(f).deleted() || !accepted(f)) continue;
            const double d = distance_to_face(m, f, seed.point_m);
            if (d < best_d || (!tree_best.is_valid() && d <= best_d)) best_d = d, best = f;
        }
        if (!best.is_valid()) best = tree_best;
    }
    return best;
}

// Best-first search from the seed face, nearest-to-plane first, for a face carrying a segment.
CutStatus find_start(ContextState& s, Walker& w, const Plane& plane, FaceHandle seed_face,
                     CutPointKey& start) {
    TriMesh& m = s.mesh;
    struct Entry {
        double d;
        std::int32_t f;
        bool operator<(const Entry& o) const { return d > o.d || (d == o.d && f > o.f); }
    };
    std::vector<Entry> heap;
    auto key = [&](FaceHandle f) {
        double d = 1e300;
        for (auto v : m.fv_range(f)) d = std::min(d, std::abs(plane.signed_distance(m.point(v))));
        return d;
    };
    heap.push_back({key(seed_face), seed_face.idx()});
    s.mark_face(seed_face);
    for (std::size_t popped = 0; !heap.empty() && popped < kMaxSeedSearchFaces; ++popped) {
        std::pop_heap(heap.begin(), heap.end());
        const FaceHandle f(heap.back().f);
        heap.pop_back();
        if (w.start_on(f, start)) return CutStatus::kOk;
        for (auto g : m.fh_range(f)) {
            const FaceHandle o = m.face_handle(m.opposite_halfedge_handle(g));
            if (!o.is_valid() || s.face_marked(o)) continue;
            s.mark_face(o);
            heap.push_back({key(o), o.idx()});
            std::push_heap(heap.begin(), heap.end());
        }
    }
    return CutStatus::kSeedFarFromCut;
}

// Walks every loop met near the plane inside each selected outer loop's box (the face tree), then
// selects the holes inside a selected outer loop and the islands inside those holes; loops outside
// stay untouched.
CutStatus add_nested_loops(ContextState& s, Walker& w, const Plane& plane) {
    SectionPlan& plan = s.plan;
    std::vector<std::size_t> outers;
    for (std::size_t i = 0; i < plan.loops.size(); ++i)
        if (plan.loops[i].selected && plan.loops[i].area_m2 > 0) outers.push_back(i);
    const auto n = static_cast<int>(s.mesh.n_faces());
    for (const std::size_t o : outers) {
        const PlanLoop outer = plan.loops[o];
        Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
        for (std::uint32_t i = 0; i < outer.count; ++i) {
            lo.minimize(plan.points[outer.first + i].uv);
            hi.maximize(plan.points[outer.first + i].uv);
        }
        CutStatus error = CutStatus::kOk;
        s.tree.for_each_near_plane(plane, lo, hi, s.tolerance_m, [&](std::int32_t fi) {
            const FaceHandle f(fi);
            if (error != CutStatus::kOk || fi >= n || s.mesh.status(f).deleted() ||
                s.face_marked(f))
                return;
            s.mark_face(f);
            CutPointKey start;
            if (!w.start_on(f, start)) return;
            const std::size_t points_before = plan.points.size();
            const CutStatus st = w.walk(start);
            if (st != CutStatus::kOk) {
                if (inside(plan, outer, plan.points[points_before].uv)) error = st;
                plan.points.resize(points_before);  // an unrelated broken loop outside: not ours
            }
        });
        if (error != CutStatus::kOk) return error;
    }
    for (PlanLoop& l : plan.loops) {
        if (l.selected || l.area_m2 >= 0) continue;
        for (const std::size_t o : outers)
            if (loop_nested(plan, l, plan.loops[o])) l.selected = true;
    }
    for (PlanLoop& l : plan.loops) {
        if (l.selected || l.area_m2 < 0) continue;
        for (const PlanLoop& h : plan.loops)
            if (h.selected && h.area_m2 < 0 && loop_nested(plan, l, h)) l.selected = true;
    }
    return CutStatus::kOk;
}

// The seed's loop (plan.loops[0]) is a hole: the material the seed touches is the region between
// it and the innermost outer loop around it, the contiguous cross-section holding the seed
// (§3.7). Every loop around the hole crosses the ray from the hole's point of largest u along +u
// within the mesh's extent, so walking every loop met along that ray (faces from the face tree,
// then the cap faces, which the tree does not hold) finds them all; the smallest outer loop
// holding the hole is selected. kSeedOnInnerBoundary when there is none (a lone inward-facing
// shell); a broken loop met inside the selected one fails the plan with its status.
CutStatus select_loop_around_hole(ContextState& s, Walker& w, const Plane& plane) {
    SectionPlan& plan = s.plan;
    const PlanLoop hole = plan.loops.front();
    Vec2 q = plan.points[hole.first].uv;
    for (std::uint32_t i = 1; i < hole.count; ++i)
        if (plan.points[hole.first + i].uv[0] > q[0]) q = plan.points[hole.first + i].uv;
    const double tol = s.tolerance_m;
    const double far = q[0] + 2.0 * s.scale_m;
    struct Broken {
        Vec2 start;
        CutStatus status;
    };
    std::vector<Broken> broken;
    const auto n = static_cast<int>(s.mesh.n_faces());
    auto walk_from = [&](FaceHandle f) {
        if (f.idx() >= n || s.mesh.status(f).deleted() || s.face_marked(f)) return;
        s.mark_face(f);
        CutPointKey start;
        if (!w.start_on(f, start)) return;
        const std::size_t points_before = plan.points.size();
        const CutStatus st = w.walk(start);
        if (st == CutStatus::kOk) return;
        broken.push_back(Broken{plan.points[points_before].uv, st});
        plan.points.resize(points_before);
    };
    s.tree.for_each_near_plane(plane, q, Vec2(far, q[1]), tol,
                               [&](std::int32_t fi) { walk_from(FaceHandle(fi)); });
    for (const FaceHandle f : s.cap_faces) {
        if (s.mesh.status(f).deleted()) continue;
        double d_lo = 1e300, d_hi = -1e300, v_lo = 1e300, v_hi = -1e300, u_hi = -1e300;
        for (auto v : s.mesh.fv_range(f)) {
            const Vec3& p = s.mesh.point(v);
            const double d = plane.signed_distance(p);
            const Vec2 uv = plane.to_2d(p);
            d_lo = std::min(d_lo, d), d_hi = std::max(d_hi, d);
            v_lo = std::min(v_lo, uv[1]), v_hi = std::max(v_hi, uv[1]);
            u_hi = std::max(u_hi, uv[0]);
        }
        if (d_lo > tol || d_hi < -tol || v_lo > q[1] + tol || v_hi < q[1] - tol ||
            u_hi < q[0] - tol)
            continue;
        walk_from(f);
    }
    std::size_t around = 0;
    for (std::size_t i = 1; i < plan.loops.size(); ++i) {
        const PlanLoop& l = plan.loops[i];
        if (l.area_m2 > 0 && (around == 0 || l.area_m2 < plan.loops[around].area_m2) &&
            loop_nested(plan, hole, l))
            around = i;
    }
    if (around == 0) return CutStatus::kSeedOnInnerBoundary;
    for (const Broken& b : broken)
        if (inside(plan, plan.loops[around], b.start)) return b.status;
    plan.loops[around].selected = true;
    return CutStatus::kOk;
}

}  // namespace

void SectionPlan::clear() {
    points.clear();
    loops.clear();
    merged.clear();
    cap_triangles.clear();
    cap_neighbours.clear();
    nesting.clear();
}

namespace {

// The vertex of face f (of edge `e`'s halfedges) opposite edge e, for both sides.
VertexHandle opposite_vertex(const TriMesh& m, HalfedgeHandle h) {
    return m.to_vertex_handle(m.next_halfedge_handle(h));
}

// Whether collapsing the vertex a split of edge point `drop` makes into the vertex of `keep`
// (both consecutive on a loop, so in one face) satisfies the link condition: the two share
// exactly the two vertices of that face's other corners as neighbours.
bool merge_is_safe(const TriMesh& m, const PlanPoint& keep, const PlanPoint& drop) {
    const EdgeHandle e(drop.key.id);
    const HalfedgeHandle h0 = m.halfedge_handle(e, 0), h1 = m.halfedge_handle(e, 1);
    if (m.is_boundary(h0) || m.is_boundary(h1)) return false;
    const VertexHandle a = m.to_vertex_handle(h0), b = m.to_vertex_handle(h1);
    const VertexHandle o0 = opposite_vertex(m, h0), o1 = opposite_vertex(m, h1);
    if (!keep.key.edge) {
        // Keep an on-plane vertex v opposite the edge: v and the far vertex must not be adjacent.
        const VertexHandle v(keep.key.id);
        const VertexHandle far = o0 == v ? o1 : (o1 == v ? o0 : VertexHandle());
        return far.is_valid() && !m.find_halfedge(v, far).is_valid();
    }
    // Both on edges of one face, sharing its lone vertex x; the far vertices across the two
    // edges must differ and x must have more than three neighbours.
    const EdgeHandle k(keep.key.id);
    const VertexHandle ka = m.to_vertex_handle(m.halfedge_handle(k, 0));
    const VertexHandle kb = m.to_vertex_handle(m.halfedge_handle(k, 1));
    const VertexHandle x = (a == ka || a == kb) ? a : ((b == ka || b == kb) ? b : VertexHandle());
    if (!x.is_valid() || m.valence(x) <= 3) return false;
    auto far_of = [&](EdgeHandle edge, VertexHandle other_corner) {
        for (int i = 0; i < 2; ++i) {
            const HalfedgeHandle h = m.halfedge_handle(edge, i);
            if (opposite_vertex(m, h) != other_corner) return opposite_vertex(m, h);
        }
        return VertexHandle();
    };
    const VertexHandle y = ka == x ? kb : ka;  // keep's other end: a corner of the shared face
    const VertexHandle z = a == x ? b : a;     // drop's other end: the third corner
    const VertexHandle w_keep = far_of(k, z), w_drop = far_of(e, y);
    return w_keep.is_valid() && w_drop.is_valid() && w_keep != w_drop;
}

}  // namespace

void merge_close_points(ContextState& s) {
    SectionPlan& plan = s.plan;
    const TriMesh& m = s.mesh;
    const double tol = s.tolerance_m;
    auto close = [&](const PlanPoint& p, const PlanPoint& q) {
        return sqrdist(p.position, q.position) <= tol * tol;
    };
    // Every merge joins two neighbours on a selected loop: with no such pair within tol (the
    // common case) nothing below would change, so the loops are left as they are.
    bool any_close = false;
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected || l.count == 0) continue;
        const PlanPoint* const p = &plan.points[l.first];
        for (std::uint32_t i = 0; i + 1 < l.count && !any_close; ++i)
            any_close = close(p[i], p[i + 1]);
        any_close = any_close || close(p[l.count - 1], p[0]);
        if (any_close) break;
    }
    if (!any_close) return;
    // Per kept point: which of its loop neighbours was merged into it (at most one per side).
    constexpr char kFromBefore = 1, kFromAfter = 2;
    std::vector<PlanPoint> points;
    points.reserve(plan.points.size());
    std::vector<char> merged_in;
    for (PlanLoop& l : plan.loops) {
        const auto first = static_cast<std::uint32_t>(points.size());
        // Only neighbours on the original loop share a face: merge p into the last kept point
        // only when that point came just before p.
        bool previous_kept = false, first_is_original = true;
        for (std::uint32_t i = 0; i < l.count; ++i) {
            const PlanPoint& p = plan.points[l.first + i];
            const std::size_t kept = points.size() - first;
            const bool room = kept + (l.count - i) - 1 >= 3;
            if (l.selected && room && previous_kept && close(points.back(), p)) {
                const auto into = static_cast<std::uint32_t>(points.size() - 1);
                // Three edge points in a row within tol (a limb crossing a fan of thin cap
                // triangles of the other limb): both ends go into the middle one, each through
                // the face it shares with it, so no two of the three are left.
                const PlanPoint* next = i + 1 < l.count ? &plan.points[l.first + i + 1] : nullptr;
                if (p.key.edge && points.back().key.edge && merged_in[into] == 0 &&
                    next != nullptr && next->key.edge && kept + (l.count - i) - 2 >= 3 &&
                    close(p, *next) && merge_is_safe(m, p, points.back()) &&
                    merge_is_safe(m, p, *next)) {
                    plan.merged.push_back(MergedPoint{points.back(), into});
                    if (into == first) first_is_original = false;
                    points.back() = p;
                    merged_in[into] = kFromBefore;
                    continue;
                }
                if (p.key.edge && !(merged_in[into] & kFromAfter) &&
                    merge_is_safe(m, points.back(), p)) {
                    plan.merged.push_back(MergedPoint{p, into});
                    merged_in[into] |= kFromAfter;
                    previous_kept = false;
                    continue;
                }
                if (!p.key.edge && points.back().key.edge && merged_in[into] == 0 &&
                    merge_is_safe(m, p, points.back())) {
                    plan.merged.push_back(MergedPoint{points.back(), into});
                    if (into == first) first_is_original = false;
                    points.back() = p;
                    merged_in[into] = kFromBefore;
                    continue;
                }
            }
            points.push_back(p);
            merged_in.push_back(0);
            previous_kept = true;
        }
        // The loop closes: its last point against its first.
        const auto last = static_cast<std::uint32_t>(points.size() - 1);
        if (l.selected && previous_kept && first_is_original && points.size() - first > 3 &&
            points[last].key.edge && merged_in[last] == 0 && !(merged_in[first] & kFromBefore) &&
            close(points[last], points[first]) && merge_is_safe(m, points[first], points[last])) {
            plan.merged.push_back(MergedPoint{points[last], first});
            merged_in[first] |= kFromBefore;
            points.pop_back();
            merged_in.pop_back();
        }
        l.first = first;
        l.count = static_cast<std::uint32_t>(points.size()) - first;
    }
    if (points.size() != plan.points.size()) plan.nesting.clear();  // the loops changed
    plan.points.swap(points);
}

CutStatus check_merged_split_areas(ContextState& s, const Plane& plane) {
    const SectionPlan& plan = s.plan;
    if (plan.merged.empty()) return CutStatus::kOk;
    const TriMesh& m = s.mesh;
    // Every cut point of the selected loops by key, with the index of the point it ends as (a
    // merged point: the one it goes into) and so the position it ends at.
    struct Final {
        CutPointKey key;
        std::uint32_t as;
    };
    std::vector<Final> finals;
    for (const PlanLoop& l : plan.loops)
        if (l.selected)
            for (std::uint32_t i = l.first; i < l.first + l.count; ++i)
                finals.push_back({plan.points[i].key, i});
    for (const MergedPoint& mp : plan.merged) finals.push_back({mp.point.key, mp.into});
    auto order = [](const CutPointKey& a, const CutPointKey& b) {
        return a.edge != b.edge ? a.edge < b.edge : a.id < b.id;
    };
    std::sort(finals.begin(), finals.end(),
              [&](const Final& a, const Final& b) { return order(a.key, b.key); });
    auto find = [&](CutPointKey k) -> const Final* {
        const auto it =
            std::lower_bound(finals.begin(), finals.end(), k,
                             [&](const Final& f, const CutPointKey& x) { return order(f.key, x); });
        return it != finals.end() && it->key == k ? &*it : nullptr;
    };
    // A corner of a split part: a mesh vertex (as = none) or a cut point (as its final point).
    constexpr std::uint32_t kVertex = 0xffffffffu;
    struct Corner {
        Vec3 p;
        std::uint32_t as;
    };
    CutStatus status = CutStatus::kOk;
    for (const MergedPoint& mp : plan.merged) {
        for (int k = 0; k < 2; ++k) {
            // Face x -> y -> z with the merged point on edge x-y: its split parts, both diagonals
            // of the quad, each corner where the merges leave it.
            const HalfedgeHandle h = m.halfedge_handle(EdgeHandle(mp.point.key.id), k);
            const FaceHandle f = m.face_handle(h);
            if (!f.is_valid()) continue;
            const HalfedgeHandle hn = m.next_halfedge_handle(h), hp = m.next_halfedge_handle(hn);
            const VertexHandle corners[3] = {m.from_vertex_handle(h), m.to_vertex_handle(h),
                                             m.to_vertex_handle(hn)};
            auto vertex = [&](VertexHandle v) {
                const Final* on = find(CutPointKey{v.idx(), false});
                return on ? Corner{plan.points[on->as].position, on->as}
                          : Corner{m.point(v), kVertex};
            };
            const Corner x = vertex(corners[0]), y = vertex(corners[1]), z = vertex(corners[2]);
            const Corner pp{plan.points[mp.into].position, mp.into};
            const Final* on_yz = find(CutPointKey{m.edge_handle(hn).idx(), true});
            const Final* on_zx = find(CutPointKey{m.edge_handle(hp).idx(), true});
            std::vector<std::array<const Corner*, 3>> parts;
            Corner qq;
            if (z.as != kVertex) {
                parts = {{&x, &pp, &z}, {&pp, &y, &z}};
            } else if (on_yz != nullptr) {
                qq = Corner{plan.points[on_yz->as].position, on_yz->as};
                parts = {
                    {&pp, &y, &qq}, {&x, &pp, &qq}, {&x, &qq, &z}, {&x, &pp, &z}, {&pp, &qq, &z}};
            } else if (on_zx != nullptr) {
                qq = Corner{plan.points[on_zx->as].position, on_zx->as};
                parts = {
                    {&x, &pp, &qq}, {&pp, &y, &z}, {&pp, &z, &qq}, {&pp, &y, &qq}, {&qq, &y, &z}};
            } else {
                continue;
            }
            const Vec3 n = OpenMesh::cross(m.point(corners[1]) - m.point(corners[0]),
                                           m.point(corners[2]) - m.point(corners[0]));
            bool bad = false;
            for (const auto& t : parts) {
                const Corner &a = *t[0], &b = *t[1], &c = *t[2];
                if ((a.as != kVertex && (a.as == b.as || a.as == c.as)) ||
                    (b.as != kVertex && b.as == c.as))
                    continue;  // a part the collapse removes
                const Vec3 twice = OpenMesh::cross(b.p - a.p, c.p - a.p);
                bad |= !(OpenMesh::dot(twice, n) > 0) || s.too_small(a.p, b.p, c.p);
            }
            if (!bad) continue;
            propose_snap(s, plane, corners);
            status = CutStatus::kSliverSplit;
        }
    }
    return status;
}

CutStatus finish_plan(ContextState& s, const Plane& plane) {
    CutStatus st = check_split_areas(s, plane);
    if (st != CutStatus::kOk) return st;
    merge_close_points(s);
    st = check_merged_split_areas(s, plane);
    return st == CutStatus::kOk ? plan_caps(s, plane) : st;
}

namespace {

// finish_plan with the merges first: the split parts are checked on the loops the merges leave
// (check_split_areas skips a pair of points that no longer share a face) and round the merged
// points where the merges leave them. A needle of an earlier cap thinner than tol, crossed by the
// plane, has its two cut points within tol: the part between them, below the threshold, goes
// with the merge instead of refusing the cut.
CutStatus finish_plan_merged_first(ContextState& s, const Plane& plane) {
    merge_close_points(s);
    CutStatus st = check_split_areas(s, plane);
    if (st == CutStatus::kOk) st = check_merged_split_areas(s, plane);
    return st == CutStatus::kOk ? plan_caps(s, plane) : st;
}

}  // namespace

CutStatus plan_snapped(ContextState& s, const Plane& plane, std::vector<std::int32_t>& snapped,
                       const std::function<CutStatus()>& plan, bool merges_first_last,
                       const CutStatus* planned) {
    s.snapped = &snapped;
    CutStatus st = CutStatus::kOk;
    for (int round = 0;; ++round) {
        s.snap_candidates.clear();
        st = round == 0 && planned != nullptr ? *planned : plan();
        if (st == CutStatus::kOk) st = finish_plan(s, plane);
        const bool sliver =
            st == CutStatus::kSliverSplit || st == CutStatus::kCapTriangulationFailed;
        if (!sliver || round == kMaxSnapRounds || s.snap_candidates.empty()) break;
        const std::size_t before = snapped.size();
        for (const std::int32_t v : s.snap_candidates)
            if (!std::binary_search(snapped.begin(), snapped.end(), v))
                snapped.insert(std::lower_bound(snapped.begin(), snapped.end(), v), v);
        if (snapped.size() == before) break;  // nothing new to try
    }
    if (st == CutStatus::kSliverSplit && merges_first_last) {
        // Last, where snapping did not help: the merges first (a plan that passes the other way
        // is left as it was, so every cut that succeeded before is unchanged).
        st = plan();
        if (st == CutStatus::kOk) st = finish_plan_merged_first(s, plane);
    }
    s.snapped = nullptr;
    return st;
}

void propose_snap(ContextState& s, const Plane& plane, std::span<const VertexHandle> vertices) {
    const double limit = kSnapTolerances * s.tolerance_m;
    VertexHandle best;
    double best_d = limit;
    for (const VertexHandle v : vertices) {
        const double d = std::abs(plane.signed_distance(s.mesh.point(v)));
        if (d > s.tolerance_m && d <= best_d) best_d = d, best = v;
    }
    if (best.is_valid()) s.snap_candidates.push_back(best.idx());
}

CutStatus check_split_areas(ContextState& s, const Plane& plane) {
    const SectionPlan& plan = s.plan;
    const TriMesh& m = s.mesh;
    // s.too_small(a, b, c) from the edges b - a and c - a and their squared lengths, which the
    // parts of one face share (up to sign): its first two tests on them, with the bounds worked
    // out once (the same operations, so the same answers), and only a triangle they leave open
    // asks too_small itself.
    const double floor = kMinTriangleRelativeArea * s.scale_m * s.scale_m;
    const double min_twice2 = 4.0 * floor * floor;
    const double loss = 4.0 * std::sqrt(3.0) * s.float_rounding_m;
    const double kept = ContextState::kFileMargin * floor;
    const double kept2 = kept * kept, loss2 = loss * loss;
    struct Edge {
        Vec3 d;       // to - from
        double len2;  // |d|²
    };
    auto edge = [](const Vec3& from, const Vec3& to) {
        const Vec3 d = sub(to, from);
        return Edge{d, sqrnorm(d)};
    };
    auto small = [&](const Vec3& a, const Vec3& b, const Vec3& c, const Edge& ab, const Edge& ac) {
        const double twice2 = sqrnorm(cross(ab.d, ac.d));
        if (!(twice2 > min_twice2)) return true;
        if (twice2 > 2.0 * (kept2 + loss2 * (2.000000001 * (ab.len2 + ac.len2)))) return false;
        return s.too_small(a, b, c, twice2, ab.len2, ac.len2);
    };
    CutStatus status = CutStatus::kOk;
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = 0; i < l.count; ++i) {
            const PlanPoint& p = plan.points[l.first + i];
            const PlanPoint& q = plan.points[l.first + (i + 1) % l.count];
            if (!p.key.edge && !q.key.edge) continue;  // along an in-plane edge: no face split
            const PlanPoint& e = p.key.edge ? p : q;   // a crossing edge's point
            const PlanPoint& o = p.key.edge ? q : p;   // the face's other cut point
            for (int k = 0; k < 2; ++k) {
                // Face x -> y -> z with e's point P on edge x-y.
                const HalfedgeHandle h = m.halfedge_handle(EdgeHandle(e.key.id), k);
                const FaceHandle f = m.face_handle(h);
                if (!f.is_valid()) continue;
                const HalfedgeHandle hn = m.next_halfedge_handle(h);
                const VertexHandle corners[3] = {m.from_vertex_handle(h), m.to_vertex_handle(h),
                                                 m.to_vertex_handle(hn)};
                const Vec3& x = m.point(corners[0]);
                const Vec3& y = m.point(corners[1]);
                const Vec3& z = m.point(corners[2]);
                const Vec3& pp = e.position;
                const Vec3& qq = o.position;
                // Which split: 0 through on-plane z, 1 with Q on y-z, 2 with Q on z-x.
                int split = 0;
                if (!o.key.edge) {
                    if (o.key.id != corners[2].idx()) continue;
                } else if (o.key.id == m.edge_handle(hn).idx()) {
                    split = 1;
                } else if (o.key.id == m.edge_handle(m.next_halfedge_handle(hn)).idx()) {
                    split = 2;
                } else {
                    continue;
                }
                // Every part is a fixed fraction of the face (P at u of x -> y, Q at v of
                // y -> z or of z -> x; make_point put them there): when even the smallest part
                // is clear of every bound small() tests on the face's own area (its edges are at
                // most the face's longest), no part is small, and the exact tests are skipped
                // with the same answer (the margin of 1.5 is far above their rounding).
                {
                    const Edge xy = edge(x, y), xz = edge(x, z);
                    const double face2 = sqrnorm(cross(xy.d, xz.d));
                    const double longest2 = std::max({xy.len2, xz.len2, sqrdist(y, z)});
                    const double clear2 =
                        1.5 *
                        std::max(min_twice2, 2.0 * (kept2 + loss2 * (4.000000002 * longest2)));
                    auto from = [](const PlanPoint& c, VertexHandle v) {
                        return c.a == v.idx() ? c.t : 1.0 - c.t;
                    };
                    const double u = from(e, corners[0]);
                    double part = std::min(u, 1.0 - u);
                    if (split == 1) {
                        const double v = from(o, corners[1]);
                        part = std::min({u, (1.0 - u) * v, (1.0 - u) * (1.0 - v), u * v, 1.0 - v});
                    } else if (split == 2) {
                        const double w = from(o, corners[2]);
                        part = std::min({u * (1.0 - w), 1.0 - u, u * w, (1.0 - u) * (1.0 - w), w});
                    }
                    if (part * part * face2 > clear2) continue;
                }
                bool bad = false;
                if (split == 0) {
                    // Split through on-plane z: (x, P, z), (P, y, z).
                    const Edge xp = edge(x, pp), xz = edge(x, z), py = edge(pp, y),
                               pz = edge(pp, z);
                    bad = small(x, pp, z, xp, xz) || small(pp, y, z, py, pz);
                } else if (split == 1) {
                    // Q on y-z: lone vertex y; the quad x, P, Q, z takes either diagonal:
                    // (P, y, Q), (x, P, z), (P, Q, z), (x, P, Q), (x, Q, z).
                    const Edge py = edge(pp, y), pq = edge(pp, qq), xp = edge(x, pp),
                               xz = edge(x, z), pz = edge(pp, z), xq = edge(x, qq);
                    bad = small(pp, y, qq, py, pq) || small(x, pp, z, xp, xz) ||
                          small(pp, qq, z, pq, pz) || small(x, pp, qq, xp, xq) ||
                          small(x, qq, z, xq, xz);
                } else {
                    // Q on z-x: lone vertex x; the quad P, y, z, Q takes either diagonal:
                    // (x, P, Q), (P, y, z), (P, z, Q), (P, y, Q), (Q, y, z).
                    const Edge xp = edge(x, pp), xq = edge(x, qq), py = edge(pp, y),
                               pz = edge(pp, z), pq = edge(pp, qq), qy = edge(qq, y),
                               qz = edge(qq, z);
                    bad = small(x, pp, qq, xp, xq) || small(pp, y, z, py, pz) ||
                          small(pp, z, qq, pz, pq) || small(pp, y, qq, py, pq) ||
                          small(qq, y, z, qy, qz);
                }
                if (!bad) continue;
                // The corner nearest the plane, when a little beyond the tolerance, can be
                // snapped onto it instead (plan_snapped): the split then runs through it.
                propose_snap(s, plane, corners);
                status = CutStatus::kSliverSplit;
            }
        }
    }
    return status;
}

double distance_to_face(const TriMesh& m, FaceHandle f, const Vec3& p) {
    auto it = m.cfv_iter(f);
    const Vec3 a = m.point(*it++), b = m.point(*it++), c = m.point(*it);
    // Ericson, Real-Time Collision Detection, 5.1.5.
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = OpenMesh::dot(ab, ap), d2 = OpenMesh::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return (p - a).norm();
    const Vec3 bp = p - b;
    const double d3 = OpenMesh::dot(ab, bp), d4 = OpenMesh::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return (p - b).norm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
    const Vec3 cp = p - c;
    const double d5 = OpenMesh::dot(ab, cp), d6 = OpenMesh::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return (p - c).norm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
    const double denom = 1.0 / (va + vb + vc);
    return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

CutStatus plan_full(ContextState& s, const Plane& plane) {
    s.plan.clear();
    s.next_generation();
    TriMesh& m = s.mesh;
    Walker w(s, plane);
    // Only vertices within one (longest non-cap) edge of the plane can end a crossing or on-plane
    // edge: one streaming pass over the positions, then their one-rings.
    const double reach = s.max_edge_m + s.tolerance_m;
    const auto n = static_cast<int>(m.n_vertices());
    const TriMesh::Point* points = m.points();
    for (int i = 0; i < n; ++i) {
        if (std::abs(plane.signed_distance(points[i])) > reach) continue;
        const VertexHandle v(i);
        if (m.status(v).deleted()) continue;
        const int sv = w.side(v);
        if (sv < 0) continue;  // crossings are found from their positive end
        for (auto h : m.voh_range(v)) {
            const VertexHandle u = m.to_vertex_handle(h);
            const int su = w.side(u);
            CutPointKey start;
            if (sv > 0 && su < 0) {
                start = CutPointKey{m.edge_handle(h).idx(), true};
                if (w.marked(start)) continue;
            } else if (sv == 0 && su == 0 && v.idx() < u.idx()) {
                const FaceHandle f = m.face_handle(h);
                if (!f.is_valid() || !w.start_on(f, start)) continue;
            } else {
                continue;
            }
            const CutStatus st = w.walk(start);
            if (st != CutStatus::kOk) return st;
            s.plan.loops.back().selected = true;
        }
    }
    // Cap edges may be longer than the bound (a cap spans its cross-section): check cap faces.
    for (const FaceHandle f : s.cap_faces) {
        CutPointKey start;
        if (m.status(f).deleted() || !w.start_on(f, start)) continue;
        const CutStatus st = w.walk(start);
        if (st != CutStatus::kOk) return st;
        s.plan.loops.back().selected = true;
    }
    return s.plan.loops.empty() ? CutStatus::kPlaneMissesMesh : CutStatus::kOk;
}

FaceHandle find_seed_face(ContextState& s, const Seed& seed) {
    s.next_generation();
    return seed_face_near(s, seed);
}

namespace {

// The rest of a localised plan once its first loop is walked from `start`.
CutStatus plan_localised_from(ContextState& s, Walker& w, const Plane& plane, CutPointKey start) {
    s.next_generation();
    CutStatus st = w.walk(start);
    if (st != CutStatus::kOk) return st;
    if (s.plan.loops.front().area_m2 < 0) {
        st = select_loop_around_hole(s, w, plane);  // the hole is selected with it, below
        if (st != CutStatus::kOk) return st;
    } else {
        s.plan.loops.front().selected = true;
    }
    return add_nested_loops(s, w, plane);
}

}  // namespace

CutStatus plan_localised(ContextState& s, const Plane& plane, const Seed& seed) {
    s.plan.clear();
    const FaceHandle seed_face = find_seed_face(s, seed);
    if (!seed_face.is_valid()) return CutStatus::kSeedNotOnSurface;
    s.next_generation();
    Walker w(s, plane);
    CutPointKey start;
    const CutStatus st = find_start(s, w, plane, seed_face, start);
    if (st != CutStatus::kOk) return st;
    return plan_localised_from(s, w, plane, start);
}

CutStatus plan_localised_on(ContextState& s, const Plane& plane,
                            const std::vector<FaceHandle>& faces) {
    s.plan.clear();
    s.next_generation();
    Walker w(s, plane);
    for (FaceHandle f : faces) {
        CutPointKey start;
        if (!s.mesh.status(f).deleted() && w.start_on(f, start))
            return plan_localised_from(s, w, plane, start);
    }
    return CutStatus::kPlaneMissesMesh;
}

CutStatus plan_from_faces(ContextState& s, const Plane& plane,
                          const std::vector<FaceHandle>& faces) {
    s.plan.clear();
    s.next_generation();
    Walker w(s, plane);
    for (FaceHandle f : faces) {
        CutPointKey start;
        if (s.mesh.status(f).deleted() || !w.start_on(f, start)) continue;
        const CutStatus st = w.walk(start);
        if (st != CutStatus::kOk) return st;
        s.plan.loops.back().selected = true;
    }
    return s.plan.loops.empty() ? CutStatus::kPlaneMissesMesh : CutStatus::kOk;
}

CutStatus plan_wall(ContextState& s, const Plane& plane, const std::vector<FaceHandle>& faces) {
    CutStatus st = plan_from_faces(s, plane, faces);
    if (st != CutStatus::kOk) return st;
    Walker w(s, plane);
    return add_nested_loops(s, w, plane);
}

}  // namespace kerf::cut::detail
