// The cap half of a slice plan: grouping loops into cap regions, triangulating each with the
// triangulator, and guaranteeing no sliver (see section_plan.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "config/base/check.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/section_plan.hpp"
#include "display/cut/vec_ops.hpp"

namespace kerf::cut::detail {

namespace {

constexpr double kMinCapRelativeArea = kMinTriangleRelativeArea;

// Smallest cosine between a kept cap triangle's normal and the cap's (see plan_caps).
constexpr double kMinCapCosine = 0.05;

double area2(const std::vector<Point2>& uv, const Triangle& t) {
    const Point2& a = uv[t.a];
    const Point2& b = uv[t.b];
    const Point2& c = uv[t.c];
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

double longest2(const std::vector<Point2>& uv, const Triangle& t) {
    return std::max({sqrnorm(sub(uv[t.a], uv[t.b])), sqrnorm(sub(uv[t.b], uv[t.c])),
                     sqrnorm(sub(uv[t.c], uv[t.a]))});
}

// Rim points that are collinear up to rounding (a plane crossing a flat quad) can leave ears of
// near-zero area. Each such sliver (a, b, c), b between a and c, is removed by flipping its long
// edge (c, a) with the neighbouring triangle (a, c, d): (a, b, d) and (b, c, d).
bool repair_slivers(const std::vector<Point2>& uv, std::vector<Triangle>& tris) {
    constexpr double kSliver = 1e-9;
    for (int round = 0; round < 8; ++round) {
        bool changed = false;
        for (std::size_t i = 0; i < tris.size(); ++i) {
            if (area2(uv, tris[i]) > kSliver * longest2(uv, tris[i])) continue;
            Triangle t = tris[i];
            // Rotate so that (c, a) is the longest edge and b the middle vertex.
            for (int r = 0; r < 3 && (uv[t.c] - uv[t.a]).sqrnorm() < longest2(uv, t); ++r)
                t = Triangle{t.b, t.c, t.a};
            std::size_t j = tris.size();
            std::uint32_t d = 0;
            for (std::size_t k = 0; k < tris.size() && j == tris.size(); ++k) {
                const Triangle& o = tris[k];
                const std::uint32_t v[3] = {o.a, o.b, o.c};
                for (int e = 0; e < 3; ++e)
                    if (v[e] == t.a && v[(e + 1) % 3] == t.c) j = k, d = v[(e + 2) % 3];
            }
            if (j == tris.size()) return false;  // the long edge is on the rim: cannot flip
            const Triangle n1{t.a, t.b, d}, n2{t.b, t.c, d};
            const double worst = std::min(area2(uv, n1), area2(uv, n2));
            if (!(worst > area2(uv, t))) continue;
            tris[i] = n1;
            tris[j] = n2;
            changed = true;
        }
        if (!changed) return true;
    }
    return true;
}

}  // namespace

namespace {

// Cap groups: each selected outer loop with the selected holes whose smallest enclosing outer
// loop it is. Loops of different pieces (or interpenetrating bones) are capped separately.
std::vector<std::int32_t> cap_groups(const SectionPlan& plan) {
    std::vector<std::int32_t> parent(plan.loops.size(), -1);
    for (std::size_t i = 0; i < plan.loops.size(); ++i) {
        const PlanLoop& h = plan.loops[i];
        if (!h.selected || h.area_m2 >= 0) continue;
        double best = 1e300;
        parent[i] = -2;  // orphan unless an outer loop contains it
        for (std::size_t j = 0; j < plan.loops.size(); ++j) {
            const PlanLoop& o = plan.loops[j];
            if (o.selected && o.area_m2 > 0 && o.area_m2 < best && loop_nested(plan, h, o))
                best = o.area_m2, parent[i] = static_cast<std::int32_t>(j);
        }
    }
    return parent;
}

}  // namespace

namespace {

// A rim point is "straight" when it lies on the line through its neighbours up to rounding (a
// plane crossing a flat quad gives runs of such points). Triangulating them directly gives ears
// of zero area, so they are left out of the triangulation and put back as fans (see below).
constexpr double kStraightRelative = 1e-9;

// b is straight between a and c when it lies on their line up to rounding, or, for on-plane
// vertices kept where they are (up to tol off the plane), when its 2-D offset from the line is
// within twice the points' distance from the plane: a triangle that thin could tilt over in 3-D.
bool straight(const Vec2& a, const Vec2& b, const Vec2& c, double off_plane_m, double min_cross) {
    const double cr = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    const double along = dot(sub(b, a), sub(c, b));
    const double ac2 = sqrnorm(sub(c, a));
    const double noise = 2.0 * off_plane_m;
    return along > 0 && (std::abs(cr) <= kStraightRelative * ac2 || std::abs(cr) <= min_cross ||
                         cr * cr <= noise * noise * ac2);
}

double plan_area2(const SectionPlan& plan, const Triangle& t) {
    const Vec2& a = plan.points[t.a].uv;
    const Vec2& b = plan.points[t.b].uv;
    const Vec2& c = plan.points[t.c].uv;
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// A bone round its canal, one outer loop and one hole, stitched as a strip with every point kept:
// no straight point is left out and put back as a fan, so the flips towards Delaunay that the
// fans needed (about one a point on a round bone) are not needed. False when the group is not an
// annulus or the strip is refused (try_triangulate_group decides then).
bool try_strip(ContextState& s, const std::vector<const PlanLoop*>& loops,
               std::vector<Triangle>& out) {
    if (loops.size() != 2 || (loops[0]->area_m2 > 0) == (loops[1]->area_m2 > 0)) return false;
    const SectionPlan& plan = s.plan;
    std::vector<Point2>& uv = s.cap_strip_uv;
    uv.clear();
    for (const PlanLoop* l : loops)
        for (std::uint32_t k = 0; k < l->count; ++k) uv.push_back(plan.points[l->first + k].uv);
    const std::uint32_t n0 = loops[0]->count;
    const std::span<const Point2> spans[2] = {{uv.data(), n0}, {uv.data() + n0, loops[1]->count}};
    std::vector<Triangle>& tris = s.cap_strip;
    if (!s.triangulator.triangulate_strip(spans, tris)) return false;
    const std::uint32_t first0 = loops[0]->first, first1 = loops[1]->first;
    auto plan_index = [&](std::uint32_t k) { return k < n0 ? first0 + k : first1 + (k - n0); };
    // The strip's neighbours, as CapAdjacency::build would link them, in O(n): triangle k is
    // (o, x, h), x the point it advanced to; its rung in, h -> o (slot 2), is the reverse of
    // triangle k - 1's rung out (slot 1, x -> h, where x is on o's loop; slot 0, o -> x, where
    // x is on h's loop), cyclically; its third edge is on the rim.
    const auto base = static_cast<std::uint32_t>(out.size());
    const auto n = static_cast<std::uint32_t>(tris.size());
    std::vector<std::uint32_t>& nb = s.cap_strip_neighbours;
    const bool linked = nb.size() == 3 * std::size_t{base};  // every group before a strip too
    if (linked) nb.resize(3 * (std::size_t{base} + n), kNoCapNeighbour);
    for (std::uint32_t k = 0; k < n; ++k) {
        const Triangle& t = tris[k];
        out.push_back(Triangle{plan_index(t.a), plan_index(t.b), plan_index(t.c)});
        if (!linked) continue;
        const std::uint32_t rung_out = 3 * (base + k) + ((t.a < n0) == (t.b < n0) ? 1 : 0);
        const std::uint32_t next_in = 3 * (base + (k + 1 == n ? 0 : k + 1)) + 2;
        nb[rung_out] = next_in;
        nb[next_in] = rung_out;
    }
    return true;
}

// Triangulates one cap group (an outer loop and its holes) over the plan's point indices.
enum class GroupResult { kOk, kFailed, kRetry };

// One attempt; a fan that would fold (its apex too close to the kept edge) forces that gap's
// points to be kept (`forced`) and asks for another attempt.
GroupResult try_triangulate_group(ContextState& s, const Plane& plane,
                                  const std::vector<const PlanLoop*>& loops,
                                  std::vector<char>& forced, std::vector<Triangle>& out) {
    SectionPlan& plan = s.plan;
    const double min_cross = 4.0 * kMinCapRelativeArea * s.scale_m * s.scale_m;
    std::vector<Point2> uv;            // kept points
    std::vector<std::uint32_t> index;  // kept point -> plan point
    std::vector<std::span<const Point2>> spans;
    std::vector<std::size_t> sizes;
    // Edges (u, w) of the kept loops that have left-out points between u and w.
    struct Gap {
        std::uint32_t u, w, first, count;  // plan indices; left-out points first .. (loop order)
    };
    std::vector<Gap> gaps;
    std::vector<std::uint32_t> removed;  // plan indices of left-out points, grouped per gap
    std::vector<double> off;             // per point of a loop: |distance from the plane|
    for (const PlanLoop* l : loops) {
        const std::size_t before = uv.size();
        const std::uint32_t count = l->count;
        auto pt = [&](std::uint32_t k) -> const Vec2& { return plan.points[l->first + k].uv; };
        auto wrap = [&](std::uint32_t k) { return k >= count ? k - count : k; };  // k < 2 count
        std::vector<char> keep(l->count, 1);
        std::uint32_t kept = l->count;
        // Each point's distance from the plane, once (the straightness test of a point and of
        // its two neighbours reads it).
        off.resize(l->count);
        for (std::uint32_t k = 0; k < l->count; ++k)
            off[k] = std::abs(plane.signed_distance(plan.points[l->first + k].position));
        for (std::uint32_t k = 0; k < l->count; ++k) {
            const std::uint32_t prev = k == 0 ? l->count - 1 : k - 1;
            const std::uint32_t next = k + 1 == l->count ? 0 : k + 1;
            const double off_plane = std::max({off[prev], off[k], off[next]});
            if (kept > 3 && !forced[l->first + k] &&
                straight(pt(prev), pt(k), pt(next), off_plane, min_cross))
                keep[k] = 0, --kept;
        }
        std::uint32_t start = 0;
        while (!keep[start]) ++start;
        for (std::uint32_t j = 0; j < count; ++j) {
            const std::uint32_t k = wrap(start + j);
            if (!keep[k]) continue;
            index.push_back(l->first + k);
            uv.push_back(pt(k));
            std::uint32_t n = 1;
            while (!keep[wrap(k + n)]) ++n;  // a kept point within one turn: n < count
            if (n > 1) {
                gaps.push_back(Gap{l->first + k, l->first + wrap(k + n),
                                   static_cast<std::uint32_t>(removed.size()), n - 1});
                for (std::uint32_t q = 1; q < n; ++q) removed.push_back(l->first + wrap(k + q));
            }
        }
        sizes.push_back(uv.size() - before);
    }
    std::size_t offset = 0;
    for (std::size_t n : sizes) spans.emplace_back(uv.data() + offset, n), offset += n;
    std::vector<Triangle> tris;
    if (!s.triangulator.triangulate(spans, tris) || !repair_slivers(uv, tris))
        return GroupResult::kFailed;
    for (Triangle& t : tris) t = Triangle{index[t.a], index[t.b], index[t.c]};
    if (gaps.empty()) {  // every point kept: nothing to put back
        out.insert(out.end(), tris.begin(), tris.end());
        return GroupResult::kOk;
    }
    // Put the left-out points back: the triangle on kept edge (u, w) becomes a fan from its apex.
    // The triangle holding each gap's edge u -> w, found through the gap starting at u (a kept
    // point starts at most one gap): the lowest such triangle, as a sorted edge list gave.
    constexpr std::uint32_t kNone = ~std::uint32_t{0};
    std::vector<std::uint32_t>& gap_at = s.cap_scratch;
    gap_at.assign(plan.points.size(), kNone);
    for (std::uint32_t k = 0; k < gaps.size(); ++k) gap_at[gaps[k].u] = k;
    std::vector<std::uint32_t> owner(gaps.size(), kNone);
    auto note = [&](std::uint32_t x, std::uint32_t y, std::uint32_t tri, bool replace) {
        const std::uint32_t k = gap_at[x];
        if (k != kNone && gaps[k].w == y && (replace || owner[k] == kNone)) owner[k] = tri;
    };
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
        const Triangle& t = tris[i];
        note(t.a, t.b, i, false), note(t.b, t.c, i, false), note(t.c, t.a, i, false);
    }
    for (std::uint32_t k = 0; k < gaps.size(); ++k) {
        const Gap& g = gaps[k];
        if (owner[k] == kNone) return GroupResult::kFailed;
        const std::uint32_t ti = owner[k];
        Triangle t = tris[ti];
        while (t.a != g.u) t = Triangle{t.b, t.c, t.a};
        if (t.b != g.w) return GroupResult::kFailed;
        const std::uint32_t apex = t.c;
        // (u, p1, x), (p1, p2, x), ..., (pk, w, x): the first keeps slot ti.
        tris[ti] = Triangle{g.u, removed[g.first], apex};
        for (std::uint32_t q = 0; q + 1 < g.count; ++q)
            tris.push_back(Triangle{removed[g.first + q], removed[g.first + q + 1], apex});
        tris.push_back(Triangle{removed[g.first + g.count - 1], g.w, apex});
        const std::size_t fan_end = tris.size();
        bool folded = !(plan_area2(plan, tris[ti]) > 0);
        for (std::size_t q = fan_end - g.count; q < fan_end; ++q)
            folded |= !(plan_area2(plan, tris[q]) > 0);
        if (folded) {
            for (std::uint32_t q = 0; q < g.count; ++q) forced[removed[g.first + q]] = 1;
            return GroupResult::kRetry;
        }
        // The fan's last triangle now holds w -> x (a later gap's edge when x follows w).
        note(g.w, apex, static_cast<std::uint32_t>(tris.size() - 1), true);
    }
    out.insert(out.end(), tris.begin(), tris.end());
    return GroupResult::kOk;
}

// What plan_caps already knows of a cap triangle (per slot, kept through every flip): `good`
// implies `acceptable`, and both are pure functions of the triangle, so a known answer is not
// asked again.
constexpr char kUnknown = 0, kKnownAcceptable = 1, kKnownGood = 2;

// Cap triangles with the neighbour across each edge (SectionPlan::cap_neighbours), kept up to
// date through every flip, so the triangle across an edge is one lookup (searching the
// triangles, or a per-point edge table rebuilt every pass, made the flips a third of a cut).
class CapAdjacency {
public:
    using Scratch = ContextState::CapPlanScratch;
    CapAdjacency(std::vector<Triangle>& tris, std::vector<std::uint32_t>& neighbours, Scratch& w)
        : tris_(tris),
          nb_(neighbours),
          from_(w.from),
          to_(w.to),
          first_(w.first),
          out_(w.out),
          in_(w.in),
          fill_(w.fill),
          seen_(w.seen) {}

    static std::uint32_t corner(const Triangle& t, int k) {
        static constexpr std::uint32_t Triangle::*kCorners[3] = {&Triangle::a, &Triangle::b,
                                                                 &Triangle::c};
        return t.*kCorners[k];
    }

    // Links every edge slot to the slot of its reverse edge; false when a directed edge is held
    // twice (not a triangulation). O(points + triangles): every triangle at point u has one edge
    // out of u and the one before it into u, so u's incoming edges are found through its own.
    bool build(std::size_t points) {
        const auto n = static_cast<std::uint32_t>(tris_.size());
        const std::size_t slots = 3 * std::size_t{n};
        nb_.assign(slots, kNoCapNeighbour);
        at_least(from_, slots);  // from_, to_, out_ and in_ are written before they are read
        at_least(to_, slots);
        for (std::uint32_t i = 0; i < n; ++i) {
            const Triangle& t = tris_[i];
            from_[3 * i] = t.a, from_[3 * i + 1] = t.b, from_[3 * i + 2] = t.c;
            to_[3 * i] = t.b, to_[3 * i + 1] = t.c, to_[3 * i + 2] = t.a;
        }
        first_.assign(points + 1, 0);
        for (std::size_t k = 0; k < slots; ++k) ++first_[from_[k] + 1];
        for (std::size_t k = 1; k < first_.size(); ++k) first_[k] += first_[k - 1];
        at_least(out_, slots);
        at_least(in_, slots);
        fill_.assign(first_.begin(), first_.end() - 1);
        for (std::uint32_t i = 0; i < n; ++i) {
            // Slot 3i + e leaves corner e; the slot before it in the triangle enters it.
            const std::uint32_t k = 3 * i;
            std::uint32_t at = fill_[from_[k]]++;
            out_[at] = k, in_[at] = k + 2;
            at = fill_[from_[k + 1]]++;
            out_[at] = k + 1, in_[at] = k;
            at = fill_[from_[k + 2]]++;
            out_[at] = k + 2, in_[at] = k + 1;
        }
        seen_.assign(points, kNoCapNeighbour);  // per point w: the slot u -> w, this u's only
        for (std::uint32_t u = 0; u < points; ++u) {
            for (std::uint32_t k = first_[u]; k < first_[u + 1]; ++k) {
                const std::uint32_t w = to_[out_[k]];
                if (seen_[w] != kNoCapNeighbour && from_[seen_[w]] == u) return false;
                seen_[w] = out_[k];
            }
            for (std::uint32_t k = first_[u]; k < first_[u + 1]; ++k) {
                const std::uint32_t in = in_[k];  // x -> u, before out_[k] in its triangle
                const std::uint32_t back = seen_[from_[in]];
                if (back == kNoCapNeighbour || from_[back] != u || nb_[in] == back) continue;
                if (nb_[in] != kNoCapNeighbour || nb_[back] != kNoCapNeighbour) return false;
                nb_[in] = back, nb_[back] = in;
            }
        }
        return true;
    }

    // The slot across slot `s` (kNoCapNeighbour on the rim).
    std::uint32_t across(std::uint32_t s) const { return nb_[s]; }
    // across() of every slot, as an array (kept up to date by flip()).
    const std::uint32_t* across_all() const { return nb_.data(); }

    // Flips the edge of slot si = 3i + e (c -> a, triangle i = (a, b, c) read from a) with its
    // reverse sj = 3j + f (a -> c, triangle j = (a, c, d)): i becomes (a, b, d), j (b, c, d).
    void flip(std::uint32_t si, std::uint32_t sj) {
        const std::uint32_t i = si / 3, j = sj / 3;
        const int e = static_cast<int>(si - 3 * i), f = static_cast<int>(sj - 3 * j);
        const int e1 = kNext[e], e2 = kAfterNext[e], f1 = kNext[f], f2 = kAfterNext[f];
        const std::uint32_t ab = nb_[3 * i + e1], bc = nb_[3 * i + e2];
        const std::uint32_t cd = nb_[3 * j + f1], da = nb_[3 * j + f2];
        const Triangle ti = tris_[i];
        const std::uint32_t d = corner(tris_[j], f2);
        tris_[i] = Triangle{corner(ti, e1), corner(ti, e2), d};
        tris_[j] = Triangle{corner(ti, e2), corner(ti, e), d};
        link(3 * i, ab), link(3 * i + 2, da), link(3 * j, bc), link(3 * j + 1, cd);
        nb_[3 * i + 1] = 3 * j + 2, nb_[3 * j + 2] = 3 * i + 1;
    }

    // The triangles flip(si, sj) would make of triangle `ti` through slot si (corner e = si % 3
    // to the next) and the apex d across it: (a, b, d) and (b, c, d), changing nothing.
    static std::pair<Triangle, Triangle> flipped(const Triangle& ti, int e, std::uint32_t d) {
        return {Triangle{corner(ti, kNext[e]), corner(ti, kAfterNext[e]), d},
                Triangle{corner(ti, kAfterNext[e]), corner(ti, e), d}};
    }
    static constexpr std::uint32_t kNoCorner = ~std::uint32_t{0};
    // The corner of triangle t opposite its edge v -> u, or kNoCorner when t has none.
    static std::uint32_t apex_of(const Triangle& t, std::uint32_t v, std::uint32_t u) {
        for (int k = 0; k < 3; ++k)
            if (corner(t, k) == v && corner(t, kNext[k]) == u) return corner(t, kAfterNext[k]);
        return kNoCorner;
    }

private:
    static constexpr int kNext[3] = {1, 2, 0}, kAfterNext[3] = {2, 0, 1};  // (k + 1, 2) % 3

    void link(std::uint32_t s, std::uint32_t other) {
        nb_[s] = other;
        if (other != kNoCapNeighbour) nb_[other] = s;
    }

    // Grows v to at least n elements, keeping (not filling) those it has.
    static void at_least(std::vector<std::uint32_t>& v, std::size_t n) {
        if (v.size() < n) v.resize(n);
    }

    std::vector<Triangle>& tris_;
    std::vector<std::uint32_t>& nb_;
    // Scratch, kept in the context from cut to cut (ContextState::CapPlanScratch).
    std::vector<std::uint32_t>& from_;  ///< per slot, as the triangles were at build()
    std::vector<std::uint32_t>& to_;
    std::vector<std::uint32_t>& first_;
    std::vector<std::uint32_t>& out_;
    std::vector<std::uint32_t>& in_;
    std::vector<std::uint32_t>& fill_;
    std::vector<std::uint32_t>& seen_;
};

// Whether plan.cap_neighbours (a plan of strips) are the links CapAdjacency::build makes of
// `tris` (a debug check: built into copies).
bool links_as_built(ContextState& s, const std::vector<Triangle>& tris) {
    std::vector<Triangle> copy = tris;
    std::vector<std::uint32_t> built;
    CapAdjacency adj(copy, built, s.cap_plan);
    return adj.build(s.plan.points.size()) && built == s.plan.cap_neighbours;
}

// Lawson flips towards the Delaunay triangulation of the cap (in the plane frame): an inner edge
// whose opposite vertex lies inside the other triangle's circumcircle is flipped when both new
// triangles are `good`. Ear clipping leaves long thin ears; Delaunay maximises the smallest angle,
// so what stays thin is only what the rim itself forces. A bounded number of passes; in a pass a
// triangle flips at most once, and an edge next to a triangle flipped in that pass waits for the
// next pass (the order and the result of the per-pass edge table this replaced). Both triangles
// of every flip are `good`: their slots in `known` are set to kKnownGood.
template <class Good>
void delaunay_flips(const SectionPlan& plan, std::vector<Triangle>& tris, CapAdjacency& adj,
                    const Good& good, std::vector<char>& known) {
    // A pass looks only at the triangles flipped in the pass before and their neighbours: every
    // other triangle had each of its edges tested in that pass against the same two triangles
    // (an edge it skipped for a flipped neighbour has that neighbour now), so it cannot flip.
    const auto n = static_cast<std::uint32_t>(tris.size());  // flips keep the triangles' count
    std::vector<char> touched, active(n, 1);
    for (int pass = 0; pass < 8; ++pass) {
        touched.assign(n, 0);
        bool flipped = false;
        // Corner (k + 2) % 3, the one before corner k: slot 3t + k ends there.
        static constexpr int kBefore[3] = {2, 0, 1};
        // The arrays through plain pointers: a byte store (touched, known) may alias a vector's
        // own members, so reading through the vectors reloads their data at every use.
        const PlanPoint* const points = plan.points.data();
        const Triangle* const tri = tris.data();           // flip() writes it
        const std::uint32_t* const nb = adj.across_all();  // and this
        char* const touch = touched.data();
        const char* const act = active.data();
        for (std::uint32_t i = 0; i < n; ++i) {
            if (!act[i] || touch[i]) continue;
            // Triangle i read as (a, b, c): flips its edge c -> a, slot 3i + e, with the neighbour
            // holding a -> c (apex d) when d is clearly inside the circumcircle and both new
            // triangles are good. Whether it flipped. Inlined at its three calls (as a loop over
            // the three readings, its table lookups were a third of the pass).
            auto try_flip = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t e)
                __attribute__((always_inline)) {
                const std::uint32_t si = 3 * i + e;
                const std::uint32_t sj = nb[si];
                if (sj == kNoCapNeighbour) return false;
                const std::uint32_t j = sj / 3;
                // j before i in this pass, untouched: its turn tested this same quad from its
                // side (i was untouched then too) and did not flip it.
                if (touch[j] || j == i || (j < i && act[j])) return false;
                const std::uint32_t fj = sj - 3 * j;  // the slot's corner in triangle j
                const std::uint32_t d = CapAdjacency::corner(tri[j], kBefore[fj]);
                const Vec2 &pa = points[a].uv, &pb = points[b].uv, &pc = points[c].uv,
                           &pd = points[d].uv;
                const double det = in_circle(pa, pb, pc, pd);
                const double scale = sqrnorm(sub(pa, pd)) * sqrnorm(sub(pb, pd));
                if (!(det > 1e-9 * scale)) return false;  // not clearly inside the circumcircle
                if (!good(Triangle{a, b, d}) || !good(Triangle{b, c, d})) return false;
                adj.flip(si, sj);
                touch[i] = touch[j] = 1;
                known[i] = known[j] = kKnownGood;
                return true;
            };
            // Read from corners a, b, c in turn; a flip changes triangle i and ends its turn.
            const Triangle ti = tri[i];
            if (try_flip(ti.a, ti.b, ti.c, 2) || try_flip(ti.b, ti.c, ti.a, 0) ||
                try_flip(ti.c, ti.a, ti.b, 1))
                flipped = true;
        }
        if (!flipped) return;
        std::fill(active.begin(), active.end(), 0);
        for (std::uint32_t i = 0; i < n; ++i) {
            if (!touch[i]) continue;
            active[i] = 1;
            for (std::uint32_t e = 0; e < 3; ++e)
                if (const std::uint32_t o = nb[3 * i + e]; o != kNoCapNeighbour) active[o / 3] = 1;
        }
    }
}

bool triangulate_group(ContextState& s, const Plane& plane,
                       const std::vector<const PlanLoop*>& loops, std::vector<char>& forced,
                       std::vector<Triangle>& out) {
    if (try_strip(s, loops, out)) return true;
    for (int attempt = 0; attempt < 4; ++attempt) {
        const GroupResult r = try_triangulate_group(s, plane, loops, forced, out);
        if (r != GroupResult::kRetry) return r == GroupResult::kOk;
    }
    return false;
}

// A cap edge between two on-plane vertices that are not neighbours on their loop, where the mesh
// already has an edge: the surface touches the plane along that edge from one side (e.g. a plane
// through two vertices of a torus's inner ring), so the cross-section pinches along it and the
// side that keeps the edge would have it three times (its two faces and the cap): refused like
// a pinch at a vertex. O(cap triangles x valence).
bool pinched_along_an_edge(const ContextState& s) {
    const SectionPlan& plan = s.plan;
    // Only a cap edge between two on-plane vertices can be one (none in most cuts).
    const auto on_plane = std::count_if(plan.points.begin(), plan.points.end(),
                                        [](const PlanPoint& p) { return !p.key.edge; });
    if (on_plane < 2) return false;
    std::vector<std::uint32_t> next(plan.points.size(), 0);
    for (const PlanLoop& l : plan.loops)
        for (std::uint32_t i = 0; i < l.count; ++i) next[l.first + i] = l.first + (i + 1) % l.count;
    auto existing_chord = [&](std::uint32_t p, std::uint32_t q) {
        const PlanPoint& a = plan.points[p];
        const PlanPoint& b = plan.points[q];
        if (a.key.edge || b.key.edge || next[p] == q || next[q] == p) return false;
        return s.mesh.find_halfedge(mesh::VertexHandle(a.key.id), mesh::VertexHandle(b.key.id))
            .is_valid();
    };
    for (const Triangle& t : plan.cap_triangles)
        if (existing_chord(t.a, t.b) || existing_chord(t.b, t.c) || existing_chord(t.c, t.a))
            return true;
    return false;
}

}  // namespace

CutStatus plan_caps(ContextState& s, const Plane& plane) {
    const Vec3& normal = plane.normal();
    SectionPlan& plan = s.plan;
    plan.cap_triangles.clear();
    s.cap_strip_neighbours.clear();
    const std::vector<std::int32_t> parent = cap_groups(plan);
    std::vector<const PlanLoop*> group;
    std::vector<char> forced(plan.points.size(), 0);
    for (std::size_t g = 0; g < plan.loops.size(); ++g) {
        const PlanLoop& outer = plan.loops[g];
        if (!outer.selected) continue;
        if (parent[g] == -2) return CutStatus::kCapTriangulationFailed;
        if (outer.area_m2 < 0) continue;
        group.clear();
        for (std::size_t i = 0; i < plan.loops.size(); ++i)
            if (i == g || parent[i] == static_cast<std::int32_t>(g))
                group.push_back(&plan.loops[i]);
        if (!triangulate_group(s, plane, group, forced, plan.cap_triangles))
            return CutStatus::kCapTriangulationFailed;
    }
    // Every cap triangle must have a real area and face the way its 2-D orientation says (rim
    // vertices may sit off the plane: up to tol, or kSnapTolerances tol when snapped, so a long
    // thin triangle can tilt over). A `good` triangle is tilted less than 60 degrees; a bad one is
    // flipped with a neighbour when both new triangles are good. Where no flip helps, a triangle
    // still facing the right way with a margin (`acceptable`: its projection at least
    // kMinCapCosine of its area, so no rounding turns it over) is kept: a rim edge between a
    // snapped vertex and a cut point near it in the plane is steep, and every triangle on it
    // tilts with it. Anything else is refused.
    auto facing = [&](const Triangle& t, double cosine) {
        const Vec3& a = plan.points[t.a].position;
        const Vec3& b = plan.points[t.b].position;
        const Vec3& c = plan.points[t.c].position;
        const Vec3 ab = sub(b, a), ac = sub(c, a);
        const Vec3 n = cross(ab, ac);
        const double n2 = sqrnorm(n);
        return !s.too_small(a, b, c, n2, sqrnorm(ab), sqrnorm(ac)) &&
               dot(n, normal) > cosine * std::sqrt(n2);
    };
    auto good = [&](const Triangle& t) { return facing(t, 0.5); };
    auto acceptable = [&](const Triangle& t) { return facing(t, kMinCapCosine); };
    auto len2 = [&](std::uint32_t a, std::uint32_t b) {
        return sqrdist(plan.points[a].position, plan.points[b].position);
    };
    std::vector<Triangle>& tris = plan.cap_triangles;
    CapAdjacency adj(tris, plan.cap_neighbours, s.cap_plan);
    if (s.cap_strip_neighbours.size() == 3 * tris.size()) {  // every group a strip: linked
        plan.cap_neighbours.assign(s.cap_strip_neighbours.begin(), s.cap_strip_neighbours.end());
        KERF_ASSERT(links_as_built(s, tris), "a strip's links are those CapAdjacency::build makes");
    } else if (!adj.build(plan.points.size())) {
        return CutStatus::kCapTriangulationFailed;
    }
    std::vector<char> known(tris.size(), kUnknown);
    delaunay_flips(plan, tris, adj, good, known);
    // A needle no one flip mends: three points of a near-straight run of the rim (where the
    // plane crosses an earlier cap along the line the two planes meet, cut points lie on that
    // line to a fraction of tol), its neighbour across the inner edge holding a fourth point of
    // the run, so both triangles of any flip keep three points of the run. Flipping that
    // neighbour's other edge first (two good triangles) brings in an apex off the run; the
    // needle's flip then makes two good (or acceptable) triangles. Both flips are worked out
    // before either is made. Reached only where the cut would otherwise be refused.
    auto two_flips = [&](std::size_t i) {
        const Triangle ti = tris[i];
        for (int e = 0; e < 3; ++e) {
            const auto si = static_cast<std::uint32_t>(3 * i + e);
            const std::uint32_t sj = adj.across(si);
            if (sj == kNoCapNeighbour) continue;
            const std::uint32_t u = CapAdjacency::corner(ti, e),
                                v = CapAdjacency::corner(ti, (e + 1) % 3);
            const std::uint32_t j = sj / 3;
            for (int g = 1; g < 3; ++g) {
                const int fk = (static_cast<int>(sj % 3) + g) % 3;
                const auto sk = static_cast<std::uint32_t>(3 * j + fk);
                const std::uint32_t sl = adj.across(sk);
                if (sl == kNoCapNeighbour || sl / 3 == i || sl / 3 == j) continue;
                const std::uint32_t dl = CapAdjacency::corner(tris[sl / 3], (sl % 3 + 2) % 3);
                const auto [j1, j2] = CapAdjacency::flipped(tris[j], fk, dl);
                if (!good(j1) || !good(j2)) continue;
                std::uint32_t d = CapAdjacency::apex_of(j1, v, u);
                if (d == CapAdjacency::kNoCorner) d = CapAdjacency::apex_of(j2, v, u);
                if (d == CapAdjacency::kNoCorner) continue;
                const auto [i1, i2] = CapAdjacency::flipped(ti, e, d);
                const char grade = good(i1) && good(i2)               ? kKnownGood
                                   : acceptable(i1) && acceptable(i2) ? kKnownAcceptable
                                                                      : kUnknown;
                if (grade == kUnknown) continue;
                adj.flip(sk, sl);
                KERF_ASSERT(adj.across(si) != kNoCapNeighbour &&
                                CapAdjacency::apex_of(tris[adj.across(si) / 3], v, u) == d,
                            "the first flip put the planned apex across the needle");
                const std::uint32_t sm = adj.across(si);
                known[j] = known[sl / 3] = kKnownGood;
                adj.flip(si, sm);
                known[i] = known[sm / 3] = grade;
                return true;
            }
        }
        return false;
    };
    // Tries the flip across the longest edge first, then the other two; good triangles first,
    // then acceptable ones.
    bool failed = false;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        if (known[i] == kKnownGood) continue;
        if (good(tris[i])) {
            known[i] = kKnownGood;
            continue;
        }
        bool fixed = false;
        for (int tier = 0; tier < 2 && !fixed; ++tier) {
            if (tier == 1 && acceptable(tris[i])) {
                known[i] = kKnownAcceptable;
                fixed = true;
                break;
            }
            // Read from corner r, triangle i is (a, b, c) with c -> a its longest edge.
            int r = 0;
            for (Triangle t = tris[i];
                 r < 3 && len2(t.c, t.a) < std::max(len2(t.a, t.b), len2(t.b, t.c)); ++r)
                t = Triangle{t.b, t.c, t.a};
            r %= 3;
            for (int edge = 0; edge < 3 && !fixed; ++edge, r = (r + 1) % 3) {
                const Triangle& ti = tris[i];
                const std::uint32_t a = CapAdjacency::corner(ti, r),
                                    b = CapAdjacency::corner(ti, (r + 1) % 3),
                                    c = CapAdjacency::corner(ti, (r + 2) % 3);
                const auto si = static_cast<std::uint32_t>(3 * i + (r + 2) % 3);
                const std::uint32_t sj = adj.across(si);
                if (sj == kNoCapNeighbour) continue;
                const std::uint32_t d =
                    CapAdjacency::corner(tris[sj / 3], static_cast<int>(sj % 3 + 2) % 3);
                const Triangle n1{a, b, d}, n2{b, c, d};
                const bool ok = tier == 0 ? good(n1) && good(n2) : acceptable(n1) && acceptable(n2);
                if (!ok) continue;
                adj.flip(si, sj), fixed = true;
                known[i] = known[sj / 3] = tier == 0 ? kKnownGood : kKnownAcceptable;
            }
        }
        if (fixed || two_flips(i)) continue;
        // Cut points clustered round a vertex just beyond the tolerance: propose snapping it
        // (plan_snapped), so that the cluster becomes that one rim vertex.
        failed = true;
        for (const std::uint32_t k : {tris[i].a, tris[i].b, tris[i].c}) {
            const PlanPoint& p = plan.points[k];
            if (!p.key.edge) continue;
            const mesh::VertexHandle ends[2] = {mesh::VertexHandle(p.a), mesh::VertexHandle(p.b)};
            propose_snap(s, plane, ends);
        }
    }
    if (failed) return CutStatus::kCapTriangulationFailed;
    for (std::size_t i = 0; i < tris.size(); ++i)
        if (known[i] == kUnknown && !acceptable(tris[i])) return CutStatus::kCapTriangulationFailed;
    return pinched_along_an_edge(s) ? CutStatus::kDegenerateCrossSection : CutStatus::kOk;
}

}  // namespace kerf::cut::detail
