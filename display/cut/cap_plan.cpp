// The cap half of a slice plan: grouping loops into cap regions, triangulating each with the
// triangulator, and guaranteeing no sliver (see section_plan.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "display/cut/context_state.hpp"
#include "display/cut/section_plan.hpp"

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
    return std::max({(uv[t.a] - uv[t.b]).sqrnorm(), (uv[t.b] - uv[t.c]).sqrnorm(),
                     (uv[t.c] - uv[t.a]).sqrnorm()});
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
    const double along = OpenMesh::dot(b - a, c - b);
    const double ac2 = (c - a).sqrnorm();
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
    for (const PlanLoop* l : loops) {
        const std::size_t before = uv.size();
        auto pt = [&](std::uint32_t k) { return plan.points[l->first + (k % l->count)].uv; };
        std::vector<char> keep(l->count, 1);
        std::uint32_t kept = l->count;
        auto off = [&](std::uint32_t k) {
            return std::abs(plane.signed_distance(plan.points[l->first + (k % l->count)].position));
        };
        for (std::uint32_t k = 0; k < l->count; ++k) {
            const std::uint32_t prev = k + l->count - 1;
            const double off_plane = std::max({off(prev), off(k), off(k + 1)});
            if (kept > 3 && !forced[l->first + k] &&
                straight(pt(prev), pt(k), pt(k + 1), off_plane, min_cross))
                keep[k] = 0, --kept;
        }
        std::uint32_t start = 0;
        while (!keep[start]) ++start;
        for (std::uint32_t j = 0; j < l->count; ++j) {
            const std::uint32_t k = (start + j) % l->count;
            if (!keep[k]) continue;
            index.push_back(l->first + k);
            uv.push_back(pt(k));
            std::uint32_t n = 1;
            while (!keep[(k + n) % l->count]) ++n;
            if (n > 1) {
                gaps.push_back(Gap{l->first + k, l->first + (k + n) % l->count,
                                   static_cast<std::uint32_t>(removed.size()), n - 1});
                for (std::uint32_t q = 1; q < n; ++q)
                    removed.push_back(l->first + (k + q) % l->count);
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
    // Put the left-out points back: the triangle on kept edge (u, w) becomes a fan from its apex.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> by_edge;
    by_edge.reserve(3 * tris.size());
    auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; };
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
        const Triangle& t = tris[i];
        by_edge.emplace_back(key(t.a, t.b), i), by_edge.emplace_back(key(t.b, t.c), i),
            by_edge.emplace_back(key(t.c, t.a), i);
    }
    std::sort(by_edge.begin(), by_edge.end());
    auto find = [&](std::uint64_t k) {
        auto it = std::lower_bound(by_edge.begin(), by_edge.end(), std::make_pair(k, 0u));
        return it != by_edge.end() && it->first == k ? it : by_edge.end();
    };
    for (const Gap& g : gaps) {
        const auto it = find(key(g.u, g.w));
        if (it == by_edge.end()) return GroupResult::kFailed;
        const std::uint32_t ti = it->second;
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
        const auto wx = find(key(g.w, apex));
        if (wx != by_edge.end()) wx->second = static_cast<std::uint32_t>(tris.size() - 1);
    }
    out.insert(out.end(), tris.begin(), tris.end());
    return GroupResult::kOk;
}

// Lawson flips towards the Delaunay triangulation of the cap (in the plane frame): an inner edge
// whose opposite vertex lies inside the other triangle's circumcircle is flipped when both new
// triangles are `good`. Ear clipping leaves long thin ears; Delaunay maximises the smallest angle,
// so what stays thin is only what the rim itself forces. A bounded number of passes.
template <class Good>
void delaunay_flips(const SectionPlan& plan, std::vector<Triangle>& tris, const Good& good) {
    // Directed edge (u, v) -> its triangle: per u, its outgoing edges in triangle order (a CSR
    // over the point indices, O(points + triangles) per pass; a sorted list cost a third of a
    // localised cut). The first match is the lowest triangle, as a sorted list gave.
    struct Out {
        std::uint32_t to, tri;
    };
    std::vector<std::uint32_t> first;
    std::vector<Out> out;
    auto find = [&](std::uint32_t u, std::uint32_t v) {
        for (std::uint32_t k = first[u]; k < first[u + 1]; ++k)
            if (out[k].to == v) return out[k].tri;
        return ~std::uint32_t{0};
    };
    for (int pass = 0; pass < 8; ++pass) {
        first.assign(plan.points.size() + 1, 0);
        for (const Triangle& t : tris) ++first[t.a + 1], ++first[t.b + 1], ++first[t.c + 1];
        for (std::size_t k = 1; k < first.size(); ++k) first[k] += first[k - 1];
        out.resize(3 * tris.size());
        std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
        for (std::uint32_t i = 0; i < tris.size(); ++i) {
            const Triangle& t = tris[i];
            out[fill[t.a]++] = Out{t.b, i}, out[fill[t.b]++] = Out{t.c, i};
            out[fill[t.c]++] = Out{t.a, i};
        }
        std::vector<char> touched(tris.size(), 0);
        bool flipped = false;
        for (std::uint32_t i = 0; i < tris.size(); ++i) {
            for (int r = 0; r < 3 && !touched[i]; ++r) {
                Triangle t = tris[i];
                for (int k = 0; k < r; ++k) t = Triangle{t.b, t.c, t.a};
                // Edge c -> a of t; the neighbour holds a -> c with apex d.
                const std::uint32_t j = find(t.a, t.c);
                if (j == ~std::uint32_t{0} || touched[j] || j == i) continue;
                Triangle o = tris[j];
                while (o.a != t.a) o = Triangle{o.b, o.c, o.a};
                if (o.b != t.c) continue;
                const std::uint32_t d = o.c;
                const Vec2 &pa = plan.points[t.a].uv, &pb = plan.points[t.b].uv,
                           &pc = plan.points[t.c].uv, &pd = plan.points[d].uv;
                const double adx = pa[0] - pd[0], ady = pa[1] - pd[1];
                const double bdx = pb[0] - pd[0], bdy = pb[1] - pd[1];
                const double cdx = pc[0] - pd[0], cdy = pc[1] - pd[1];
                const double det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) -
                                   (bdx * bdx + bdy * bdy) * (adx * cdy - cdx * ady) +
                                   (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
                const double scale = (adx * adx + ady * ady) * (bdx * bdx + bdy * bdy);
                if (!(det > 1e-9 * scale)) continue;  // not clearly inside the circumcircle
                const Triangle n1{t.a, t.b, d}, n2{t.b, t.c, d};
                if (!good(n1) || !good(n2)) continue;
                tris[i] = n1, tris[j] = n2;
                touched[i] = touched[j] = 1;
                flipped = true;
            }
        }
        if (!flipped) return;
    }
}

bool triangulate_group(ContextState& s, const Plane& plane,
                       const std::vector<const PlanLoop*>& loops, std::vector<char>& forced,
                       std::vector<Triangle>& out) {
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
    plan.cap_points.clear();
    plan.cap_triangles.clear();
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
    // Cap triangles index plan points directly: cap_points is the identity over the plan.
    plan.cap_points.resize(plan.points.size());
    for (std::uint32_t i = 0; i < plan.cap_points.size(); ++i) plan.cap_points[i] = i;
    // Every cap triangle must have a real area and face the way its 2-D orientation says (rim
    // vertices may sit off the plane: up to tol, or kSnapTolerances tol when snapped, so a long
    // thin triangle can tilt over). A `good` triangle is tilted less than 60 degrees; a bad one is
    // flipped with a neighbour when both new triangles are good. Where no flip helps, a triangle
    // still facing the right way with a margin (`acceptable`: its projection at least
    // kMinCapCosine of its area, so no rounding turns it over) is kept: a rim edge between a
    // snapped vertex and a cut point near it in the plane is steep, and every triangle on it
    // tilts with it. Anything else is refused.
    const double min_area = kMinCapRelativeArea * s.scale_m * s.scale_m;
    auto facing = [&](const Triangle& t, double cosine) {
        const Vec3& a = plan.points[t.a].position;
        const Vec3& b = plan.points[t.b].position;
        const Vec3& c = plan.points[t.c].position;
        const Vec3 n = OpenMesh::cross(b - a, c - a);
        return 0.5 * n.norm() > min_area && OpenMesh::dot(n, normal) > cosine * n.norm();
    };
    auto good = [&](const Triangle& t) { return facing(t, 0.5); };
    auto acceptable = [&](const Triangle& t) { return facing(t, kMinCapCosine); };
    auto len2 = [&](std::uint32_t a, std::uint32_t b) {
        return (plan.points[a].position - plan.points[b].position).sqrnorm();
    };
    std::vector<Triangle>& tris = plan.cap_triangles;
    delaunay_flips(plan, tris, good);
    // Tries the flip across the longest edge first, then the other two; good triangles first,
    // then acceptable ones.
    bool failed = false;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        if (good(tris[i])) continue;
        bool fixed = false;
        for (int tier = 0; tier < 2 && !fixed; ++tier) {
            if (tier == 1 && acceptable(tris[i])) {
                fixed = true;
                break;
            }
            Triangle t = tris[i];
            for (int r = 0; r < 3 && len2(t.c, t.a) < std::max(len2(t.a, t.b), len2(t.b, t.c)); ++r)
                t = Triangle{t.b, t.c, t.a};
            for (int edge = 0; edge < 3 && !fixed; ++edge, t = Triangle{t.b, t.c, t.a}) {
                for (std::size_t k = 0; k < tris.size() && !fixed; ++k) {
                    const std::uint32_t v[3] = {tris[k].a, tris[k].b, tris[k].c};
                    for (int e = 0; e < 3 && !fixed; ++e) {
                        if (v[e] != t.a || v[(e + 1) % 3] != t.c) continue;
                        const std::uint32_t d = v[(e + 2) % 3];
                        const Triangle n1{t.a, t.b, d}, n2{t.b, t.c, d};
                        const bool ok =
                            tier == 0 ? good(n1) && good(n2) : acceptable(n1) && acceptable(n2);
                        if (ok) tris[i] = n1, tris[k] = n2, fixed = true;
                    }
                }
            }
        }
        if (fixed) continue;
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
    for (const Triangle& t : tris)
        if (!acceptable(t)) return CutStatus::kCapTriangulationFailed;
    return pinched_along_an_edge(s) ? CutStatus::kDegenerateCrossSection : CutStatus::kOk;
}

}  // namespace kerf::cut::detail
