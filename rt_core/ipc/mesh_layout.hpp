// Shared layout of the geometry mailbox (kerf-display -> kerf-rt): the collision mesh after a
// topology edit, double-buffered. Pinned by static_asserts and tests/ipc/layout_test.cpp.
//
//   latest = (generation << 1) | buffer     0 = nothing published yet
//   writer: picks the buffer `latest` does NOT point at, seq odd, writes, seq even, latest = new
//   reader: reads `latest`, copies that buffer under its seq (retry if the seq moved)
#pragma once

#include <cstdint>

#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {

inline constexpr std::uint32_t kMeshMaxBodies = 64;
inline constexpr std::uint32_t kMeshMaxVertices = 1u << 17;        ///< over all bodies
inline constexpr std::uint32_t kMeshMaxIndices = 3u * (1u << 18);  ///< 2^18 triangles
inline constexpr float kMeshMaxCoordinate_m = 10.0f;               ///< |x|, |y|, |z| bound

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
    std::uint32_t reserved;
    MeshBodyEntry bodies[kMeshMaxBodies];
};

struct MeshBuffer {
    PaddedCounter sequence;  ///< even: complete; odd: being written
    MeshBufferHeader header;
    float vertices_m[3 * kMeshMaxVertices];  ///< x y z per vertex, body frame, m
    std::uint32_t indices[kMeshMaxIndices];  ///< 3 per triangle, counter-clockwise outward
};

struct MeshMailbox {
    PaddedCounter latest;  ///< (generation << 1) | buffer index; 0 = empty
    MeshBuffer buffers[2];
};

static_assert(sizeof(MeshBodyEntry) == 80 && sizeof(MeshBufferHeader) == 24 + 80 * kMeshMaxBodies);
static_assert(offsetof(MeshBuffer, header) == 64);
static_assert(offsetof(MeshBuffer, vertices_m) == 64 + sizeof(MeshBufferHeader));
static_assert(offsetof(MeshBuffer, indices) % 8 == 0 && sizeof(MeshBuffer) % 64 == 0);

}  // namespace kerf::ipc
