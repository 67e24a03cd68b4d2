// Sever detection: which pieces a mesh is made of, globally or from the cut outwards.
//
//   std::vector<Body> all = find_components(mesh);               // O(V + F), every piece
//
//   PieceFinder finder(mesh);                                     // O(F) once per mesh
//   SeverReport r = finder.find_pieces(cross_section);            // after each cut
//   for (const Body& b : r.severed) spawn_body(b);                // pieces cut free
//
// A piece is a set of live faces connected through shared edges (deleted faces are skipped).
// find_pieces() starts one breadth-first search per rim loop and side of the cut and runs them in
// lockstep, merging searches that meet. A search that runs out of faces has walked a whole piece:
// that piece was cut free. It stops as soon as at most one search is still growing, so its cost
// is proportional to the pieces cut free (the small ones), not to the mesh: cutting the tip off a
// toe visits the tip, not the foot. The still-growing search is the remainder, which keeps being
// the original body. A cut that severs nothing merges every search and reports no new body.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "display/cut/cross_section.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

/// One piece: its elements (sorted by index), signed volume and bounding box.
struct Body {
    std::vector<mesh::FaceHandle> faces;
    std::vector<mesh::VertexHandle> vertices;
    double volume_m3 = 0.0;  ///< signed (divergence theorem); positive for a closed outward piece
    mesh::Point bbox_min_m{0.0, 0.0, 0.0};
    mesh::Point bbox_max_m{0.0, 0.0, 0.0};
};

/// Every piece of `mesh`, ordered by their lowest face index. O(V + F).
std::vector<Body> find_components(const mesh::TriMesh& mesh);

/// Groups shells into bodies: a shell of negative volume (a cavity, e.g. a bone's medullary canal
/// modelled as an inward-facing shell) joins the smallest positive shell whose bounding box holds
/// its own (a box test: cavities are assumed not to straddle two bones). Order: that of the
/// positive shells; a cavity with no holder stays a body of its own.
std::vector<Body> group_cavities(std::vector<Body> shells);

/// What find_pieces() found. When every search closes (e.g. two equal halves finish in the same
/// round) every piece is in `severed` and no seed is kRemainder: keep the largest as the original.
struct SeverReport {
    static constexpr std::uint32_t kRemainder = 0xFFFFFFFFu;
    std::vector<Body> severed;                 ///< pieces walked whole, in the order they closed
    std::vector<std::uint32_t> piece_of_seed;  ///< per seed: index into `severed`, or kRemainder
    std::uint64_t faces_visited = 0;           ///< work done (the localisation claim, measured)
};

/// Two vertices whose pieces still hold together although the mesh is cut between them: the
/// copies of a rim vertex of a partial cut where the blade never went (the material there is
/// whole, see CutSession). A search reaching one continues from the faces of the other.
struct Glue {
    mesh::VertexHandle a;
    mesh::VertexHandle b;
    friend bool operator<(const Glue& x, const Glue& y) noexcept {
        return x.a < y.a || (x.a == y.a && x.b < y.b);
    }
};

/// Localised sever detection with scratch that persists between cuts.
class PieceFinder {
public:
    /// Binds to `mesh` (which must outlive the finder) and sizes the scratch arrays.
    explicit PieceFinder(const mesh::TriMesh& mesh);

    /// Pieces reached from `seeds` (live faces), searching in lockstep as described above.
    /// Invalid or deleted seeds are skipped (reported as kRemainder). `glue` (sorted, each pair
    /// listed both ways) joins faces the mesh does not: a piece is then a set of faces connected
    /// through shared edges or glued vertices.
    SeverReport find_pieces(std::span<const mesh::FaceHandle> seeds,
                            std::span<const Glue> glue = {});

    /// Seeds for a cut: one face at the first rim vertex of every loop on each side.
    SeverReport find_pieces(const CrossSection& cut, std::span<const Glue> glue = {});

private:
    const mesh::TriMesh& mesh_;
    std::vector<std::uint32_t> face_stamp_;  // == stamp_: face claimed in this call
    std::vector<std::uint32_t> face_owner_;  // seed that claimed it
    std::vector<std::uint32_t> vertex_stamp_;
    std::uint32_t stamp_ = 0;

    void grow_to_mesh();
    bool claimed(mesh::FaceHandle f) const noexcept;
};

/// Builds the Body of `faces` (vertices, volume, bbox); `faces` need not be sorted.
/// `vertex_seen` is scratch sized to the vertex count, compared against `stamp`.
Body make_body(const mesh::TriMesh& mesh, std::vector<mesh::FaceHandle> faces,
               std::vector<std::uint32_t>& vertex_seen, std::uint32_t stamp);

}  // namespace kerf::cut
