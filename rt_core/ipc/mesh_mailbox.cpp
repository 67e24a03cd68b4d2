#include "rt_core/ipc/mesh_mailbox.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstring>

namespace kerf::ipc {
namespace {

constexpr std::size_t words_for(std::size_t bytes) { return (bytes + 7) / 8; }

// Word-wise atomic copies: the other side may be writing concurrently (the buffer's sequence tells
// afterwards whether the copy is usable), so plain memcpy would be a data race. Release stores /
// acquire loads order the words against the sequence without standalone fences (see seqlock.hpp).
void load_words(void* dst, const void* src, std::size_t bytes) noexcept {
    auto* d = static_cast<std::uint64_t*>(dst);
    const auto* s = static_cast<const std::uint64_t*>(src);
    for (std::size_t i = 0, n = words_for(bytes); i < n; ++i)
        d[i] = __atomic_load_n(&s[i], __ATOMIC_ACQUIRE);
}

void store_words(void* dst, const void* src, std::size_t bytes) noexcept {
    auto* d = static_cast<std::uint64_t*>(dst);
    const auto* s = static_cast<const std::uint64_t*>(src);
    for (std::size_t i = 0, n = words_for(bytes); i < n; ++i)
        __atomic_store_n(&d[i], s[i], __ATOMIC_RELEASE);
}

bool rigid(const float* m) {
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(m[i])) return false;
    }
    if (m[3] != 0.f || m[7] != 0.f || m[11] != 0.f || m[15] != 1.f) return false;
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            const double dot = double(m[4 * a]) * m[4 * b] + double(m[4 * a + 1]) * m[4 * b + 1] +
                               double(m[4 * a + 2]) * m[4 * b + 2];
            if (std::fabs(dot - (a == b ? 1.0 : 0.0)) > 1e-3) return false;
        }
    }
    return std::fabs(m[12]) <= kMeshMaxCoordinate_m && std::fabs(m[13]) <= kMeshMaxCoordinate_m &&
           std::fabs(m[14]) <= kMeshMaxCoordinate_m;
}

MeshFault validate_body(const CollisionMesh& mesh, std::uint32_t b, std::string& where) {
    const MeshBodyEntry& e = mesh.bodies[b];
    where = "body " + std::to_string(b);
    if (std::uint64_t(e.vertex_offset) + e.vertex_count > mesh.vertex_count ||
        std::uint64_t(e.index_offset) + e.index_count > mesh.index_count ||
        e.index_count % 3 != 0 || e.index_offset % 3 != 0 || e.vertex_count == 0) {
        where += ": vertex/index range outside the arrays or not whole triangles";
        return MeshFault::kBadBodyRange;
    }
    if (!rigid(e.world_from_body)) {
        where += ": transform not finite, not rigid or too far";
        return MeshFault::kBadTransform;
    }
    for (std::uint32_t i = 0; i < e.index_count; ++i) {
        const std::uint32_t v = mesh.indices[e.index_offset + i];
        if (v >= e.vertex_count) {
            where += ": index " + std::to_string(i) + " = " + std::to_string(v) +
                     " >= " + std::to_string(e.vertex_count) + " vertices";
            return MeshFault::kBadIndex;
        }
    }
    for (std::uint32_t t = e.index_offset / 3; t < (e.index_offset + e.index_count) / 3; ++t) {
        if (mesh.materials[t] >= kTriangleMaterialCount) {
            where += ": triangle " + std::to_string(t - e.index_offset / 3) + " material " +
                     std::to_string(mesh.materials[t]);
            return MeshFault::kBadMaterial;
        }
    }
    return MeshFault::kNone;
}

std::uint64_t hash_words(std::uint64_t h, const void* data, std::size_t bytes) noexcept {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
        std::uint64_t w;
        std::memcpy(&w, p + i, 8);
        h = (h ^ w) * 0x100000001B3ull;
        h ^= h >> 29;
    }
    std::uint64_t tail = 0;
    std::memcpy(&tail, p + i, bytes - i);
    h = (h ^ tail ^ (std::uint64_t(bytes) << 56)) * 0x100000001B3ull;
    return h ^ (h >> 31);
}

}  // namespace

std::string_view to_string(TriangleMaterial material) noexcept {
    switch (material) {
        case TriangleMaterial::kCortical:
            return "cortical";
        case TriangleMaterial::kCancellous:
            return "cancellous";
        case TriangleMaterial::kCutSurface:
            return "cut_surface";
    }
    return "unknown";
}

std::uint64_t mesh_content_hash(const CollisionMesh& mesh) noexcept {
    const std::uint32_t counts[3] = {mesh.body_count, mesh.vertex_count, mesh.index_count};
    std::uint64_t h = hash_words(0xCBF29CE484222325ull, counts, sizeof counts);
    h = hash_words(h, mesh.bodies.data(), mesh.body_count * sizeof(MeshBodyEntry));
    h = hash_words(h, mesh.vertices_m.data(), 12u * std::size_t{mesh.vertex_count});
    h = hash_words(h, mesh.indices.data(), 4u * std::size_t{mesh.index_count});
    return hash_words(h, mesh.materials.data(), mesh.index_count / 3);
}

CollisionMesh::CollisionMesh()
    : bodies(kMeshMaxBodies),
      vertices_m(3u * kMeshMaxVertices + 2),
      indices(kMeshMaxIndices + 2),
      materials(kMeshMaxTriangles + 8) {}

std::string_view to_string(MeshFault fault) noexcept {
    switch (fault) {
        case MeshFault::kNone:
            return "none";
        case MeshFault::kBadCounts:
            return "bad_counts";
        case MeshFault::kBadBodyRange:
            return "bad_body_range";
        case MeshFault::kBadIndex:
            return "bad_index";
        case MeshFault::kNotFinite:
            return "not_finite";
        case MeshFault::kOutOfBounds:
            return "out_of_bounds";
        case MeshFault::kBadTransform:
            return "bad_transform";
        case MeshFault::kBadGeneration:
            return "bad_generation";
        case MeshFault::kBadMaterial:
            return "bad_material";
        case MeshFault::kBadHash:
            return "bad_hash";
    }
    return "unknown";
}

MeshFault validate_mesh(const CollisionMesh& mesh, std::string& where) {
    if (mesh.body_count == 0 || mesh.body_count > kMeshMaxBodies ||
        mesh.vertex_count > kMeshMaxVertices || mesh.index_count > kMeshMaxIndices ||
        mesh.bodies.size() < mesh.body_count || mesh.vertices_m.size() < 3u * mesh.vertex_count ||
        mesh.indices.size() < mesh.index_count || mesh.materials.size() < mesh.index_count / 3) {
        where = "counts: " + std::to_string(mesh.body_count) + " bodies, " +
                std::to_string(mesh.vertex_count) + " vertices, " +
                std::to_string(mesh.index_count) + " indices (capacity " +
                std::to_string(kMeshMaxBodies) + ", " + std::to_string(kMeshMaxVertices) + ", " +
                std::to_string(kMeshMaxIndices) + ")";
        return MeshFault::kBadCounts;
    }
    for (std::uint32_t i = 0; i < 3u * mesh.vertex_count; ++i) {
        const float c = mesh.vertices_m[i];
        if (!std::isfinite(c) || std::fabs(c) > kMeshMaxCoordinate_m) {
            where = "vertex " + std::to_string(i / 3) + ": coordinate " + std::to_string(c);
            return std::isfinite(c) ? MeshFault::kOutOfBounds : MeshFault::kNotFinite;
        }
    }
    for (std::uint32_t b = 0; b < mesh.body_count; ++b) {
        const MeshFault f = validate_body(mesh, b, where);
        if (f != MeshFault::kNone) return f;
    }
    where.clear();
    return MeshFault::kNone;
}

MeshMailboxWriter::MeshMailboxWriter(SegmentLayout& segment) noexcept : segment_(segment) {}

Result<std::uint64_t, IpcError> MeshMailboxWriter::publish(const CollisionMesh& mesh) {
    std::string where;
    const MeshFault fault = validate_mesh(mesh, where);
    if (fault != MeshFault::kNone) {
        return Err{IpcError{IpcErrc::kBadArgument, "collision mesh",
                            std::string(to_string(fault)) + ": " + where}};
    }
    MeshMailbox& box = segment_.mailbox;
    const auto latest = box.latest.value.load(std::memory_order_acquire);
    const std::uint64_t generation = (latest >> 1) + 1;
    const std::uint32_t target = latest == 0 ? 0u : std::uint32_t((latest & 1u) ^ 1u);
    MeshBuffer& buf = box.buffers[target];
    const auto odd = buf.sequence.value.load(std::memory_order_relaxed) | 1u;
    buf.sequence.value.store(odd, std::memory_order_relaxed);
    MeshBufferHeader header{};
    header.generation = generation;
    header.body_count = mesh.body_count;
    header.vertex_count = mesh.vertex_count;
    header.index_count = mesh.index_count;
    header.content_hash = mesh_content_hash(mesh);
    std::memcpy(header.bodies, mesh.bodies.data(), mesh.body_count * sizeof(MeshBodyEntry));
    store_words(&buf.header, &header, sizeof header);
    store_words(buf.vertices_m, mesh.vertices_m.data(), 12u * mesh.vertex_count);
    store_words(buf.indices, mesh.indices.data(), 4u * mesh.index_count);
    store_words(buf.materials, mesh.materials.data(), mesh.index_count / 3);
    buf.sequence.value.store(odd + 1, std::memory_order_release);
    box.latest.value.store((generation << 1) | target, std::memory_order_release);
    return generation;
}

MeshMailboxReader::MeshMailboxReader(const SegmentLayout& segment) noexcept : segment_(segment) {}

MailboxRead MeshMailboxReader::try_take_newest(CollisionMesh& out) {
    const MeshMailbox& box = segment_.mailbox;
    const auto latest = box.latest.value.load(std::memory_order_acquire);
    const std::uint64_t generation = latest >> 1;
    if (latest == 0 || generation <= taken_generation_ || latest == rejected_word_) {
        return MailboxRead::kNothingNew;
    }
    const MeshBuffer& buf = box.buffers[latest & 1u];
    const auto s1 = buf.sequence.value.load(std::memory_order_acquire);
    if (s1 & 1u) return MailboxRead::kBusy;
    MeshBufferHeader header{};
    load_words(&header, &buf.header, sizeof header);
    out.generation = header.generation;
    out.body_count = header.body_count;
    out.vertex_count = header.vertex_count;
    out.index_count = header.index_count;
    const bool counts_ok = header.body_count <= kMeshMaxBodies &&
                           header.vertex_count <= kMeshMaxVertices &&
                           header.index_count <= kMeshMaxIndices;
    if (counts_ok) {  // copy only what fits; validate_mesh reports bad counts below
        std::memcpy(out.bodies.data(), header.bodies, header.body_count * sizeof(MeshBodyEntry));
        load_words(out.vertices_m.data(), buf.vertices_m, 12u * header.vertex_count);
        load_words(out.indices.data(), buf.indices, 4u * header.index_count);
        load_words(out.materials.data(), buf.materials, header.index_count / 3);
    }
    if (buf.sequence.value.load(std::memory_order_relaxed) != s1) return MailboxRead::kBusy;
    std::string where;
    MeshFault fault = validate_mesh(out, where);
    if (fault == MeshFault::kNone && out.generation != generation) {
        fault = MeshFault::kBadGeneration;
        where = "generation " + std::to_string(out.generation) + ", latest says " +
                std::to_string(generation);
    }
    if (fault == MeshFault::kNone && mesh_content_hash(out) != header.content_hash) {
        fault = MeshFault::kBadHash;
        where = "content hash differs from the writer's (generation " + std::to_string(generation) +
                ")";
    }
    if (fault == MeshFault::kNone) {
        taken_generation_ = generation;
        return MailboxRead::kNew;
    }
    ++rejected_;
    rejected_word_ = latest;
    last_rejection_ = std::string(to_string(fault)) + ": " + where;
    if ((rejected_ & (rejected_ - 1)) == 0) {  // rate-limited: 1st, 2nd, 4th, 8th, ...
        spdlog::warn("kerf ipc: mesh mailbox generation {} rejected: {} ({} so far)", generation,
                     last_rejection_, rejected_);
    }
    return MailboxRead::kRejected;
}

}  // namespace kerf::ipc
