#include "display/mesh/indexed_mesh.hpp"

#include <algorithm>
#include <bit>
#include <utility>

#include "display/mesh/detail/halfedge_build.hpp"

namespace kerf::mesh {
namespace {

std::uint64_t coordinate_bits(double v) noexcept {
    return std::bit_cast<std::uint64_t>(v == 0.0 ? 0.0 : v);  // -0 welds with +0
}

struct WeldKey {
    std::uint64_t x, y, z;
    bool operator==(const WeldKey&) const = default;
};

WeldKey weld_key(const Point& p) noexcept {
    return {coordinate_bits(p[0]), coordinate_bits(p[1]), coordinate_bits(p[2])};
}

std::uint64_t weld_hash(const WeldKey& k) noexcept {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2)) * 0xBF58476D1CE4E5B9ull;
    h ^= (k.z + 0x94D049BB133111EBull + (h << 6) + (h >> 2)) * 0x9E3779B97F4A7C15ull;
    return h ^ (h >> 31);
}

}  // namespace

void VertexWelder::reserve(std::size_t vertices) {
    if (2 * vertices > slots_.size() && used_ == 0) slots_.assign(std::bit_ceil(2 * vertices), {});
}

void VertexWelder::rehash(std::size_t slot_count, const IndexedMesh& out) {
    std::vector<Slot> old = std::exchange(slots_, std::vector<Slot>(slot_count));
    const std::size_t mask = slot_count - 1;
    for (const Slot& s : old) {
        if (s.index_plus_one == 0) continue;
        std::size_t i = weld_hash(weld_key(out.positions_m[s.index_plus_one - 1])) & mask;
        while (slots_[i].index_plus_one != 0) i = (i + 1) & mask;
        slots_[i] = s;
    }
}

std::uint32_t VertexWelder::weld(const Point& p, IndexedMesh& out) {
    if (2 * (used_ + 1) > slots_.size()) rehash(std::max<std::size_t>(64, 2 * slots_.size()), out);
    const WeldKey key = weld_key(p);
    const std::uint64_t h = weld_hash(key);
    const auto tag = static_cast<std::uint32_t>(h >> 32);
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = h & mask;; i = (i + 1) & mask) {
        Slot& s = slots_[i];
        if (s.index_plus_one == 0) {
            const auto index = static_cast<std::uint32_t>(out.positions_m.size());
            out.positions_m.push_back(p);
            s = {index + 1, tag};
            ++used_;
            return index;
        }
        if (s.tag == tag && weld_key(out.positions_m[s.index_plus_one - 1]) == key)
            return s.index_plus_one - 1;
    }
}

namespace {

/// OpenMesh's vector types construct without writing: give a new vertex's texture coordinates and
/// colour defined values, so that mesh_hash() (which reads them) is the same in every run.
void clear_attributes(TriMesh& m, VertexHandle v) {
    m.set_texcoord2D(v, TriMesh::TexCoord2D(0.0f, 0.0f));
    m.set_color(v, TriMesh::Color(1.0f, 1.0f, 1.0f));
}

}  // namespace

BuiltMesh build_tri_mesh(const IndexedMesh& in) {
    BuiltMesh out{make_mesh(), 0};
    out.detached_triangles = build_tri_mesh_into(in, out.mesh);
    return out;
}

std::size_t edit_headroom_faces(std::size_t faces) noexcept {
    return std::max(faces / 8, std::size_t{1} << 16);
}

std::size_t build_tri_mesh_into(const IndexedMesh& in, TriMesh& m, std::size_t spare_faces) {
    // The connectivity OpenMesh's add_face would build, face by face, written straight into the
    // mesh's arrays (detail/halfedge_build.hpp).
    std::size_t detached = 0;
    const std::size_t n_in = in.positions_m.size();
    m.reserve(n_in + spare_faces / 2, in.triangles.size() * 3 / 2 + 2 * spare_faces,
              in.triangles.size() + spare_faces);
    detail::HalfedgeBuilder builder(m);
    builder.add_vertices(n_in);
    std::vector<std::uint32_t> copied_from;  // the source vertex of each detached copy
    for (const Triangle& t : in.triangles) {
        const auto a = static_cast<std::int32_t>(t[0]);
        const auto b = static_cast<std::int32_t>(t[1]);
        const auto c = static_cast<std::int32_t>(t[2]);
        const bool distinct = a != b && b != c && a != c;
        if (distinct && builder.add_face(a, b, c) >= 0) continue;
        ++detached;
        std::int32_t copies[3];
        for (std::size_t k = 0; k < 3; ++k) {
            copies[k] = builder.add_vertex();
            copied_from.push_back(t[k]);
        }
        builder.add_face(copies[0], copies[1], copies[2]);
    }
    builder.finish();
    const bool has_materials = in.materials.size() == n_in;
    const auto set_vertex = [&](std::size_t v, std::size_t src) {
        const VertexHandle vh(static_cast<int>(v));
        m.set_point(vh, in.positions_m[src]);
        clear_attributes(m, vh);
        if (has_materials) m.data(vh).set_material(in.materials[src]);
    };
    for (std::size_t v = 0; v < n_in; ++v) set_vertex(v, v);
    for (std::size_t k = 0; k < copied_from.size(); ++k) set_vertex(n_in + k, copied_from[k]);
    builder.write_normals();  // m.update_normals(), bit for bit
    return detached;
}

IndexedMesh to_indexed(const TriMesh& mesh) {
    IndexedMesh out;
    std::vector<std::uint32_t> remap(mesh.n_vertices(), 0);
    out.positions_m.reserve(mesh.n_vertices());
    out.materials.reserve(mesh.n_vertices());
    for (const VertexHandle v : mesh.vertices()) {  // skips deleted vertices
        remap[static_cast<std::size_t>(v.idx())] =
            static_cast<std::uint32_t>(out.positions_m.size());
        out.positions_m.push_back(mesh.point(v));
        out.materials.push_back(mesh.data(v).material());
    }
    out.triangles.reserve(mesh.n_faces());
    for (const FaceHandle f : mesh.faces()) {
        Triangle t{};
        std::size_t k = 0;
        for (const VertexHandle v : mesh.fv_range(f)) {
            if (k < 3) t[k] = remap[static_cast<std::size_t>(v.idx())];
            ++k;
        }
        if (k == 3) out.triangles.push_back(t);
    }
    return out;
}

}  // namespace kerf::mesh
