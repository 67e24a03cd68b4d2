// What changed in a CutSession's mesh since the last look, as index ranges a renderer uploads
// (glBufferSubData per range) instead of the whole buffer.
//
//   SessionChanges changes;
//   session.take_changes(changes);
//   for (IndexRange r : changes.vertices) upload_vertices(r.first, r.count);
//   for (IndexRange r : changes.faces) upload_triangles(r.first, r.count);
//
// Indices are OpenMesh's: vertex i is vertex buffer element i, face f is triangle f (indices
// 3f..3f+2). Cuts edit in place and append, never compact, so a range is all that moves.
#pragma once

#include <cstdint>
#include <vector>

namespace kerf::cut {

/// Elements [first, first + count).
struct IndexRange {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};

/// Ranges closer than this many elements are merged into one (fewer, larger uploads).
inline constexpr std::uint32_t kRangeMergeGap = 64;

struct SessionChanges {
    bool everything = false;           ///< upload all (first take, or after a rebuild)
    bool poses = false;                ///< some body's pose changed
    bool bodies = false;               ///< bodies were added or faces changed body
    std::uint32_t vertex_count = 0;    ///< vertices in the mesh now (deleted ones included)
    std::uint32_t face_count = 0;      ///< faces in the mesh now (deleted ones included)
    std::vector<IndexRange> vertices;  ///< sorted, disjoint
    std::vector<IndexRange> faces;     ///< sorted, disjoint

    /// Elements covered by `ranges`.
    static std::uint64_t covered(const std::vector<IndexRange>& ranges) noexcept;
    void clear() noexcept;
};

/// Sorts `indices` and turns them into sorted disjoint ranges in `out` (replacing its content),
/// merging neighbours at most `merge_gap` elements apart.
void to_ranges(std::vector<std::uint32_t>& indices, std::uint32_t merge_gap,
               std::vector<IndexRange>& out);

}  // namespace kerf::cut
