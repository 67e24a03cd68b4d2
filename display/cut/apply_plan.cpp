#include "display/cut/apply_plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "display/cut/context_state.hpp"

namespace kerf::cut::detail {

namespace {

using mesh::EdgeHandle;
using mesh::FaceHandle;
using mesh::HalfedgeHandle;
using mesh::TriMesh;
using mesh::VertexHandle;

// The vertex for an edge cut point: every attribute interpolated with the plan's t, from the
// lower-index endpoint a towards b; the material is the nearer endpoint's.
VertexHandle make_edge_vertex(TriMesh& m, const PlanPoint& p) {
    const VertexHandle a(p.a), b(p.b);
    const double t = p.t;
    const VertexHandle v = m.add_vertex(p.position);
    OpenMesh::Vec3d n = m.normal(a) + (m.normal(b) - m.normal(a)) * t;
    const double len = n.norm();
    m.set_normal(v, len > 0 ? n / len : m.normal(a));
    const auto ta = m.texcoord2D(a), tb = m.texcoord2D(b);
    m.set_texcoord2D(v, TriMesh::TexCoord2D(static_cast<float>(ta[0] + (tb[0] - ta[0]) * t),
                                            static_cast<float>(ta[1] + (tb[1] - ta[1]) * t)));
    const auto ca = m.color(a), cb = m.color(b);
    TriMesh::Color c;
    for (int i = 0; i < 3; ++i) c[i] = static_cast<float>(ca[i] + (cb[i] - ca[i]) * t);
    m.set_color(v, c);
    m.data(v).set_material(t <= 0.5 ? m.data(a).material() : m.data(b).material());
    return v;
}

VertexHandle duplicate_vertex(TriMesh& m, VertexHandle v) {
    const TriMesh::Point p = m.point(v);  // copy: add_vertex may reallocate the point array
    const VertexHandle d = m.add_vertex(p);
    m.set_normal(d, m.normal(v));
    m.set_texcoord2D(d, m.texcoord2D(v));
    m.set_color(d, m.color(v));
    m.data(d).set_material(m.data(v).material());
    return d;
}

// Gives the negative-side face of rim halfedge o (r[i+1] -> r[i]) its own edge x between the
// duplicates, leaving o as a boundary halfedge of the positive side.
HalfedgeHandle detach(TriMesh& m, HalfedgeHandle o, VertexHandle from_dup, VertexHandle to_dup) {
    const FaceHandle f = m.face_handle(o);
    const HalfedgeHandle p = m.prev_halfedge_handle(o);
    const HalfedgeHandle n = m.next_halfedge_handle(o);
    const HalfedgeHandle x = m.new_edge(from_dup, to_dup);
    m.set_next_halfedge_handle(p, x);
    m.set_next_halfedge_handle(x, n);
    m.set_face_handle(x, f);
    if (m.halfedge_handle(f) == o) m.set_halfedge_handle(f, x);
    m.set_face_handle(o, FaceHandle());
    return x;
}

// Cuts one loop apart: rim vertices r (positive side keeps them) and their duplicates d.
using RimEdges = std::vector<std::pair<std::uint64_t, HalfedgeHandle>>;

std::uint64_t edge_key(VertexHandle a, VertexHandle b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a.idx())) << 32) |
           static_cast<std::uint32_t>(b.idx());
}

bool separate_loop(TriMesh& m, const std::vector<VertexHandle>& r,
                   const std::vector<VertexHandle>& d, RimEdges& pos_rim, RimEdges& neg_rim) {
    const std::size_t n = r.size();
    std::vector<HalfedgeHandle> h(n), x(n);
    for (std::size_t i = 0; i < n; ++i) {
        h[i] = m.find_halfedge(r[i], r[(i + 1) % n]);
        if (!h[i].is_valid() || m.is_boundary(h[i]) ||
            m.is_boundary(m.opposite_halfedge_handle(h[i])))
            return false;
    }
    for (std::size_t i = 0; i < n; ++i)
        x[i] = detach(m, m.opposite_halfedge_handle(h[i]), d[(i + 1) % n], d[i]);
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
        pos_rim.emplace_back(edge_key(r[(i + 1) % n], r[i]), o);
        neg_rim.emplace_back(edge_key(d[i], d[(i + 1) % n]), y);
    }
    return true;
}

// Closes the rim loops of one side with the cap triangles `tris` (vertex triples, wound to face
// out of that side). Built directly on the halfedge arrays: every triangle edge is either a rim
// boundary halfedge or an inner edge shared by two cap triangles, so no search around vertices
// (OpenMesh's add_face would scan a fan vertex's whole one-ring for every triangle).
bool add_cap(TriMesh& m, const std::vector<std::array<VertexHandle, 3>>& tris, RimEdges& rim,
             std::vector<FaceHandle>& faces) {
    // Keys are unique (one rim halfedge per directed edge): order and search by key alone.
    const auto by_key = [](const RimEdges::value_type& a, const RimEdges::value_type& b) {
        return a.first < b.first;
    };
    std::sort(rim.begin(), rim.end(), by_key);
    const std::size_t n = tris.size();
    std::vector<HalfedgeHandle> he(3 * n);
    struct Inner {
        std::uint64_t undirected;
        std::uint32_t slot;
        bool operator<(const Inner& o) const {
            return undirected < o.undirected || (undirected == o.undirected && slot < o.slot);
        }
    };
    std::vector<Inner> inner;
    std::size_t rim_used = 0;
    for (std::size_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
            const VertexHandle u = tris[t][k], v = tris[t][(k + 1) % 3];
            const auto it = std::lower_bound(
                rim.begin(), rim.end(), std::make_pair(edge_key(u, v), HalfedgeHandle()), by_key);
            if (it != rim.end() && it->first == edge_key(u, v)) {
                if (!m.is_boundary(it->second)) return false;  // used twice
                he[3 * t + k] = it->second;
                ++rim_used;
                continue;
            }
            inner.push_back(Inner{u.idx() < v.idx() ? edge_key(u, v) : edge_key(v, u),
                                  static_cast<std::uint32_t>(3 * t + k)});
        }
    std::sort(inner.begin(), inner.end());
    if (inner.size() % 2 != 0 || rim_used != rim.size()) return false;  // every rim edge once
    for (std::size_t i = 0; i < inner.size(); i += 2) {
        if (inner[i].undirected != inner[i + 1].undirected) return false;
        const std::uint32_t a = inner[i].slot, b = inner[i + 1].slot;
        const VertexHandle u = tris[a / 3][a % 3], v = tris[a / 3][(a % 3 + 1) % 3];
        if (tris[b / 3][b % 3] != v) return false;  // the two uses must run opposite ways
        he[a] = m.new_edge(u, v);
        he[b] = m.opposite_halfedge_handle(he[a]);
    }
    for (std::size_t t = 0; t < n; ++t) {
        const FaceHandle f = m.new_face();
        m.set_halfedge_handle(f, he[3 * t]);
        for (int k = 0; k < 3; ++k) {
            m.set_face_handle(he[3 * t + k], f);
            m.set_next_halfedge_handle(he[3 * t + k], he[3 * t + (k + 1) % 3]);
            m.set_halfedge_handle(tris[t][k], he[3 * t + k]);
        }
        faces.push_back(f);
    }
    return true;
}

}  // namespace

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
    std::vector<VertexHandle> rim(plan.points.size());
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const PlanPoint& p = plan.points[i];
            if (!p.key.edge) {
                rim[i] = VertexHandle(p.key.id);
                continue;
            }
            rim[i] = make_edge_vertex(m, p);
            m.split_copy(EdgeHandle(p.key.id), rim[i]);
        }
    }
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
    std::vector<VertexHandle> dup(plan.points.size());
    RimEdges pos_rim, neg_rim;
    for (const PlanLoop& l : plan.loops) {
        if (!l.selected) continue;
        std::vector<VertexHandle> r(rim.begin() + l.first, rim.begin() + l.first + l.count);
        std::vector<VertexHandle> d(l.count);
        for (std::uint32_t i = 0; i < l.count; ++i)
            d[i] = dup[l.first + i] = duplicate_vertex(m, r[i]);
        if (!separate_loop(m, r, d, pos_rim, neg_rim)) return CutStatus::kInternalError;
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
            s.grid.insert(m, f);
    }
    // Caps: positive side faces -normal (reversed triangles), negative side +normal.
    std::vector<std::array<VertexHandle, 3>> pos_tris, neg_tris;
    pos_tris.reserve(plan.cap_triangles.size());
    neg_tris.reserve(plan.cap_triangles.size());
    for (const Triangle& t : plan.cap_triangles) {
        const std::uint32_t a = plan.cap_points[t.a], b = plan.cap_points[t.b],
                            c = plan.cap_points[t.c];
        pos_tris.push_back({rim[a], rim[c], rim[b]});
        neg_tris.push_back({dup[a], dup[b], dup[c]});
    }
    if (!add_cap(m, pos_tris, pos_rim, out.positive.cap_faces) ||
        !add_cap(m, neg_tris, neg_rim, out.negative.cap_faces))
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
