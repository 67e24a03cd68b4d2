// Library-internal: what a CutContext holds. Scratch properties are created on the mesh once and
// reused by every cut through generation stamps (no clearing pass, no property churn per cut).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "display/cut/face_tree.hpp"
#include "display/cut/section_plan.hpp"
#include "display/cut/triangulate.hpp"
#include "display/cut/vec_ops.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

struct ContextState {
    explicit ContextState(mesh::TriMesh& m);
    ~ContextState();
    ContextState(const ContextState&) = delete;
    ContextState& operator=(const ContextState&) = delete;

    /// Measures the mesh and rebuilds the face index (index()), clears the stamps and reserves
    /// the headroom.
    void rebuild();
    /// Measures the mesh (scale, tolerance, longest non-cap edge), builds the face tree and lists
    /// the cap faces.
    void index();
    /// Starts a new stamp generation (resets every stamp on wrap-around).
    void next_generation();
    /// Sets every stamp to 0 and the generation to 1. O(mesh).
    void clear_stamps();
    /// Makes room for `vertices`, `edges`, `faces` more elements without reallocating during the
    /// edit. Normally a no-op: idle-time grow_step() keeps headroom ahead of the cuts; if a cut
    /// still needs more, it grows everything here (O(mesh)) and counts it in growths_in_cuts.
    void ensure_capacity(std::size_t vertices, std::size_t edges, std::size_t faces);
    /// One bounded step for idle time: clears the stamps when fewer than kStampReserve
    /// generations are left before they wrap (so no cut meets the O(mesh) wrap-around), else
    /// hangs the face tree's pending inserts on their leaves when there are any, else writes one
    /// element kind of the headroom rebuild() reserved (write_headroom), else grow_kind(), else,
    /// once after the mesh grew, warm_appends(). Returns whether it did something.
    bool grow_step(std::size_t min_spare_faces);
    /// Writes the next elements past the end of every element array (vertices, edges, faces,
    /// with all their properties, and the list of cap faces), twice as many as were added since the
    /// last warm_appends() (at least kWarmElements, never past the reserved room), then shrinks
    /// back: the lines the next cut appends to are in cache, not in memory. On a 4M-triangle mesh a
    /// cut's appends missed the cache on about 1,000 lines a cut, reloaded from memory only to be
    /// overwritten; on a 100k one they stay in cache from cut to cut. Nothing observable changes.
    /// O(those elements).
    void warm_appends();
    static constexpr std::size_t kWarmElements = 256;
    /// Reserves the headroom (headroom_faces(0) faces, half as many vertices, twice as many
    /// edges, as many face-tree inserts) without writing it: no cut reallocates, and the first
    /// idle steps make it resident. A cut before them page-faults in the pages it writes (a few
    /// hundred at most: a cut adds a few thousand elements), instead of the context build
    /// writing all of it (1/8 of the mesh; `kerf cut`, which has no idle time, never does).
    void reserve_headroom();
    /// Writes the reserved room of one element kind (0 vertices, 1 edges, 2 faces, 3 the face
    /// tree's inserts) once, so that its pages become resident. O(that room).
    void write_headroom(int kind);
    /// When the spare room of one element kind (vertices, edges, faces, the face tree's inserts)
    /// is below half its target, grows that kind alone to its target and makes it resident.
    /// Targets: headroom_faces(min_spare_faces) faces, half as many vertices, twice as many
    /// edges. Returns whether it grew something. O(that array).
    bool grow_kind(std::size_t min_spare_faces);
    /// Faces of headroom the context keeps: an eighth of the mesh, at least `min_spare_faces`.
    std::size_t headroom_faces(std::size_t min_spare_faces) const;

    /// Whether triangle a, b, c is too small for a cut to make: twice its area is not above twice
    /// kMinTriangleRelativeArea x scale², or a float32 file in some supported unit (STL) would
    /// write it degenerate by validate() (mesh::kDegenerateTwiceAreaRelative x scale², which
    /// bounds every piece's threshold). The file check runs only for a triangle whose area the
    /// rounding could bring that low: each corner moves up to sqrt(3) float_rounding_m, which
    /// takes at most 4 sqrt(3) float_rounding_m x its longest edge from twice its area (a cap
    /// triangle 1.6 um long and 9 nm high, 50 mm from the origin, lost 79 % of its area). A
    /// triangle with two corners within the tolerance is left to merge_close_points, which
    /// collapses them (a file may well merge them). No square root on the common path.
    bool too_small(const Vec3& a, const Vec3& b, const Vec3& c) const {
        return too_small(a, b, c, twice_area2(a, b, c));
    }
    /// The same, given twice2 = |(b - a) x (c - a)|² as computed above (callers that need the
    /// cross product anyway pass it: same value, same answer).
    bool too_small(const Vec3& a, const Vec3& b, const Vec3& c, double twice2) const {
        return too_small(a, b, c, twice2, sqrdist(b, a), sqrdist(a, c));
    }
    /// The same, given also ab = |b - a|² and ca = |a - c|² (callers that have the edges).
    bool too_small(const Vec3& a, const Vec3& b, const Vec3& c, double twice2, double ab,
                   double ca) const {
        const double floor = kMinTriangleRelativeArea * scale_m * scale_m;
        if (!(twice2 > 4.0 * floor * floor)) return true;
        const double loss = 4.0 * std::sqrt(3.0) * float_rounding_m;  // per metre of edge
        const double kept = kFileMargin * floor;
        // (kept + loss L)² <= 2 kept² + 2 loss² L²: enough room without a square root. First
        // with 2.000000001 (ab + ca), which bounds the longest edge² (bc <= 2 (ab + ca), with room
        // for rounding), so the common case skips the third edge: the same answer either way.
        if (twice2 > 2.0 * (kept * kept + loss * loss * (2.000000001 * (ab + ca)))) return false;
        const double bc = sqrdist(c, b);
        const double longest2 = std::max({ab, bc, ca});
        if (twice2 > 2.0 * (kept * kept + loss * loss * longest2)) return false;
        if (std::sqrt(twice2) - loss * std::sqrt(longest2) > kept) return false;
        if (std::min({ab, bc, ca}) <= tolerance_m * tolerance_m) return false;
        return degenerate_in_a_float_file(a, b, c, kept);
    }
    /// Margin on validate()'s threshold for a triangle read back from a float32 file.
    static constexpr double kFileMargin = 1.25;
    /// Whether twice the area of a, b, c written as float32 in any LengthUnit (as the STL
    /// writer rounds) is at most `floor_m2`.
    static bool degenerate_in_a_float_file(const Vec3& a, const Vec3& b, const Vec3& c,
                                           double floor_m2);

    bool vertex_marked(mesh::VertexHandle v) const {
        return mesh.property(v_stamp, v) == generation;
    }
    bool edge_marked(mesh::EdgeHandle e) const { return mesh.property(e_stamp, e) == generation; }
    bool face_marked(mesh::FaceHandle f) const { return mesh.property(f_stamp, f) == generation; }
    void mark_face(mesh::FaceHandle f) { mesh.property(f_stamp, f) = generation; }

    mesh::TriMesh& mesh;
    double scale_m = 0.0;
    double tolerance_m = 0.0;
    /// Half a float32 step at the mesh's largest coordinate, m: how far writing a vertex to a
    /// float32 file (STL) may move each of its coordinates, whatever the file's unit.
    double float_rounding_m = 0.0;
    double max_edge_m =
        0.0;        ///< longest non-cap edge (+ vertex moves noted since): full-slice reach
    FaceTree tree;  ///< faces by bounding box, for seed and nested-loop queries
    std::vector<mesh::FaceHandle> cap_faces;  ///< every cap face made so far (not in the tree)

    /// A generation stamp: 16 bits, 2 bytes a vertex, edge and face (32 bits made the context
    /// 6 MiB heavier on a 1M mesh: issue 10 item 10). A cut uses a few generations; the stamps
    /// are cleared (O(mesh)) when they wrap, normally from idle time (grow_step).
    using Stamp = std::uint16_t;
    static constexpr Stamp kStampReserve = 4096;  ///< generations kept for cuts between idles
    OpenMesh::VPropHandleT<Stamp> v_stamp;
    OpenMesh::EPropHandleT<Stamp> e_stamp;
    OpenMesh::FPropHandleT<Stamp> f_stamp;
    OpenMesh::FPropHandleT<std::uint8_t> cap;  ///< named kCapFaceProperty
    Stamp generation = 1;
    std::size_t reserved_vertices = 0, reserved_edges = 0, reserved_faces = 0;
    unsigned unwritten_kinds = 0;  ///< bit k: kind k's reserved room is not written yet
    std::size_t warmed_vertices = 0, warmed_edges = 0, warmed_faces = 0;  ///< sizes at the last
                                                                          ///< warm_appends()
    std::uint64_t growths_in_cuts = 0;  ///< cuts that had to grow capacity themselves

    /// Whether a slice crossing an earlier cap puts its chord into that cap (cap_chords.hpp) rather
    /// than splitting the cap's triangles one by one. Off only to replay a sequence of cuts
    /// recorded before the chords (the regression tests' recorded face hints index that mesh).
    bool cap_chords = true;
    /// Vertices a little beyond the tolerance that the plan being made treats as on the plane
    /// (sorted; see plan_snapped in section_plan.hpp); null outside plan_snapped.
    const std::vector<std::int32_t>* snapped = nullptr;
    std::vector<std::int32_t> snap_candidates;  ///< what the last plan's checks would snap
    SectionPlan plan;
    Triangulator triangulator;
    std::vector<std::uint32_t> heap;         ///< seed search scratch
    std::vector<std::uint32_t> cap_scratch;  ///< per plan point, for the caps (cap_plan.cpp)
    std::vector<Point2> cap_strip_uv;        ///< an annulus's points, for its strip (cap_plan.cpp)
    std::vector<Triangle> cap_strip;         ///< and its triangles
    std::vector<std::uint32_t> cap_strip_neighbours;  ///< the plan's strips' slot links
    /// Scratch of the cap planning's triangle adjacency (cap_plan.cpp CapAdjacency), kept from
    /// cut to cut.
    struct CapPlanScratch {
        std::vector<std::uint32_t> from, to, first, out, in, fill, seen;
    } cap_plan;
    /// Scratch of the edit (apply_plan.cpp), kept from cut to cut: each plan point's vertex on
    /// the positive and the negative side, and one loop's rim halfedges.
    struct EditScratch {
        std::vector<mesh::VertexHandle> rim, dup;
        std::vector<mesh::HalfedgeHandle> h, x;
    } edit;
    /// Scratch of the edit's caps (apply_plan.cpp add_cap), kept from cut to cut.
    struct CapScratch {
        std::vector<std::uint32_t> from, to, across, inner, rank, lo, hi, count, sorted;
        std::vector<char> on_rim;
        std::vector<mesh::HalfedgeHandle> he;
        std::vector<std::pair<int, std::uint32_t>> by_handle;
    } cap_edit;
};

}  // namespace kerf::cut::detail
