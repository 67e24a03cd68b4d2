// kerf::render::ChunkIssue — the order in which a frame issues the bone's draw calls (chunks of
// kBoneChunkTriangles triangles) and what it has issued so far, so that an edit arriving while a
// frame is being issued can join that frame instead of starting it over. No GL: the Renderer
// draws the ranges it hands out; a test can drive it alone.
//
//   issue.uploaded(mesh);                   // after every upload: what the GL buffers hold
//   issue.begin();                          // a new frame: nothing issued yet
//   while (issue.next(first, count)) {      // chunks edited lately come last
//       if (newer edit && issue.can_join(mesh)) upload it (-> uploaded(mesh));
//       draw(first, count);
//   }
//
// An edit can join when it changes nothing the frame has drawn: no dirty triangle lies in an
// issued range, and no issued triangle uses a dirty vertex (checked on the CPU copy of the
// indices, O(issued triangles), only when a dirty vertex is one the frame could have used).
// Then uploading it and drawing on gives exactly the frame drawn after the edit. Chunks an edit
// touched are drawn last for a while: the next edits of a cut in progress land in the same place,
// so they usually find those chunks not yet issued and join the frame in flight.
#pragma once

#include <cstdint>
#include <vector>

#include "display/render/render_mesh.hpp"

namespace kerf::render {

/// Triangles per draw call of the mesh when a frame may take an edit between them.
inline constexpr std::uint32_t kBoneChunkTriangles = 1u << 15;

class ChunkIssue {
public:
    /// The GL buffers now hold `mesh` (call after every upload, mid-frame ones included): its
    /// triangles join the frame; its vertices may be used by the triangles issued from now on.
    void uploaded(const RenderMesh& mesh);
    /// A new frame: nothing issued yet.
    void begin();
    /// The next triangles to draw, [first, first + count): chunks not edited lately in order,
    /// then the ones edited lately (and what edits that joined appended). False at the end.
    bool next(std::uint32_t& first, std::uint32_t& count);

    /// Whether the changes `mesh` has not uploaded yet leave every issued triangle as drawn (see
    /// the header comment). A chunk that stands in the way is drawn last in the next frames.
    bool can_join(RenderMesh& mesh);
    /// Chunks `mesh`'s dirty index ranges touch are edited now (call before uploading them).
    void note_edits(RenderMesh& mesh);

    /// Uploads with edits seen so far; a chunk edited within the last kHotUploads stays "hot".
    static constexpr std::uint32_t kHotUploads = 64;

private:
    std::uint32_t chunk_end(std::uint32_t c) const noexcept;
    bool hot(std::uint32_t c) const noexcept;
    void mark_hot(std::uint32_t c);
    void plan();

    std::uint32_t triangles_ = 0;         ///< triangles in the buffers (grows when edits join)
    std::uint32_t vertex_limit_ = 0;      ///< issued triangles use mesh vertices below this ...
    std::uint32_t vertex_capacity_ = 0;   ///< ... and cap corners from here ...
    std::uint32_t cap_limit_ = 0;         ///< ... below vertex_capacity_ + this
    std::uint64_t generation_ = 0;        ///< RenderMesh::generation() of the buffers
    std::vector<std::uint32_t> done_;     ///< per chunk: triangles of it issued this frame
    std::vector<std::uint32_t> edited_;   ///< per chunk: upload stamp of its last edit (0: never)
    std::vector<std::uint32_t> pending_;  ///< chunks still to issue, in order
    std::size_t at_ = 0;                  ///< next entry of pending_
    std::uint32_t stamp_ = 0;             ///< uploads with edits so far
    std::vector<std::uint64_t> bits_;     ///< scratch: dirty vertices, one bit each
};

}  // namespace kerf::render
