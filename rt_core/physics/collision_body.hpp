// kerf::physics::CollisionBody — the immutable collision structure of one rigid body, and the
// per-tick queries the 1 kHz loop asks of it.
//
// Construction (off the real-time thread; allocates):
//   auto body = CollisionBody::build(view);               // Result<unique_ptr<...>, ...>
//   auto next = CollisionBody::update(**body, new_view);  // after a cut: touched chunks only
// Swap (the loop's business, not this library's): keep the unique_ptr alive off the RT thread,
// hand the raw pointer to CollisionWorld::set_body() at a tick boundary, and free the previous body
// off the RT thread once the loop has stopped using it.
// Per tick (any thread, concurrently; noexcept, allocation-free, bounded by the tree depth):
//   closest_point(), first_hit(), crossings(), triangles_near().
//
// Structure (why, measured in tests/physics/bench_collision.cpp; rt_core/README.md has figures):
// the triangles are split by a spatial median split into chunks of about `chunk_triangles`; each
// chunk has its own flat binary AABB tree (median split, up to `leaf_triangles` per leaf, each
// triangle's three corners copied into the leaf order; a triangle wider than `max_piece_edge_m`
// along an axis has one entry per piece, each boxing its piece); a small top tree over the
// chunks' boxes is rebuilt on every update. After a cut the new mesh is compared with the
// previous one triangle by triangle (indices, corners, material); a chunk with changed triangles
// is copied, its changed triangles patched, and its boxes refitted (a cut shrinks the triangles
// it splits and moves vertices by half a kerf, so the boxes stay tight), a chunk that lost
// triangles is rebuilt, appended triangles get new chunks of their own (they are local to the
// cut), and unchanged chunks are shared with the previous body. A
// chunk is a set of triangle indices, so when faces are removed (a body severed) the indices after
// them shift and its triangles are no longer neighbours: a changed chunk whose box grew by more
// than a quarter is emptied and its triangles grouped afresh, with the new ones, into new chunks.
// Embree's rtcPointQuery is measured against this tree in the same benchmark; the choice and its
// figures are in rt_core/README.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "config/base/result.hpp"
#include "rt_core/physics/collision_mesh.hpp"

namespace kerf::physics {

inline constexpr std::uint32_t kNoTriangle = 0xFFFFFFFFu;  ///< same value as ipc::kNoTriangle

/// Tuning of the collision structure.
struct BuildOptions {
    std::uint32_t chunk_triangles = 4096;  ///< triangles per chunk (the unit a cut refits)
    std::uint32_t leaf_triangles = 4;      ///< triangles per leaf of a chunk's tree
    /// A triangle whose box is wider than this (m) along an axis is indexed as pieces: boxes
    /// covering it, the widest halved across its widest axis (the triangle clipped to each half)
    /// until none is wider, at most 16. A cut's cap triangles span the bone's section, and one
    /// box that size would be entered by every query near the cut. Queries test the whole
    /// triangle.
    double max_piece_edge_m = 0.004;
};

/// The nearest surface point found by a query. Body queries fill body frame; world queries fill
/// world frame and `body`.
struct SurfaceHit {
    bool found = false;                    ///< false: nothing within the search distance
    std::uint32_t body = 0;                ///< world slot (world queries only)
    std::uint32_t triangle = kNoTriangle;  ///< triangle index in the body's mesh
    Vec3 point;                            ///< nearest point on the surface, m
    Vec3 normal;                           ///< the triangle's unit outward normal
    double distance = 0;                   ///< |query - point|, m
    Material material = Material::kCortical;
};

/// A set of materials: bit (1 << Material) per member.
using MaterialMask = std::uint8_t;
inline constexpr MaterialMask kAllMaterials = 0x7;
/// Bone surfaces only (cut surfaces excluded).
inline constexpr MaterialMask kBoneSurfaces = (1u << 0) | (1u << 1);

/// Which triangle sides stop a segment.
enum class HitSides : std::uint8_t {
    kFront = 0,  ///< only crossings from outside to inside (the proxy's rule on closed meshes)
    kBoth = 1,   ///< any crossing
};

/// The first crossing of a segment with the surface.
struct SegmentHit {
    bool found = false;
    std::uint32_t body = 0;                ///< world slot (world queries only)
    std::uint32_t triangle = kNoTriangle;  ///< triangle crossed first
    double t = 1;                          ///< crossing at from + t (to - from), t in [0, 1]
    Vec3 point;                            ///< the crossing point, m
    Vec3 normal;                           ///< the triangle's unit outward normal
    Material material = Material::kCortical;
};

/// One crossing of a segment with the surface (every one, not only the first: crossings()).
struct SegmentCrossing {
    double t = 1;                          ///< at from + t (to - from), t in [0, 1)
    std::uint32_t body = 0;                ///< world slot (world queries only)
    std::uint32_t triangle = kNoTriangle;  ///< the triangle crossed
    int sign = 0;                          ///< +1 leaving (along the outward normal), -1 entering
};

/// What an update() did.
struct UpdateStats {
    std::uint32_t chunks_total = 0;       ///< chunks in the new body
    std::uint32_t chunks_refitted = 0;    ///< copied, changed triangles patched, boxes refitted
    std::uint32_t chunks_rebuilt = 0;     ///< rebuilt (lost triangles) or new (added triangles)
    std::uint32_t chunks_regrouped = 0;   ///< emptied: their box grew (shifted indices), regrouped
    std::uint64_t triangles_touched = 0;  ///< triangles in refitted and rebuilt chunks
};

/// One triangle's corners, m, body frame.
struct TriangleCorners {
    Vec3 a, b, c;
};

class CollisionBody {
public:
    using Built = Result<std::unique_ptr<const CollisionBody>, MeshProblem>;

    /// Validates `mesh` (validate_mesh) and builds the structure from scratch. Off the RT thread.
    static Built build(const CollisionMeshView& mesh, const BuildOptions& options = {});
    /// Builds the structure of `next` (the same body after a topology edit) from `previous`:
    /// unchanged chunks shared, changed ones refitted, new triangles in new chunks; `stats`
    /// (optional) says what was done. Off the RT thread.
    static Built update(const CollisionBody& previous, const CollisionMeshView& next,
                        UpdateStats* stats = nullptr);
    /// Same topology, moved vertices: refits every box of `previous` to `next`'s positions (a
    /// whole refit). Refused (kIndexOutOfRange at the first difference) if the triangles differ.
    static Built refit(const CollisionBody& previous, const CollisionMeshView& next);

    ~CollisionBody();
    CollisionBody(const CollisionBody&) = delete;
    CollisionBody& operator=(const CollisionBody&) = delete;

    // ---- per tick: noexcept, allocation-free, body frame ------------------------------------
    /// Nearest point to `p` within `max_distance` (m) on the triangles whose material is in
    /// `materials`; found == false when there is none.
    SurfaceHit closest_point(const Vec3& p, double max_distance,
                             MaterialMask materials = kAllMaterials) const noexcept;
    /// First crossing of the segment from -> to with the surface (smallest t), counting `sides`.
    SegmentHit first_hit(const Vec3& from, const Vec3& to, HitSides sides) const noexcept;
    /// Every crossing of the segment from -> to with the surface, both sides, in no order, in one
    /// traversal: writes up to out.size() and returns how many exist (may exceed out.size()).
    /// Watertight for counting (segment_crossing): through a shared edge or vertex the segment
    /// crosses one triangle, so on closed meshes the signs sum to the winding-number difference.
    /// (Past out.size(), a triangle indexed in pieces may be counted once per piece.)
    std::size_t crossings(const Vec3& from, const Vec3& to,
                          std::span<SegmentCrossing> out) const noexcept;
    /// Triangles with a point within `radius` of `center` (the proxy's neighbourhood): writes up
    /// to out.size() indices and returns how many exist (may exceed out.size(); past it, a
    /// triangle indexed in pieces may be counted once per piece).
    std::size_t triangles_near(const Vec3& center, double radius,
                               std::span<std::uint32_t> out) const noexcept;

    // ---- the mesh it was built from ----------------------------------------------------------
    std::size_t triangle_count() const noexcept;
    std::size_t vertex_count() const noexcept;
    Material material(std::uint32_t triangle) const noexcept;
    TriangleCorners corners(std::uint32_t triangle) const noexcept;
    /// The pose published with the mesh (CollisionWorld may override it per tick).
    const RigidTransform& world_from_body() const noexcept;
    /// Axis-aligned bounds of the whole mesh, body frame, m.
    void bounds(Vec3& lo, Vec3& hi) const noexcept;
    std::uint32_t chunk_count() const noexcept;
    /// Heap bytes held by the structure (mesh copy included).
    std::size_t memory_bytes() const noexcept;

    struct Impl;  ///< defined in collision_body.cpp

private:
    explicit CollisionBody(std::unique_ptr<Impl> impl) noexcept;
    std::unique_ptr<Impl> impl_;
};

}  // namespace kerf::physics
