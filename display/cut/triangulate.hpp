// triangulate_loops — 2-D triangulation of a planar region bounded by closed loops (cap builder).
//
// The region is given as loops of 2-D points in any orientation and any nesting: outer boundaries,
// holes inside them, islands inside holes, several regions side by side (a bone's cross-section is
// an annulus around the marrow canal). Nesting decides the role of a loop: a loop inside an even
// number of other loops bounds material on its inside (outer), one inside an odd number is a hole.
//
// Output triangles index the CONCATENATED input points (loop 0's points first, then loop 1's, ...):
// no point is added, so cap vertices map 1:1 to cross-section vertices. Every triangle is counter-
// clockwise in the given frame (positive signed area); a cap facing the other way swaps two
// indices. Every loop edge is the edge of exactly one triangle and every other triangle edge is
// shared by exactly two, in opposite directions, so a cap closes a sliced mesh into a 2-manifold.
//
// Method: a loop verified strictly convex and without holes is fanned from its first point. A
// region with exactly one hole (a bone round its canal) is first stitched as a strip between the
// two loops, each step taking the rung the in-circle test clearly wants, else the shorter one
// (near-Delaunay on annuli, in linear time); the strip is kept only if every triangle is clearly
// counter-clockwise, which makes it a valid triangulation (each point of the region is covered
// once: the sum of the triangles' orientations over a point is the winding number of the two
// loops). Every other region is ear-clipped after bridging each hole to the boundary (Eberly,
// "Triangulation by ear clipping", hole = leftmost vertex joined to a visible boundary vertex).
// The smallest ear is clipped first (size classes, O(1) each), only the two neighbours of a
// clipped ear are re-tested, and an ear test only visits reflex vertices in the grid cells under
// the ear's box: a few thousand points take about a millisecond or less. Deterministic: the result
// depends only on the input values and their order (no hash maps, no pointers compared).
// Degenerate input is a value, never a hang: fewer than 3 points, non-finite coordinates, a loop of
// zero area, or loops that cross or touch (including a loop touching itself) are refused with the
// loop(s) named. Zero-area triangles: collinear input points never need one (the clipper prefers a
// proper ear), but when rounding leaves no proper ear the clipper takes a degenerate one rather
// than stall; `TriangulateStats::degenerate_ears` counts them (0 on every input in the tests).
#pragma once

#include <OpenMesh/Core/Geometry/VectorT.hh>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"

namespace kerf::cut {

using Point2 = OpenMesh::Vec2d;  ///< a point in the plane's 2-D frame (metres)

/// Three indices into the concatenated input points, counter-clockwise.
struct Triangle {
    std::uint32_t a;
    std::uint32_t b;
    std::uint32_t c;
    friend bool operator==(const Triangle&, const Triangle&) = default;
};

/// Why a set of loops cannot be triangulated.
enum class TriangulateErrc : std::uint8_t {
    kNoLoops = 0,           ///< the loop list is empty
    kTooFewPoints = 1,      ///< a loop has fewer than 3 points
    kNonFinite = 2,         ///< a coordinate is NaN or infinite
    kZeroArea = 3,          ///< a loop encloses (relatively) zero area
    kSelfIntersecting = 4,  ///< two loop edges cross or touch (same loop or two loops)
    kTooManyPoints = 5,     ///< more points than a 32-bit index can name
};
/// Stable snake_case name ("self_intersecting").
std::string_view to_string(TriangulateErrc f) noexcept;

/// A refusal (kerf::Error): where names the loop(s) ("loop 2", "loops 0 and 3"; indices into the
/// input), what says what is wrong; the indices are kept as numbers (`other_loop` is the second
/// loop of a crossing, equal to `loop` for a self-crossing, -1 where not applicable).
struct TriangulateError : Error<TriangulateErrc> {
    std::int32_t loop = -1;
    std::int32_t other_loop = -1;
};

/// A TriangulateError with where and what made from the code and the loop indices.
TriangulateError triangulate_error(TriangulateErrc code, std::int32_t loop = -1,
                                   std::int32_t other_loop = -1);

/// What one triangulation did.
struct TriangulateStats {
    std::uint32_t loops = 0;            ///< loops given
    std::uint32_t outer_loops = 0;      ///< loops bounding material (even nesting depth)
    std::uint32_t holes = 0;            ///< loops bounding a hole (odd nesting depth)
    std::uint32_t fans = 0;             ///< regions fanned because the loop was strictly convex
    std::uint32_t strips = 0;           ///< one-hole regions stitched as a strip between the loops
    std::uint32_t degenerate_ears = 0;  ///< zero-area ears taken when no proper ear was left
};

/// Reusable triangulator: keeps its scratch buffers between calls so that capping every cut
/// allocates only while the buffers grow. Not thread-safe; one per thread.
class Triangulator {
public:
    Triangulator();
    ~Triangulator();
    Triangulator(Triangulator&&) noexcept;
    Triangulator& operator=(Triangulator&&) noexcept;

    /// Triangulates the region bounded by `loops` into `out` (cleared first).
    /// @pre each loop lists its points once (no repeated closing point).
    /// On failure `out` is empty and the error names the offending loop(s).
    Status<TriangulateError> triangulate(std::span<const std::span<const Point2>> loops,
                                         std::vector<Triangle>& out);

    /// Triangulates an annulus, one outer loop and one hole inside it, as a strip between the
    /// two loops with every point kept (a strip needs no ear, so points in a straight line on a
    /// loop are no trouble), into `out` (cleared first). False, with `out` empty, when the loops
    /// are not one outer loop and its hole, fail triangulate()'s checks, or some strip triangle
    /// would not be clearly counter-clockwise: triangulate() decides then.
    bool triangulate_strip(std::span<const std::span<const Point2>> loops,
                           std::vector<Triangle>& out);

    /// Statistics of the last call.
    const TriangulateStats& stats() const noexcept { return stats_; }

private:
    struct Impl;  // scratch buffers (points, nesting, linked rings, reflex grid)
    std::unique_ptr<Impl> impl_;
    TriangulateStats stats_;
};

/// One-shot convenience: triangulates `loops` with a fresh Triangulator.
Result<std::vector<Triangle>, TriangulateError> triangulate_loops(
    std::span<const std::span<const Point2>> loops);

/// Signed area of one loop (positive when counter-clockwise), by the shoelace formula.
double signed_area(std::span<const Point2> loop) noexcept;

}  // namespace kerf::cut
