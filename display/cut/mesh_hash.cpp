#include "display/cut/mesh_hash.hpp"

#include <bit>
#include <cstdio>
#include <vector>

namespace kerf::cut {
namespace {

/// A streaming 64-bit hasher in the style of xxHash64's round: each word is multiplied, rotated and
/// folded into the state with fixed primes; the finish step avalanches the bits.
class WordHasher {
public:
    void add(std::uint64_t word) noexcept {
        state_ ^= round(word);
        state_ = std::rotl(state_, 27) * kPrime1 + kPrime4;
        ++words_;
    }
    void add(double d) noexcept { add(std::bit_cast<std::uint64_t>(d)); }
    void add(float f) noexcept { add(std::uint64_t{std::bit_cast<std::uint32_t>(f)}); }

    std::uint64_t finish() const noexcept {
        std::uint64_t h = state_ ^ (words_ * kPrime5);
        h ^= h >> 33;
        h *= kPrime2;
        h ^= h >> 29;
        h *= kPrime3;
        h ^= h >> 32;
        return h;
    }

private:
    static constexpr std::uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
    static constexpr std::uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
    static constexpr std::uint64_t kPrime3 = 0x165667B19E3779F9ull;
    static constexpr std::uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
    static constexpr std::uint64_t kPrime5 = 0x27D4EB2F165667C5ull;

    static std::uint64_t round(std::uint64_t word) noexcept {
        return std::rotl(word * kPrime2, 31) * kPrime1;
    }

    std::uint64_t state_ = kPrime5;
    std::uint64_t words_ = 0;
};

void hash_vertex(const mesh::TriMesh& m, mesh::VertexHandle v, WordHasher& h) {
    const auto& p = m.point(v);
    h.add(p[0]);
    h.add(p[1]);
    h.add(p[2]);
    if (m.has_vertex_normals()) {
        const auto& n = m.normal(v);
        h.add(n[0]);
        h.add(n[1]);
        h.add(n[2]);
    }
    if (m.has_vertex_texcoords2D()) {
        const auto& t = m.texcoord2D(v);
        h.add(t[0]);
        h.add(t[1]);
    }
    if (m.has_vertex_colors()) {
        const auto& c = m.color(v);
        h.add(c[0]);
        h.add(c[1]);
        h.add(c[2]);
    }
    h.add(std::uint64_t{static_cast<std::uint8_t>(m.data(v).material())});
}

bool is_deleted(const mesh::TriMesh& m, mesh::VertexHandle v) {
    return m.has_vertex_status() && m.status(v).deleted();
}

bool is_deleted(const mesh::TriMesh& m, mesh::FaceHandle f) {
    return m.has_face_status() && m.status(f).deleted();
}

}  // namespace

std::uint64_t mesh_hash(const mesh::TriMesh& m) {
    constexpr std::uint32_t kGone = 0xFFFFFFFFu;
    std::vector<std::uint32_t> dense(m.n_vertices(), kGone);
    WordHasher h;
    std::uint32_t live_vertices = 0;
    for (std::size_t i = 0; i < m.n_vertices(); ++i) {
        const mesh::VertexHandle v(static_cast<int>(i));
        if (is_deleted(m, v)) continue;
        dense[i] = live_vertices++;
        hash_vertex(m, v, h);
    }
    std::uint64_t live_faces = 0;
    for (std::size_t i = 0; i < m.n_faces(); ++i) {
        const mesh::FaceHandle f(static_cast<int>(i));
        if (is_deleted(m, f)) continue;
        // The corners as fv_range() gives them (from the face's half-edge, following next, until
        // back at it; none without a half-edge), straight from the half-edge arrays.
        std::uint32_t ids[3] = {kGone, kGone, kGone};
        int k = 0;
        const mesh::HalfedgeHandle first_halfedge = m.halfedge_handle(f);
        for (mesh::HalfedgeHandle he = first_halfedge; he.is_valid();) {
            if (k < 3) ids[k] = dense[static_cast<std::size_t>(m.to_vertex_handle(he).idx())];
            ++k;
            he = m.next_halfedge_handle(he);
            if (he == first_halfedge) break;
        }
        int first = 0;  // rotate so the lowest number leads; the winding stays
        for (int j = 1; j < 3; ++j) first = ids[j] < ids[first] ? j : first;
        h.add((std::uint64_t{ids[first]} << 32) | ids[(first + 1) % 3]);
        h.add((std::uint64_t{ids[(first + 2) % 3]} << 32) | static_cast<std::uint32_t>(k));
        ++live_faces;
    }
    h.add((std::uint64_t{live_vertices} << 32) ^ live_faces);
    return h.finish();
}

std::string mesh_hash_hex(const mesh::TriMesh& m) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(mesh_hash(m)));
    return text;
}

}  // namespace kerf::cut
