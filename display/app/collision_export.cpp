#include "display/app/collision_export.hpp"

#include <map>
#include <vector>

#include "display/cut/cross_section.hpp"

namespace kerf::display {
namespace {

ipc::TriangleMaterial material_of(const mesh::TriMesh& m, mesh::FaceHandle f,
                                  const OpenMesh::FPropHandleT<std::uint8_t>* cap) {
    if (cap && m.property(*cap, f) != cut::kCapNone) return ipc::TriangleMaterial::kCutSurface;
    for (const auto v : m.fv_range(f)) {
        if (m.data(v).material() != mesh::Material::kCancellous)
            return ipc::TriangleMaterial::kCortical;
    }
    return ipc::TriangleMaterial::kCancellous;
}

/// Union-find root of `x` in `parent` (path halving).
std::uint32_t root(std::map<std::uint32_t, std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

/// Closes the withdrawn and aborted cuts (see the header): every vertex of a cap face within
/// half a kerf (and a margin) of such a cut's plane and inside the box of its rim goes onto the
/// plane (a later cut that crossed the opened caps left its own rim points there, off the plane),
/// then both copies of each rim point (the session's withdrawn_rim_pairs(), chained where a rim
/// vertex of one cut is a rim vertex of another) go to their mean, written as one float triple,
/// so the two caps coincide and the sides meet edge to edge. Pairs whose copies ended in
/// different bodies (a piece partial cuts severed together) stay apart. `at_out` is each vertex's
/// index in `out`. O(F + cap vertices x withdrawn cuts + pairs).
void close_withdrawn(const cut::CutSession& session, const std::vector<std::uint32_t>& at_out,
                     ipc::CollisionMesh& out) {
    const auto cuts = session.withdrawn_cuts();
    const auto pairs = session.withdrawn_rim_pairs();
    if (cuts.empty()) return;
    const mesh::TriMesh& m = session.mesh();
    const std::size_t n = session.bodies().size();
    const auto usable = [&](mesh::VertexHandle v) {
        return v.is_valid() && static_cast<std::size_t>(v.idx()) < m.n_vertices() &&
               !m.status(v).deleted() && session.body_of(v) < n;
    };
    // Positions as exported, in double (every vertex a cap face uses).
    std::map<std::uint32_t, mesh::Point> moved;
    OpenMesh::FPropHandleT<std::uint8_t> cap;
    if (m.get_property_handle(cap, cut::kCapFaceProperty)) {
        for (const auto f : m.faces()) {
            if (m.property(cap, f) == cut::kCapNone || session.body_of(f) >= n) continue;
            for (const auto v : m.fv_range(f))
                moved.try_emplace(std::uint32_t(v.idx()), m.point(v));
        }
    }
    for (const cut::WithdrawnCut& c : cuts) {
        mesh::Point lo(1e30, 1e30, 1e30), hi(-1e30, -1e30, -1e30);
        for (std::size_t k = c.first_pair; k < c.first_pair + c.pair_count; ++k) {
            for (const auto v : {pairs[k].a, pairs[k].b}) {
                if (!usable(v)) continue;
                lo.minimize(m.point(v));
                hi.maximize(m.point(v));
            }
        }
        const double band = 0.5 * c.kerf_m + 1e-6;
        const mesh::Point grow(band, band, band);
        lo -= grow;
        hi += grow;
        const mesh::Point normal = c.plane.normal();
        for (auto& [v, p] : moved) {
            const double d = c.plane.signed_distance(p);
            if (std::abs(d) > band) continue;
            bool inside = true;
            for (int k = 0; k < 3; ++k) inside = inside && p[k] >= lo[k] && p[k] <= hi[k];
            if (inside) p -= normal * d;
        }
    }
    // Rim pairs: one position per chain of copies.
    std::map<std::uint32_t, std::uint32_t> parent;
    for (const cut::Glue& g : pairs) {
        if (!usable(g.a) || !usable(g.b) || session.body_of(g.a) != session.body_of(g.b)) continue;
        const auto a = static_cast<std::uint32_t>(g.a.idx());
        const auto b = static_cast<std::uint32_t>(g.b.idx());
        parent.try_emplace(a, a);
        parent.try_emplace(b, b);
        parent[root(parent, a)] = root(parent, b);
    }
    const auto position = [&](std::uint32_t v) {
        const auto it = moved.find(v);
        return it != moved.end() ? it->second : m.point(mesh::VertexHandle(static_cast<int>(v)));
    };
    struct Sum {
        mesh::Point p{0, 0, 0};
        double count = 0;
    };
    std::map<std::uint32_t, Sum> mean;
    for (const auto& [v, up] : parent) {
        Sum& s = mean[root(parent, v)];
        s.p += position(v);
        s.count += 1;
    }
    for (const auto& [v, up] : parent) {
        const Sum& s = mean[root(parent, v)];
        moved[v] = s.p / s.count;
    }
    for (const auto& [v, p] : moved) {
        const std::size_t at = 3 * std::size_t{at_out[v]};
        for (std::size_t k = 0; k < 3; ++k) out.vertices_m[at + k] = float(p[k]);
    }
}

}  // namespace

std::string mailbox_misfit(std::size_t bodies, std::size_t vertices, std::size_t triangles) {
    if (bodies > ipc::kMeshMaxBodies) {
        return std::to_string(bodies) + " bodies; the mailbox holds " +
               std::to_string(ipc::kMeshMaxBodies);
    }
    if (vertices > ipc::kMeshMaxVertices || triangles > ipc::kMeshMaxTriangles) {
        return std::to_string(vertices) + " vertices, " + std::to_string(triangles) +
               " triangles; the mailbox holds " + std::to_string(ipc::kMeshMaxVertices) + " and " +
               std::to_string(ipc::kMeshMaxTriangles);
    }
    return {};
}

Status<std::string> export_collision(const cut::CutSession& session, ipc::CollisionMesh& out) {
    const mesh::TriMesh& m = session.mesh();
    const auto bodies = session.bodies();
    if (auto misfit = mailbox_misfit(bodies.size(), m.n_vertices(), m.n_faces()); !misfit.empty()) {
        return Err{std::move(misfit)};
    }
    OpenMesh::FPropHandleT<std::uint8_t> cap;
    const bool has_cap = m.get_property_handle(cap, cut::kCapFaceProperty);

    // Per body: its vertices in index order, renumbered from 0; then its faces in index order.
    // Two passes (count, then place) so the cost is O(V + F) whatever the number of bodies.
    const std::size_t n = bodies.size();
    std::vector<std::uint32_t> vertex_next(n + 1, 0), index_next(n + 1, 0);
    for (const auto v : m.vertices()) {
        if (const auto b = session.body_of(v); b < n) ++vertex_next[b + 1];
    }
    for (const auto f : m.faces()) {
        if (const auto b = session.body_of(f); b < n) index_next[b + 1] += 3;
    }
    for (std::size_t b = 0; b < n; ++b) {
        vertex_next[b + 1] += vertex_next[b];
        index_next[b + 1] += index_next[b];
        ipc::MeshBodyEntry& entry = out.bodies[b];
        entry.vertex_offset = vertex_next[b];
        entry.vertex_count = vertex_next[b + 1] - vertex_next[b];
        entry.index_offset = index_next[b];
        entry.index_count = index_next[b + 1] - index_next[b];
        const auto world = bodies[b].pose.matrix();
        std::copy(world.begin(), world.end(), entry.world_from_body);
    }
    std::vector<std::uint32_t> local(m.n_vertices(), 0), at_out(m.n_vertices(), 0);
    for (const auto v : m.vertices()) {
        const auto b = session.body_of(v);
        if (b >= n) continue;
        const std::uint32_t at = vertex_next[b]++;
        at_out[static_cast<std::size_t>(v.idx())] = at;
        local[static_cast<std::size_t>(v.idx())] = at - out.bodies[b].vertex_offset;
        const auto p = m.point(v);
        for (std::size_t k = 0; k < 3; ++k) out.vertices_m[3 * std::size_t{at} + k] = float(p[k]);
    }
    close_withdrawn(session, at_out, out);
    for (const auto f : m.faces()) {
        const auto b = session.body_of(f);
        if (b >= n) continue;
        std::uint32_t at = index_next[b];
        index_next[b] += 3;
        out.materials[at / 3] =
            static_cast<std::uint8_t>(material_of(m, f, has_cap ? &cap : nullptr));
        for (const auto v : m.fv_range(f)) out.indices[at++] = local[std::size_t(v.idx())];
    }
    const std::uint32_t vertex_at =
        n ? out.bodies[n - 1].vertex_offset + out.bodies[n - 1].vertex_count : 0;
    const std::uint32_t index_at =
        n ? out.bodies[n - 1].index_offset + out.bodies[n - 1].index_count : 0;
    out.body_count = static_cast<std::uint32_t>(bodies.size());
    out.vertex_count = vertex_at;
    out.index_count = index_at;
    return {};
}

}  // namespace kerf::display
