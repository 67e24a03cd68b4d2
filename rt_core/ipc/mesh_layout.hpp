// Shared layout of the geometry mailbox (kerf-display -> kerf-rt): the collision mesh after a
// topology edit, double-buffered. Pinned by static_asserts and tests/ipc/layout_test.cpp.
//
//   latest = (generation << 1) | buffer     0 = nothing published yet
//   writer: picks the buffer `latest` does NOT point at, seq odd, writes, seq even, latest = new
//   reader: reads `latest`, copies that buffer under its seq (retry if the seq moved), then
//           checks content_hash and validates every count, index, coordinate and material
//
// Layout version 2 added a material per triangle (materials[]) and the header's content_hash.
// Layout version 3 grew the capacity from 2^17 vertices / 2^18 triangles (a 4.8 MiB buffer) to
// 2^20 / 2^21, so that a 1M-triangle scene (the built-in foot at 1M: 499,909 vertices, 999,666
// triangles) is published whole — the surface kerf-rt makes the surgeon feel is the one the
// display draws, not a decimated stand-in. One buffer is 38 MiB, the mailbox 76 MiB of the
// segment; pages are only backed once written (kerf-rt under mlockall backs them all).
#pragma once

#include <cstdint>
#include <string_view>

#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {

inline constexpr std::uint32_t kMeshMaxBodies = 64;
inline constexpr std::uint32_t kMeshMaxVertices = 1u << 20;        ///< over all bodies
inline constexpr std::uint32_t kMeshMaxIndices = 3u * (1u << 21);  ///< 2^21 triangles
inline constexpr std::uint32_t kMeshMaxTriangles = kMeshMaxIndices / 3;
inline constexpr float kMeshMaxCoordinate_m = 10.0f;  ///< |x|, |y|, |z| bound

/// What one collision triangle is made of: what the proxy feels and what the saw cuts through.
/// Values are part of the layout (never renumber, only append).
enum class TriangleMaterial : std::uint8_t {
    kCortical = 0,    ///< the hard outer shell of a bone (the default)
    kCancellous = 1,  ///< spongy inner bone, e.g. the medullary canal's wall
    kCutSurface = 2,  ///< a cap or kerf face a cut exposed (shaded and felt as cancellous)
};
inline constexpr std::uint8_t kTriangleMaterialCount = 3;
std::string_view to_string(TriangleMaterial material) noexcept;

/// One body's slice of the vertex and index arrays.
struct MeshBodyEntry {
    std::uint32_t vertex_offset;  ///< first vertex (in vertices, not floats)
    std::uint32_t vertex_count;
    std::uint32_t index_offset;  ///< first index
    std::uint32_t index_count;   ///< multiple of 3; indices are body-local (0..vertex_count-1)
    float world_from_body[16];   ///< rigid transform, column-major, translation in m
};

/// Counts and bodies of one published mesh.
struct MeshBufferHeader {
    std::uint64_t generation;  ///< increases with every publish, never 0
    std::uint32_t body_count;
    std::uint32_t vertex_count;  ///< total over bodies
    std::uint32_t index_count;   ///< total over bodies
    std::uint32_t reserved;      ///< 0
    std::uint64_t content_hash;  ///< mesh_content_hash() of everything below, set by the writer
    MeshBodyEntry bodies[kMeshMaxBodies];
};

struct MeshBuffer {
    PaddedCounter sequence;  ///< even: complete; odd: being written
    MeshBufferHeader header;
    float vertices_m[3 * kMeshMaxVertices];     ///< x y z per vertex, body frame, m
    std::uint32_t indices[kMeshMaxIndices];     ///< 3 per triangle, counter-clockwise outward
    std::uint8_t materials[kMeshMaxTriangles];  ///< TriangleMaterial per triangle (index / 3)
};

struct MeshMailbox {
    PaddedCounter latest;  ///< (generation << 1) | buffer index; 0 = empty
    MeshBuffer buffers[2];
};

static_assert(sizeof(MeshBodyEntry) == 80 && sizeof(MeshBufferHeader) == 32 + 80 * kMeshMaxBodies);
static_assert(offsetof(MeshBuffer, header) == 64);
static_assert(offsetof(MeshBuffer, vertices_m) == 64 + sizeof(MeshBufferHeader));
static_assert(offsetof(MeshBuffer, indices) % 8 == 0 && sizeof(MeshBuffer) % 64 == 0);
static_assert(offsetof(MeshBuffer, materials) ==
              offsetof(MeshBuffer, indices) + 4 * kMeshMaxIndices);
static_assert(offsetof(MeshBuffer, materials) % 8 == 0 && kMeshMaxTriangles % 8 == 0);

}  // namespace kerf::ipc
