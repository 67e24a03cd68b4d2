#include "display/cut/cap_chords.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_set>
#include <utility>
#include <vector>

#include "display/cut/apply_plan.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/section_plan.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/vec_ops.hpp"

namespace kerf::cut::detail {

namespace {

using mesh::EdgeHandle;
using mesh::FaceHandle;
using mesh::HalfedgeHandle;
using mesh::TriMesh;
using mesh::VertexHandle;

// A 2-D orientation is taken as a sign only beyond this fraction of the product of the two edge
// lengths (a point that close to a line is on it: the chord is not put in).
constexpr double kSideRelative = 1e-9;

// Flips move the surface only by the four corners' distances from the cap's plane (rim vertices
// of the earlier cut up to a few tolerances off it): the volume of the tetrahedron of each flipped
// quad, summed over a cut, may not exceed this times the mesh scale cubed (1e-13 refused 50 of
// the first chords of the 720 sequential cuts; the tests conserve volume to 1e-9 of meshes of at
// least 1e-2 scale³, 10 times this).
constexpr double kFlipVolumeRelative = 1e-12;

// A triangle of the earlier cap after the chord is kept only tilted less than 60 degrees from the
// cap's normal (as the caps' own `good` triangles).
constexpr double kMinCosine = 0.5;

// Whether edge e is an inner edge of one earlier cap.
bool inner_cap_edge(const ContextState& s, EdgeHandle e) {
    const TriMesh& m = s.mesh;
    const FaceHandle f = m.face_handle(m.halfedge_handle(e, 0));
    const FaceHandle g = m.face_handle(m.halfedge_handle(e, 1));
    if (!f.is_valid() || !g.is_valid()) return false;
    const std::uint8_t tag = m.property(s.cap, f);
    return tag != kCapNone && tag == m.property(s.cap, g) && m.normal(f) == m.normal(g);
}

bool inner_point(const ContextState& s, const PlanPoint& p) {
    return p.key.edge && inner_cap_edge(s, EdgeHandle(p.key.id));
}

// One crossing of an earlier cap: from cut point `from` to cut point `to` (an on-plane vertex or
// a point on an edge that is not an inner cap edge) over the inner edges `edges`, in loop order.
struct Run {
    PlanPoint from, to;
    std::vector<EdgeHandle> edges;
    Vec3 normal;  // the cap's stored normal
    std::uint8_t tag = kCapNone;
    VertexHandle e, x;  // the chord's ends, once they are vertices
};

std::vector<Run> find_runs(const ContextState& s) {
    const SectionPlan& plan = s.plan;
    const TriMesh& m = s.mesh;
    std::vector<Run> runs;
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected || l.count < 3) continue;
        std::uint32_t start = 0;
        while (start < l.count && inner_point(s, plan.points[l.first + start])) ++start;
        if (start == l.count) continue;  // no end to start from (cannot happen on a closed cap)
        Run run;
        for (std::uint32_t j = 1; j <= l.count; ++j) {
            const PlanPoint& p = plan.points[l.first + (start + j) % l.count];
            if (inner_point(s, p)) {
                if (run.edges.empty()) run.from = plan.points[l.first + (start + j - 1) % l.count];
                run.edges.push_back(EdgeHandle(p.key.id));
                continue;
            }
            if (!run.edges.empty()) {
                run.to = p;
                const FaceHandle f = m.face_handle(m.halfedge_handle(run.edges.front(), 0));
                run.normal = m.normal(f);
                run.tag = m.property(s.cap, f);
                runs.push_back(std::move(run));
                run.edges.clear();
            }
        }
    }
    return runs;
}

// The earlier cap's plane frame (its stored normal), with `origin` at (0, 0).
struct Frame {
    Vec3 origin, u, v;
    Vec2 at(const Vec3& p) const {
        const Vec3 d = sub(p, origin);
        return Vec2(dot(d, u), dot(d, v));
    }
};

Frame frame_of(const Vec3& origin, const Vec3& normal) {
    const Vec3 axis = std::abs(normal[0]) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    Vec3 u = cross(normal, axis);
    u /= std::sqrt(sqrnorm(u));
    return Frame{origin, u, cross(normal, u)};
}

double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// The side of c from the line a -> b: +1 left, -1 right, 0 on it (within kSideRelative).
int side_of(const Vec2& a, const Vec2& b, const Vec2& c) {
    const double o = orient(a, b, c);
    const double scale = std::sqrt(sqrnorm(sub(b, a)) * sqrnorm(sub(c, a)));
    if (o > kSideRelative * scale) return 1;
    if (o < -kSideRelative * scale) return -1;
    return 0;
}

class ChordMaker {
public:
    ChordMaker(ContextState& s, const Plane& plane, EditUndo& undo)
        : s_(s), m_(s.mesh), plane_(plane), undo_(undo) {}

    // Puts in the chord of every run that takes one (each run on its own: one that fails is
    // undone and left to the usual split); the number put in.
    std::uint32_t run(std::vector<Run>& runs) {
        s_.ensure_capacity(2 * runs.size(), 6 * runs.size(), 4 * runs.size());
        std::uint32_t made = 0;
        for (Run& r : runs) {
            if (!feasible(r)) continue;
            const EditUndo::Checkpoint before = undo_.checkpoint(s_);
            const std::size_t splits = split_.size();
            // Each face once per run, at its state before the run: a run that fails is undone
            // to there (a face an earlier run kept and this one changed included).
            recorded_.clear();
            const double volume = volume6_;
            flipped_.clear();
            r.e = end_vertex(r.from);
            r.x = end_vertex(r.to);
            if (r.e.is_valid() && r.x.is_valid() && r.e != r.x && insert(r) && check(r)) {
                ++made;
                continue;
            }
            undo_.restore_to(s_, before);
            split_.resize(splits);
            volume6_ = volume;
            r.e = r.x = VertexHandle();
        }
        return made;
    }

private:
    // What can be checked before any edit: the chord's ends apart, every crossed edge's ends
    // clearly on both sides of it in the cap's plane.
    bool feasible(const Run& r) const {
        if (sqrdist(r.from.position, r.to.position) <= s_.tolerance_m * s_.tolerance_m)
            return false;
        const Frame fr = frame_of(r.from.position, r.normal);
        const Vec2 a(0, 0), b = fr.at(r.to.position);
        for (const EdgeHandle e : r.edges) {
            const HalfedgeHandle h = m_.halfedge_handle(e, 0);
            const int su = side_of(a, b, fr.at(m_.point(m_.from_vertex_handle(h))));
            const int sw = side_of(a, b, fr.at(m_.point(m_.to_vertex_handle(h))));
            if (su == 0 || sw == 0 || su == sw) return false;
        }
        for (const PlanPoint* p : {&r.from, &r.to})
            if (p->key.edge && m_.is_boundary(EdgeHandle(p->key.id))) return false;
        return true;
    }

    // Records each face once, before its first edit (the flips of a run only trade diagonals
    // among the same faces: recording every flip's faces made the records grow with the flips).
    void record(std::initializer_list<FaceHandle> faces) {
        std::vector<FaceHandle> fresh;
        for (const FaceHandle f : faces)
            if (recorded_.insert(f.idx()).second) fresh.push_back(f);
        if (!fresh.empty()) undo_.record_faces(s_, fresh);
    }

    // The vertex at a chord's end: an on-plane vertex as it is, an edge point split into its edge
    // (once, when two runs share it). The split halves are checked in check().
    VertexHandle end_vertex(const PlanPoint& p) {
        if (!p.key.edge) return VertexHandle(p.key.id);
        for (const Split& sp : split_)
            if (sp.edge == p.key.id) return sp.v;
        const EdgeHandle e(p.key.id);
        const HalfedgeHandle h0 = m_.halfedge_handle(e, 0), h1 = m_.halfedge_handle(e, 1);
        const FaceHandle f = m_.face_handle(h0), g = m_.face_handle(h1);
        if (!f.is_valid() || !g.is_valid()) return VertexHandle();
        // Each original face's far corner and twice-area vector: its halves must keep it.
        Split sp;
        sp.edge = p.key.id;
        for (int k = 0; k < 2; ++k) {
            const HalfedgeHandle h = k == 0 ? h0 : h1;
            const VertexHandle a = m_.from_vertex_handle(h), b = m_.to_vertex_handle(h);
            const VertexHandle c = m_.to_vertex_handle(m_.next_halfedge_handle(h));
            sp.corner[k] = c;
            sp.twice[k] = cross(sub(m_.point(b), m_.point(a)), sub(m_.point(c), m_.point(a)));
        }
        record({f, g});
        const int faces_before = static_cast<int>(m_.n_faces());
        sp.v = make_cut_vertex(m_, p);
        m_.split_copy(e, sp.v);
        for (int fi = faces_before; fi < static_cast<int>(m_.n_faces()); ++fi) {
            const FaceHandle n(fi);
            if (m_.property(s_.cap, n) != kCapNone)
                s_.cap_faces.push_back(n);
            else
                s_.tree.insert(m_, n);
        }
        split_.push_back(sp);
        return sp.v;
    }

    // Sloan's constrained edge insertion of r.e -> r.x over the crossed inner edges.
    bool insert(const Run& r) {
        const Frame fr = frame_of(m_.point(r.e), r.normal);
        const Vec2 a(0, 0), b = fr.at(m_.point(r.x));
        auto side = [&](VertexHandle v) { return side_of(a, b, fr.at(m_.point(v))); };
        std::deque<EdgeHandle> queue(r.edges.begin(), r.edges.end());
        std::size_t since_flip = 0;
        // Sloan's insertion ends after O(n^2) flips for n crossed edges (a fan of near-collinear
        // needles, flipped from its ends, takes about that); rounding could make it cycle, so it
        // stops after 64 + n^2.
        std::size_t flips_left = 64 + r.edges.size() * r.edges.size();
        while (!queue.empty()) {
            if (since_flip > queue.size()) return false;  // no crossed quad is convex
            if (flips_left == 0) return false;
            const EdgeHandle e = queue.front();
            queue.pop_front();
            const HalfedgeHandle h = m_.halfedge_handle(e, 0), o = m_.halfedge_handle(e, 1);
            const FaceHandle f = m_.face_handle(h), g = m_.face_handle(o);
            if (!f.is_valid() || !g.is_valid() || m_.property(s_.cap, f) != r.tag ||
                m_.property(s_.cap, g) != r.tag || m_.normal(f) != r.normal ||
                m_.normal(g) != r.normal)
                return false;
            const VertexHandle u = m_.from_vertex_handle(h), w = m_.to_vertex_handle(h);
            const VertexHandle x = m_.to_vertex_handle(m_.next_halfedge_handle(h));
            const VertexHandle y = m_.to_vertex_handle(m_.next_halfedge_handle(o));
            const Vec2 px = fr.at(m_.point(x)), py = fr.at(m_.point(y));
            const int su = side_of(px, py, fr.at(m_.point(u)));
            const int sw = side_of(px, py, fr.at(m_.point(w)));
            if (su == 0 || sw == 0 || su == sw || !m_.is_flip_ok(e)) {
                queue.push_back(e);
                ++since_flip;
                continue;
            }
            const Vec3& pu = m_.point(u);
            volume6_ += std::abs(
                dot(cross(sub(m_.point(w), pu), sub(m_.point(x), pu)), sub(m_.point(y), pu)));
            record({f, g});
            --flips_left;
            m_.flip(e);
            flipped_.push_back(e);
            since_flip = 0;
            if (x == r.e || x == r.x || y == r.e || y == r.x) continue;
            const int sx = side(x), sy = side(y);
            if (sx == 0 || sy == 0) return false;  // a cap vertex on the chord
            if (sx != sy) queue.push_back(e);
        }
        return m_.find_halfedge(r.e, r.x).is_valid();
    }

    bool bad_triangle(FaceHandle f, const Vec3& normal, double cosine) const {
        auto it = m_.cfv_iter(f);
        const Vec3 a = m_.point(*it++), b = m_.point(*it++), c = m_.point(*it);
        const Vec3 n = cross(sub(b, a), sub(c, a));
        const double n2 = sqrnorm(n);
        return s_.too_small(a, b, c, n2) || !(dot(n, normal) > cosine * std::sqrt(n2));
    }

    // The run's edit: the flips' volume (all runs so far) within the bound, every flipped quad's
    // two triangles good triangles of their cap, the split halves at its ends (cap halves good,
    // others facing as the face they come from), and the chord's two faces on either side of the
    // new plane (the plan walks the chord as an edge in the plane between a positive and a
    // negative face).
    bool check(const Run& r) const {
        const double scale3 = s_.scale_m * s_.scale_m * s_.scale_m;
        if (!(volume6_ <= 6.0 * kFlipVolumeRelative * scale3)) return false;
        for (const EdgeHandle e : flipped_)
            for (int k = 0; k < 2; ++k) {
                const FaceHandle f = m_.face_handle(m_.halfedge_handle(e, k));
                if (bad_triangle(f, m_.normal(f), kMinCosine)) return false;
            }
        for (const Split& sp : split_) {
            if (sp.v != r.e && sp.v != r.x) continue;
            for (const FaceHandle f : m_.vf_range(sp.v)) {
                if (m_.property(s_.cap, f) != kCapNone) {
                    if (bad_triangle(f, m_.normal(f), kMinCosine)) return false;
                    continue;
                }
                bool matched = false;
                for (int k = 0; k < 2; ++k) {
                    bool has = false;
                    for (const VertexHandle c : m_.fv_range(f)) has |= c == sp.corner[k];
                    if (!has) continue;
                    matched = true;
                    if (bad_triangle(f, sp.twice[k], 0.0)) return false;
                }
                if (!matched) return false;
            }
        }
        const HalfedgeHandle h = m_.find_halfedge(r.e, r.x);
        if (!h.is_valid()) return false;
        const double tol = kSnapTolerances * s_.tolerance_m;
        const double dx =
            plane_.signed_distance(m_.point(m_.to_vertex_handle(m_.next_halfedge_handle(h))));
        const double dy = plane_.signed_distance(
            m_.point(m_.to_vertex_handle(m_.next_halfedge_handle(m_.opposite_halfedge_handle(h)))));
        if (!((dx > tol && dy < -tol) || (dx < -tol && dy > tol))) return false;
        return true;
    }

    ContextState& s_;
    TriMesh& m_;
    const Plane& plane_;
    EditUndo& undo_;
    // An end split into its edge: the edge, the new vertex, and per original face of the edge its
    // far corner and twice-area vector (its halves must keep that orientation).
    struct Split {
        std::int32_t edge = -1;
        VertexHandle v;
        VertexHandle corner[2];
        Vec3 twice[2];
    };
    std::vector<Split> split_;
    std::vector<EdgeHandle> flipped_;            // by the run being put in
    double volume6_ = 0;                         // six times the flips' tetrahedra, summed
    std::unordered_set<std::int32_t> recorded_;  // faces recorded in undo_ in this run
};

}  // namespace

bool crosses_cap_inner_edges(const ContextState& s) {
    const SectionPlan& plan = s.plan;
    const TriMesh& m = s.mesh;
    // Every cut of a mesh with caps asks this: the tags read straight from their array, and the
    // full test only for an edge whose first face is a cap face.
    const std::uint8_t* const tags = m.property(s.cap).data();
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const PlanPoint& p = plan.points[i];
            if (!p.key.edge) continue;
            const FaceHandle f = m.face_handle(HalfedgeHandle(2 * p.key.id));
            if (f.is_valid() && tags[f.idx()] != kCapNone &&
                inner_cap_edge(s, EdgeHandle(p.key.id)))
                return true;
        }
    }
    return false;
}

std::uint32_t insert_cap_chords(ContextState& s, const Plane& plane, EditUndo& undo) {
    std::vector<Run> runs = find_runs(s);
    if (runs.empty()) return 0;
    ChordMaker maker(s, plane, undo);
    return maker.run(runs);
}

CutStatus plan_through_caps(ContextState& s, const Plane& plane, std::vector<std::int32_t>& snapped,
                            const std::function<CutStatus()>& plan, EditUndo& undo,
                            std::uint32_t& chords, bool merges_first_last) {
    chords = 0;
    if (s.cap_faces.empty() || !s.cap_chords)
        return plan_snapped(s, plane, snapped, plan, merges_first_last);
    s.snapped = &snapped;
    const CutStatus first = plan();
    s.snapped = nullptr;
    if (first != CutStatus::kOk || !crosses_cap_inner_edges(s))
        return plan_snapped(s, plane, snapped, plan, merges_first_last, &first);
    const EditUndo::Checkpoint before = undo.checkpoint(s);
    const std::vector<std::int32_t> snapped_before = snapped;
    if (const std::uint32_t n = insert_cap_chords(s, plane, undo); n > 0) {
        const CutStatus st = plan_snapped(s, plane, snapped, plan, merges_first_last);
        if (st == CutStatus::kOk) {
            chords = n;
            return st;
        }
    }
    undo.restore_to(s, before);
    snapped = snapped_before;
    return plan_snapped(s, plane, snapped, plan, merges_first_last);
}

}  // namespace kerf::cut::detail
