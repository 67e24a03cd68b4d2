#include "display/cut/apply_plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "display/cut/context_state.hpp"
#include "display/cut/vec_ops.hpp"

namespace kerf::cut::detail {

namespace {

using mesh::EdgeHandle;
using mesh::FaceHandle;
using mesh::HalfedgeHandle;
using mesh::TriMesh;
using mesh::VertexHandle;
using CapScratch = ContextState::CapScratch;

// data() of `v` with room for at least n elements; elements already there are kept, not filled.
template <class T>
T* room(std::vector<T>& v, std::size_t n) {
    if (v.size() < n) v.resize(n);
    return v.data();
}

// Writes the attributes of vertex v made for an edge cut point: every attribute interpolated
// with the plan's t, from the lower-index endpoint a towards b; the material is the nearer
// endpoint's.
void set_edge_vertex(TriMesh& m, const PlanPoint& p, VertexHandle v) {
    const VertexHandle a(p.a), b(p.b);
    const double t = p.t;
    m.set_point(v, p.position);
    const Vec3 n = lerp(m.normal(a), m.normal(b), t);
    const double len = std::sqrt(sqrnorm(n));
    m.set_normal(v, len > 0 ? Vec3(n[0] / len, n[1] / len, n[2] / len) : m.normal(a));
    const auto ta = m.texcoord2D(a), tb = m.texcoord2D(b);
    m.set_texcoord2D(v, TriMesh::TexCoord2D(static_cast<float>(ta[0] + (tb[0] - ta[0]) * t),
                                            static_cast<float>(ta[1] + (tb[1] - ta[1]) * t)));
    const TriMesh::Color &ca = m.color(a), &cb = m.color(b);
    auto channel = [&](int i) { return static_cast<float>(ca[i] + (cb[i] - ca[i]) * t); };
    m.set_color(v, TriMesh::Color(channel(0), channel(1), channel(2)));
    m.data(v).set_material(t <= 0.5 ? m.data(a).material() : m.data(b).material());
}

VertexHandle make_edge_vertex(TriMesh& m, const PlanPoint& p) {
    const VertexHandle v = m.add_vertex(p.position);
    set_edge_vertex(m, p, v);
    return v;
}

// The 2-4 split of interior edge e at the new vertex v, on the halfedge arrays, into elements
// already allocated: edges ne, ne+1, ne+2 and faces nf, nf+1. The connectivity is exactly what
// OpenMesh's TriConnectivity::split makes (same handles, same order, so meshes and hashes are
// those of split_copy); of the properties only what Kerf owns is written: the new edges take
// the old edge's status and stamp, the new faces their old face's normal, status, stamp and cap
// tag (split_copy copied every property generically, one virtual call per property).
void split_interior_edge(TriMesh& m, const ContextState& s, EdgeHandle e, VertexHandle v, int ne,
                         int nf) {
    const HalfedgeHandle h0 = m.halfedge_handle(e, 0), o0 = m.halfedge_handle(e, 1);
    const VertexHandle v2 = m.to_vertex_handle(o0);
    const HalfedgeHandle e1(2 * ne), t1(2 * ne + 1);
    const HalfedgeHandle e0(2 * ne + 2), t0(2 * ne + 3);
    const HalfedgeHandle e2(2 * ne + 4), t2(2 * ne + 5);
    const FaceHandle f0 = m.face_handle(h0), f3 = m.face_handle(o0);
    const FaceHandle f1(nf), f2(nf + 1);
    m.set_vertex_handle(e1, v2);
    m.set_vertex_handle(t1, v);
    m.set_halfedge_handle(v, h0);
    m.set_vertex_handle(o0, v);

    const HalfedgeHandle h1 = m.next_halfedge_handle(h0), h2 = m.next_halfedge_handle(h1);
    m.set_vertex_handle(e0, m.to_vertex_handle(h1));
    m.set_vertex_handle(t0, v);
    m.set_halfedge_handle(f0, h0);
    m.set_halfedge_handle(f1, h2);
    m.set_face_handle(h1, f0);
    m.set_face_handle(t0, f0);
    m.set_face_handle(h0, f0);
    m.set_face_handle(h2, f1);
    m.set_face_handle(t1, f1);
    m.set_face_handle(e0, f1);
    m.set_next_halfedge_handle(h0, h1);
    m.set_next_halfedge_handle(h1, t0);
    m.set_next_halfedge_handle(t0, h0);
    m.set_next_halfedge_handle(e0, h2);
    m.set_next_halfedge_handle(h2, t1);
    m.set_next_halfedge_handle(t1, e0);

    const HalfedgeHandle o1 = m.next_halfedge_handle(o0), o2 = m.next_halfedge_handle(o1);
    m.set_vertex_handle(e2, m.to_vertex_handle(o1));
    m.set_vertex_handle(t2, v);
    m.set_halfedge_handle(f2, o1);
    m.set_halfedge_handle(f3, o0);
    m.set_face_handle(o1, f2);
    m.set_face_handle(t2, f2);
    m.set_face_handle(e1, f2);
    m.set_face_handle(o2, f3);
    m.set_face_handle(o0, f3);
    m.set_face_handle(e2, f3);
    m.set_next_halfedge_handle(e1, o1);
    m.set_next_halfedge_handle(o1, t2);
    m.set_next_halfedge_handle(t2, e1);
    m.set_next_halfedge_handle(o0, e2);
    m.set_next_halfedge_handle(e2, o2);
    m.set_next_halfedge_handle(o2, o0);
    if (m.halfedge_handle(v2) == h0) m.set_halfedge_handle(v2, t1);

    for (int k = 0; k < 3; ++k) {
        const EdgeHandle x(ne + k);
        m.status(x) = m.status(e);
        m.property(s.e_stamp, x) = m.property(s.e_stamp, e);
    }
    for (const auto& [from, to] : {std::pair{f0, f1}, std::pair{f3, f2}}) {
        m.set_normal(to, m.normal(from));
        m.status(to) = m.status(from);
        m.property(s.f_stamp, to) = m.property(s.f_stamp, from);
        m.property(s.cap, to) = m.property(s.cap, from);
    }
}

// Splits every crossing edge of the selected loops (loop order), allocating all their elements
// in one resize: each split makes vertex nv+i, edges ne+3i..ne+3i+2 and faces nf+2i, nf+2i+1, the
// handles OpenMesh's add_vertex + split_copy made one at a time. rim[i] gets every point's vertex.
// False (before any edit) if a crossing edge has a boundary side (the walk refuses those first).
bool split_crossing_edges(ContextState& s, VertexHandle* rim) {
    TriMesh& m = s.mesh;
    const SectionPlan& plan = s.plan;
    int splits = 0;
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const PlanPoint& p = plan.points[i];
            if (!p.key.edge) continue;
            if (m.is_boundary(EdgeHandle(p.key.id))) return false;
            ++splits;
        }
    }
    const int nv = static_cast<int>(m.n_vertices()), ne = static_cast<int>(m.n_edges()),
              nf = static_cast<int>(m.n_faces());
    if (splits > 0) m.resize(nv + splits, ne + 3 * splits, nf + 2 * splits);
    int k = 0;
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const PlanPoint& p = plan.points[i];
            if (!p.key.edge) {
                rim[i] = VertexHandle(p.key.id);
                continue;
            }
            rim[i] = VertexHandle(nv + k);
            set_edge_vertex(m, p, rim[i]);
            split_interior_edge(m, s, EdgeHandle(p.key.id), rim[i], ne + 3 * k, nf + 2 * k);
            ++k;
        }
    }
    return true;
}

// OpenMesh's find_halfedge(from, to) on the halfedge arrays, inline: the outgoing halfedges of
// `from` clockwise from its own halfedge, as OpenMesh's circulator visits them.
HalfedgeHandle find_halfedge(const TriMesh& m, VertexHandle from, VertexHandle to) {
    const HalfedgeHandle start = m.halfedge_handle(from);
    if (!start.is_valid()) return start;
    HalfedgeHandle h = start;
    do {
        if (m.to_vertex_handle(h) == to) return h;
        h = m.next_halfedge_handle(m.opposite_halfedge_handle(h));
    } while (h != start);
    return HalfedgeHandle();
}

// Makes allocated vertex d a copy of v's attributes.
void duplicate_vertex(TriMesh& m, VertexHandle v, VertexHandle d) {
    m.set_point(d, m.point(v));
    m.set_normal(d, m.normal(v));
    m.set_texcoord2D(d, m.texcoord2D(v));
    m.set_color(d, m.color(v));
    m.data(d).set_material(m.data(v).material());
}

// Allocated edge e as OpenMesh's new_edge(from, to) makes it; its halfedge from -> to.
HalfedgeHandle make_edge(TriMesh& m, EdgeHandle e, VertexHandle from, VertexHandle to) {
    const HalfedgeHandle h = m.halfedge_handle(e, 0);
    m.set_vertex_handle(h, to);
    m.set_vertex_handle(m.opposite_halfedge_handle(h), from);
    return h;
}

// Gives the negative-side face of rim halfedge o (r[i+1] -> r[i]) its own (allocated) edge x
// between the duplicates, leaving o as a boundary halfedge of the positive side.
HalfedgeHandle detach(TriMesh& m, HalfedgeHandle o, EdgeHandle edge, VertexHandle from_dup,
                      VertexHandle to_dup) {
    const FaceHandle f = m.face_handle(o);
    const HalfedgeHandle p = m.prev_halfedge_handle(o);
    const HalfedgeHandle n = m.next_halfedge_handle(o);
    const HalfedgeHandle x = make_edge(m, edge, from_dup, to_dup);
    m.set_next_halfedge_handle(p, x);
    m.set_next_halfedge_handle(x, n);
    m.set_face_handle(x, f);
    if (m.halfedge_handle(f) == o) m.set_halfedge_handle(f, x);
    m.set_face_handle(o, FaceHandle());
    return x;
}

// Cuts one loop apart: rim vertices r (positive side keeps them) and their duplicates d.
// The new edges are the allocated edges next_edge, next_edge + 1, ... (advanced).
// h and x: scratch for r.size() halfedges each.
bool separate_loop(TriMesh& m, const std::vector<VertexHandle>& r,
                   const std::vector<VertexHandle>& d, int& next_edge, HalfedgeHandle* h,
                   HalfedgeHandle* x) {
    const std::size_t n = r.size();
    for (std::size_t i = 0; i < n; ++i) {
        h[i] = find_halfedge(m, r[i], r[(i + 1) % n]);
        if (!h[i].is_valid() || m.is_boundary(h[i]) ||
            m.is_boundary(m.opposite_halfedge_handle(h[i])))
            return false;
    }
    for (std::size_t i = 0; i < n; ++i)
        x[i] = detach(m, m.opposite_halfedge_handle(h[i]), EdgeHandle(next_edge++), d[(i + 1) % n],
                      d[i]);
    // Move the negative fan of every rim vertex to its duplicate: from x[i] (into r[i]) around
    // r[i] through negative faces until the rim halfedge x[i-1] leaves it.
    for (std::size_t i = 0; i < n; ++i) {
        const HalfedgeHandle stop = x[(i + n - 1) % n];
        HalfedgeHandle in = x[i];
        for (int guard = 0; guard < 100000; ++guard) {
            const HalfedgeHandle g = m.next_halfedge_handle(in);
            if (g == stop) break;
            in = m.opposite_halfedge_handle(g);
            if (m.is_boundary(in)) return false;
            m.set_vertex_handle(in, d[i]);
        }
    }
    // Boundary cycles: positive side o[i] = r[i+1] -> r[i]; negative side y[i] = d[i] -> d[i+1].
    for (std::size_t i = 0; i < n; ++i) {
        const HalfedgeHandle o = m.opposite_halfedge_handle(h[i]);
        const HalfedgeHandle o_prev = m.opposite_halfedge_handle(h[(i + n - 1) % n]);
        m.set_next_halfedge_handle(o, o_prev);
        const HalfedgeHandle y = m.opposite_halfedge_handle(x[i]);
        m.set_next_halfedge_handle(y, m.opposite_halfedge_handle(x[(i + 1) % n]));
        m.set_halfedge_handle(r[(i + 1) % n], o);
        m.set_halfedge_handle(d[i], y);
    }
    return true;
}

// What the positive side's cap (built first) leaves for the negative side's: its rim slots, its
// inner edges in their order (in CapScratch: `inner`, by the positive side's slots) and whether
// that order can be the negative side's too (no two edges with the same ranks, no inner edge
// between two slots of one triangle, its points ranked in plan order).
struct CapMirror {
    const char* on_rim = nullptr;
    std::size_t inner = 0;
    bool derivable = false;
};

// The slot of the other side's cap triangle edge that runs slot `s` the other way (one side's
// triangles are the other's with corners b and c swapped: slot 3t + k is slot 3t + (2 - k)).
std::uint32_t mirrored(std::uint32_t s) { return s - s % 3 + (2 - s % 3); }

// Checks that every edge of one side's cap triangles that is not on its rim (`on_rim`) is paired
// with the slot across it, which runs the other way and is not on the rim, and orders these inner
// edges (each by its lower slot) by the (lower, higher) rank of their vertex handles, as
// OpenMesh's new_edge in sorted order numbered them: the points are ranked by their handle
// (w.rank), then two stable counting passes (higher rank, then lower rank) over the edges in slot
// order give what a sort by (handles, slot) gave, into w.inner. False when the pairing fails;
// `derivable` (see CapMirror) is set.
bool order_cap_edges(const SectionPlan& plan, const VertexHandle* vertex, std::size_t slots,
                     const std::uint32_t* from, const std::uint32_t* to,
                     const std::uint32_t* across, const char* on_rim, CapScratch& w,
                     bool& derivable) {
    std::vector<std::uint32_t>& inner = w.inner;  // the lower slot of each inner edge
    inner.clear();
    bool one_triangle = false;  // an edge between two slots of one triangle
    for (std::uint32_t slot = 0; slot < slots; ++slot) {
        if (on_rim[slot]) continue;
        const std::uint32_t o = across[slot];
        if (o == kNoCapNeighbour || on_rim[o] || across[o] != slot) return false;
        if (from[o] != to[slot] || to[o] != from[slot]) return false;  // run opposite ways
        if (slot < o) inner.push_back(slot), one_triangle |= o / 3 == slot / 3;
    }
    std::vector<std::pair<int, std::uint32_t>>& by_handle = w.by_handle;
    by_handle.clear();
    std::vector<std::uint32_t>& rank = w.rank;
    rank.assign(plan.points.size(), kNoCapNeighbour);
    for (std::size_t slot = 0; slot < slots; ++slot) rank[from[slot]] = 0;
    for (std::uint32_t p = 0; p < plan.points.size(); ++p)
        if (rank[p] == 0) by_handle.emplace_back(vertex[p].idx(), p);
    const bool plan_order = std::is_sorted(by_handle.begin(), by_handle.end());
    if (!plan_order) std::sort(by_handle.begin(), by_handle.end());
    for (std::uint32_t r = 0; r < by_handle.size(); ++r) rank[by_handle[r].second] = r;
    std::uint32_t* const lo = room(w.lo, slots);
    std::uint32_t* const hi = room(w.hi, slots);
    for (const std::uint32_t slot : inner) {
        const std::uint32_t a = rank[from[slot]], b = rank[to[slot]];
        lo[slot] = std::min(a, b), hi[slot] = std::max(a, b);
    }
    std::uint32_t* const count = room(w.count, by_handle.size() + 1);
    std::uint32_t* edges = inner.data();
    std::uint32_t* other = room(w.sorted, inner.size());
    for (const std::uint32_t* key : {hi, lo}) {
        std::fill(count, count + by_handle.size() + 1, 0u);
        for (std::size_t i = 0; i < inner.size(); ++i) ++count[key[edges[i]] + 1];
        for (std::size_t k = 1; k <= by_handle.size(); ++k) count[k] += count[k - 1];
        for (std::size_t i = 0; i < inner.size(); ++i) other[count[key[edges[i]]]++] = edges[i];
        std::swap(edges, other);
    }
    bool tied = false;
    for (std::size_t i = 1; i < inner.size() && !tied; ++i)
        tied = lo[edges[i]] == lo[edges[i - 1]] && hi[edges[i]] == hi[edges[i - 1]];
    derivable = plan_order && !one_triangle && !tied;
    return true;  // two passes: the order is back in `inner`
}

// Closes the rim loops of one side with the plan's cap triangles on that side's vertices
// (`vertex` per plan point; `reversed`: corners b and c swapped, so the cap faces the other way).
// Built directly on the halfedge arrays: every triangle edge is either a rim boundary halfedge or
// an inner edge shared by two cap triangles, paired by the plan (SectionPlan::cap_neighbours), so
// no search around vertices (OpenMesh's add_face would scan a fan vertex's whole one-ring for
// every triangle) and no sort of the edges (they are numbered in the order of their two vertex
// handles, as OpenMesh's new_edge in sorted order gave them, by two counting passes). The positive
// side (reversed) is built first and fills `mirror`; the negative side then takes the positive
// side's pairing checks and edge order, mirrored, when its rim slots are the positive side's
// mirrored and its points rank alike (its duplicates are numbered in plan order, so whenever the
// positive side's handles rise with the plan order too: no on-plane vertex out of order).
bool add_cap(TriMesh& m, const SectionPlan& plan, const VertexHandle* vertex, bool reversed,
             std::size_t rim_edges, std::vector<FaceHandle>& faces, CapScratch& w,
             CapMirror& mirror) {
    const std::size_t n = plan.cap_triangles.size();
    const std::size_t slots = 3 * n;
    // Per slot 3t + k of this side (the edge from corner k to corner k + 1 of triangle t as built
    // here): its first and second point and the slot across it. A plan slot 3t + e is slot
    // 3t + (2 - e) here when reversed, corners (a, c, b). Scratch arrays are written before they
    // are read, so they are kept from cut to cut without filling.
    std::uint32_t* const from = room(w.from, slots);
    std::uint32_t* const to = room(w.to, slots);
    std::uint32_t* const across = room(w.across, slots);
    for (std::size_t t = 0; t < n; ++t) {
        const Triangle& tri = plan.cap_triangles[t];
        const std::uint32_t c0 = tri.a, c1 = reversed ? tri.c : tri.b,
                            c2 = reversed ? tri.b : tri.c;
        from[3 * t] = c0, from[3 * t + 1] = c1, from[3 * t + 2] = c2;
        to[3 * t] = c1, to[3 * t + 1] = c2, to[3 * t + 2] = c0;
        const std::uint32_t* const nb = &plan.cap_neighbours[3 * t];
        if (!reversed) {
            across[3 * t] = nb[0], across[3 * t + 1] = nb[1], across[3 * t + 2] = nb[2];
            continue;
        }
        for (std::uint32_t e = 0; e < 3; ++e) {
            std::uint32_t o = nb[e];
            if (o != kNoCapNeighbour) o = o - o % 3 + (2 - o % 3);
            across[3 * t + 2 - e] = o;
        }
    }
    HalfedgeHandle* const he = room(w.he, slots);
    char* const on_rim = room(w.on_rim, 2 * slots) + (reversed ? 0 : slots);
    std::size_t rim_used = 0;
    for (std::size_t slot = 0; slot < slots; ++slot) {
        // A rim edge u -> v is u's own halfedge: separate_loop made every rim vertex's halfedge
        // its outgoing boundary halfedge (rim vertices are never on a boundary of the input: the
        // walk refuses those), so no search.
        const HalfedgeHandle b = m.halfedge_handle(vertex[from[slot]]);
        const bool r =
            b.is_valid() && m.is_boundary(b) && m.to_vertex_handle(b) == vertex[to[slot]];
        on_rim[slot] = r;
        if (r) he[slot] = b, ++rim_used;
    }
    if (rim_used != rim_edges) return false;  // every rim edge once
    std::uint32_t* edges = nullptr;
    std::size_t n_inner = 0;
    // The negative side as the positive side's mirror: the same pairing (so the same checks
    // pass), the same inner edges and, ranked alike, the same order by ranks.
    bool alike = !reversed && mirror.derivable;
    for (std::size_t t = 0; t < n && alike; ++t)
        alike = on_rim[3 * t] == mirror.on_rim[3 * t + 2] &&
                on_rim[3 * t + 1] == mirror.on_rim[3 * t + 1] &&
                on_rim[3 * t + 2] == mirror.on_rim[3 * t];
    if (alike) {
        const std::vector<std::uint32_t>& rank = w.rank;  // the positive side's: points in use
        int last = -1;
        for (std::uint32_t p = 0; p < plan.points.size() && alike; ++p) {
            if (rank[p] == kNoCapNeighbour) continue;
            alike = vertex[p].idx() >= last;
            last = vertex[p].idx();
        }
    }
    if (alike) {
        n_inner = mirror.inner;
        edges = room(w.sorted, n_inner);
        for (std::size_t i = 0; i < n_inner; ++i) edges[i] = mirrored(w.inner[i]);
    } else {
        if (!order_cap_edges(plan, vertex, slots, from, to, across, on_rim, w, mirror.derivable))
            return false;
        edges = w.inner.data();
        n_inner = w.inner.size();
        mirror.on_rim = on_rim;
        mirror.inner = n_inner;
        mirror.derivable = reversed && mirror.derivable;
    }
    // Every edge and face allocated in one resize, handed out in the order OpenMesh's
    // new_edge / new_face would give them.
    const int ne = static_cast<int>(m.n_edges()), nf = static_cast<int>(m.n_faces());
    m.resize(m.n_vertices(), ne + n_inner, nf + n);
    for (std::size_t i = 0; i < n_inner; ++i) {
        const std::uint32_t a = edges[i];
        he[a] = make_edge(m, EdgeHandle(ne + static_cast<int>(i)), vertex[from[a]], vertex[to[a]]);
        he[across[a]] = m.opposite_halfedge_handle(he[a]);
    }
    for (std::size_t t = 0; t < n; ++t) {
        const FaceHandle f(nf + static_cast<int>(t));
        const HalfedgeHandle h0 = he[3 * t], h1 = he[3 * t + 1], h2 = he[3 * t + 2];
        m.set_halfedge_handle(f, h0);
        m.set_face_handle(h0, f), m.set_face_handle(h1, f), m.set_face_handle(h2, f);
        m.set_next_halfedge_handle(h0, h1);
        m.set_next_halfedge_handle(h1, h2);
        m.set_next_halfedge_handle(h2, h0);
        m.set_halfedge_handle(vertex[from[3 * t]], h0);
        m.set_halfedge_handle(vertex[from[3 * t + 1]], h1);
        m.set_halfedge_handle(vertex[from[3 * t + 2]], h2);
        faces.push_back(f);
    }
    return true;
}

}  // namespace

mesh::VertexHandle make_cut_vertex(mesh::TriMesh& m, const PlanPoint& p) {
    return make_edge_vertex(m, p);
}

CutStatus apply_plan(ContextState& s, const Plane& plane, CrossSection& out, CutStats& stats) {
    TriMesh& m = s.mesh;
    SectionPlan& plan = s.plan;
    const int faces_before = static_cast<int>(m.n_faces());
    const int vertices_before = static_cast<int>(m.n_vertices());
    // Room for everything this edit adds (splits: 1 vertex, 3 edges, 2 faces each; duplicates:
    // 1 vertex, 1 edge each; caps: 2 faces and 3 edges per triangle).
    const std::size_t n_points = plan.points.size(), n_caps = plan.cap_triangles.size();
    s.ensure_capacity(2 * n_points + plan.merged.size(),
                      4 * n_points + 3 * n_caps + 3 * plan.merged.size(),
                      2 * n_points + 2 * n_caps + 2 * plan.merged.size());
    // Per plan point, its vertex on each side (written for the selected loops' points, the only
    // ones read).
    VertexHandle* const rim = room(s.edit.rim, n_points);
    VertexHandle* const dup = room(s.edit.dup, n_points);
    if (!split_crossing_edges(s, rim)) return CutStatus::kInternalError;
    // Cut points within tol of their loop neighbour: split, then collapse into the neighbour's
    // vertex (merge_close_points checked the link condition on the unedited mesh).
    for (const MergedPoint& mp : plan.merged) {
        const VertexHandle v = make_edge_vertex(m, mp.point);
        m.split_copy(EdgeHandle(mp.point.key.id), v);
        const HalfedgeHandle h = m.find_halfedge(v, rim[mp.into]);
        if (!h.is_valid() || !m.is_collapse_ok(h)) return CutStatus::kInternalError;
        m.collapse(h);
    }
    out.clear();
    out.plane = plane;
    // One duplicate vertex and one detaching edge per rim point, allocated in one resize and
    // handed out in loop order (the handles add_vertex / new_edge would give one at a time).
    int rim_points = 0;
    for (const PlanLoop& l : plan.loops) rim_points += l.selected ? static_cast<int>(l.count) : 0;
    int next_vertex = static_cast<int>(m.n_vertices()), next_edge = static_cast<int>(m.n_edges());
    m.resize(next_vertex + rim_points, next_edge + rim_points, m.n_faces());
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            dup[i] = VertexHandle(next_vertex++);
            duplicate_vertex(m, rim[i], dup[i]);
        }
        std::vector<VertexHandle> r(rim + l.first, rim + l.first + l.count);
        std::vector<VertexHandle> d(dup + l.first, dup + l.first + l.count);
        if (!separate_loop(m, r, d, next_edge, room(s.edit.h, l.count), room(s.edit.x, l.count)))
            return CutStatus::kInternalError;
        std::vector<Vec2> uv(l.count);
        for (std::uint32_t i = 0; i < l.count; ++i) uv[i] = plan.points[l.first + i].uv;
        out.loops_2d.push_back(std::move(uv));
        out.loop_is_hole.push_back(l.area_m2 < 0 ? 1 : 0);
        out.positive.cap_vertices.insert(out.positive.cap_vertices.end(), r.begin(), r.end());
        out.negative.cap_vertices.insert(out.negative.cap_vertices.end(), d.begin(), d.end());
        out.positive.loops.push_back(std::move(r));
        out.negative.loops.push_back(std::move(d));
    }
    for (int fi = faces_before; fi < static_cast<int>(m.n_faces()); ++fi) {
        const FaceHandle f(fi);
        if (m.status(f).deleted()) continue;  // removed by a merge's collapse
        if (m.property(s.cap, f) != kCapNone)
            s.cap_faces.push_back(f);
        else
            s.tree.insert(m, f);
    }
    // Caps: positive side faces -normal (reversed triangles), negative side +normal.
    // (One rim halfedge per rim point on each side.)
    CapMirror mirror;
    const auto rim_edges = static_cast<std::size_t>(rim_points);
    if (!add_cap(m, plan, rim, true, rim_edges, out.positive.cap_faces, s.cap_edit, mirror) ||
        !add_cap(m, plan, dup, false, rim_edges, out.negative.cap_faces, s.cap_edit, mirror))
        return CutStatus::kInternalError;
    for (FaceHandle f : out.positive.cap_faces) {
        m.set_normal(f, -plane.normal());
        m.property(s.cap, f) = kCapPositive;
        s.cap_faces.push_back(f);
    }
    for (FaceHandle f : out.negative.cap_faces) {
        m.set_normal(f, plane.normal());
        m.property(s.cap, f) = kCapNegative;
        s.cap_faces.push_back(f);
    }
    for (const PlanLoop& l : plan.loops) stats.faces_split += l.selected ? l.faces : 0;
    stats.vertices_added +=
        static_cast<std::uint32_t>(static_cast<int>(m.n_vertices()) - vertices_before);
    stats.triangles_added +=
        static_cast<std::uint32_t>(static_cast<int>(m.n_faces()) - faces_before);
    stats.cap_triangles += static_cast<std::uint32_t>(2 * plan.cap_triangles.size());
    stats.loops += static_cast<std::uint32_t>(out.loops_2d.size());
    stats.vertices_merged += static_cast<std::uint32_t>(plan.merged.size());
    return CutStatus::kOk;
}

}  // namespace kerf::cut::detail
