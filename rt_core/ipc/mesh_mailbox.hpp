// The geometry mailbox, display -> real-time process: the collision mesh after a topology edit.
// MeshMailboxWriter (kerf-display) publishes a new generation into the buffer readers are not
// pointed at and never waits; MeshMailboxReader (kerf-rt, on its non-real-time builder thread)
// copies the newest complete generation out and validates every size, index and coordinate
// before anything uses it (counts, ranges, indices, finiteness, materials, generation and the
// writer's content hash). See mesh_layout.hpp for the protocol.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/result.hpp"
#include "rt_core/ipc/ipc_error.hpp"
#include "rt_core/ipc/layout.hpp"

namespace kerf::ipc {

/// A collision mesh in plain arrays. Vectors are sized to the mailbox capacity once (allocate
/// in configure); the counts say how much is valid.
struct CollisionMesh {
    CollisionMesh();  ///< allocates capacity for the largest mesh the mailbox holds
    std::uint64_t generation = 0;
    std::uint32_t body_count = 0;
    std::uint32_t vertex_count = 0;  ///< total vertices (3 floats each)
    std::uint32_t index_count = 0;   ///< total indices (3 per triangle)
    std::vector<MeshBodyEntry> bodies;
    std::vector<float> vertices_m;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint8_t> materials;  ///< TriangleMaterial per triangle (global index / 3)
};

/// Hash of the valid part of a mesh (counts, bodies, vertices, indices, materials): what the
/// writer stores in MeshBufferHeader::content_hash and the reader recomputes. Word-wise, fast
/// (~1 ms per 10 MB), not cryptographic: it catches scribbles, not adversaries.
std::uint64_t mesh_content_hash(const CollisionMesh& mesh) noexcept;

/// Why a published mesh was refused.
enum class MeshFault : std::uint8_t {
    kNone,
    kBadCounts,
    kBadBodyRange,
    kBadIndex,
    kNotFinite,
    kOutOfBounds,
    kBadTransform,
    kBadGeneration,
    kBadMaterial,  ///< a triangle's material is not a TriangleMaterial
    kBadHash,      ///< content differs from what the writer hashed (scribbled after publish)
};
std::string_view to_string(MeshFault fault) noexcept;

/// Checks a mesh completely: counts within capacity, body ranges inside the arrays, every index
/// inside its body, coordinates finite and within kMeshMaxCoordinate_m, transforms rigid,
/// index ranges whole triangles, every material a TriangleMaterial.
/// On failure `where` says which body/element ("body 3: index 17 = 900 >= 512 vertices").
MeshFault validate_mesh(const CollisionMesh& mesh, std::string& where);

class MeshMailboxWriter {
public:
    /// @pre `segment` is mapped read-write and outlives the writer
    explicit MeshMailboxWriter(SegmentLayout& segment) noexcept;
    /// Validates `mesh` (a bad mesh is refused here, before readers see it), then publishes it
    /// as the next generation. Never waits for readers. Returns the generation.
    Result<std::uint64_t, IpcError> publish(const CollisionMesh& mesh);

private:
    SegmentLayout& segment_;
};

/// Outcome of MeshMailboxReader::try_take_newest.
enum class MailboxRead : std::uint8_t {
    kNew,         ///< `out` holds a newer generation, validated
    kNothingNew,  ///< nothing published since the last take
    kBusy,        ///< the writer overwrote the buffer during the copy; try again
    kRejected,    ///< the newest generation failed validation (counted, logged)
};

class MeshMailboxReader {
public:
    /// @pre `segment` outlives the reader
    explicit MeshMailboxReader(const SegmentLayout& segment) noexcept;
    /// Copies and validates the newest complete generation if newer than the last one taken.
    MailboxRead try_take_newest(CollisionMesh& out);
    std::uint64_t rejected() const noexcept { return rejected_; }
    const std::string& last_rejection() const noexcept { return last_rejection_; }

private:
    const SegmentLayout& segment_;
    std::uint64_t taken_generation_ = 0;
    std::uint64_t rejected_ = 0;
    std::uint64_t rejected_word_ = 0;  ///< latest-word refused last time (not logged twice)
    std::string last_rejection_;
};

}  // namespace kerf::ipc
