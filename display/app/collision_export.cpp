#include "display/app/collision_export.hpp"

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
    std::vector<std::uint32_t> local(m.n_vertices(), 0);
    for (const auto v : m.vertices()) {
        const auto b = session.body_of(v);
        if (b >= n) continue;
        const std::uint32_t at = vertex_next[b]++;
        local[static_cast<std::size_t>(v.idx())] = at - out.bodies[b].vertex_offset;
        const auto p = m.point(v);
        for (std::size_t k = 0; k < 3; ++k) out.vertices_m[3 * std::size_t{at} + k] = float(p[k]);
    }
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
