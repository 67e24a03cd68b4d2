// Library-internal: the read-only first phase of a slice. It finds the cross-section loops (as
// sequences of cut points: on-plane vertices and crossing edges), decides which loops the cut
// takes, computes every new point and triangulates the caps — all before the mesh is touched, so
// any failure leaves the mesh unchanged.
//
// Loop direction: a loop runs along the positive side's rim halfedges, so outer loops are
// counter-clockwise in the plane frame (positive area) and holes clockwise.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"
#include "display/cut/seed.hpp"
#include "display/cut/triangulate.hpp"
#include "display/mesh/validate.hpp"

namespace kerf::cut::detail {

struct ContextState;

/// A point where the cross-section meets the mesh: an on-plane vertex or a crossing edge.
struct CutPointKey {
    std::int32_t id = -1;  ///< vertex index or edge index
    bool edge = false;
    friend bool operator==(const CutPointKey&, const CutPointKey&) = default;
};

/// One cut point with its geometry.
struct PlanPoint {
    CutPointKey key;
    Vec3 position;  ///< m (the vertex's own position for on-plane vertices)
    Vec2 uv;        ///< in the plane frame, m
    double t = 0;   ///< edge parameter from the lower-index endpoint `a` towards `b`
    std::int32_t a = -1;
    std::int32_t b = -1;
};

/// A closed loop of cut points: points[first .. first + count).
struct PlanLoop {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    double area_m2 = 0;       ///< signed, in the plane frame
    std::uint32_t faces = 0;  ///< crossing faces the loop passes through (split if selected)
    bool selected = false;    ///< cut by this slice
};

/// An edge cut point within tol of its neighbour on the loop (the vertex it would make could be
/// reused): its edge is still split, and the new vertex is collapsed into the neighbour's.
struct MergedPoint {
    PlanPoint point;     ///< the dropped cut point (always on an edge)
    std::uint32_t into;  ///< index in SectionPlan::points of the point that stays
};

/// A cap triangle edge on the rim (no neighbouring cap triangle): SectionPlan::cap_neighbours.
inline constexpr std::uint32_t kNoCapNeighbour = 0xffffffffu;

/// Everything the second (editing) phase needs.
struct SectionPlan {
    std::vector<PlanPoint> points;
    std::vector<PlanLoop> loops;
    std::vector<MergedPoint> merged;      ///< dropped from the selected loops by merge_close_points
    std::vector<Triangle> cap_triangles;  ///< counter-clockwise, indexing `points`
    /// Per cap triangle edge slot 3t + e (from corner e to corner e + 1 of cap_triangles[t]): the
    /// slot of the same edge, run the other way, in the neighbouring cap triangle, or
    /// kNoCapNeighbour on the rim.
    std::vector<std::uint32_t> cap_neighbours;
    /// loop_nested()'s answers so far, by the two loops' points (the loop selection and the cap
    /// groups ask the same question of the same loops): loops are only appended until
    /// merge_close_points rewrites them, which clears it. The first 32 answers only (a bounded
    /// search per question).
    struct Nesting {
        std::uint32_t inner_first, inner_count, outer_first, outer_count;
        bool nested;
    };
    mutable std::vector<Nesting> nesting;

    void clear();
};

/// Plans a full-plane slice: every loop. O(n) classification.
CutStatus plan_full(ContextState& s, const Plane& plane);

/// The face the seed lies on: the hint when it holds the point (within the seed tolerance), else
/// the nearest face within that tolerance (invalid if none).
mesh::FaceHandle find_seed_face(ContextState& s, const Seed& seed);

/// Plans a localised slice: the seed's loop and the loops nested inside it.
CutStatus plan_localised(ContextState& s, const Plane& plane, const Seed& seed);

/// Plans a localised slice from the first of `faces` the plane crosses (as plan_localised does
/// from the crossing it finds nearest the seed); kPlaneMissesMesh if it crosses none.
CutStatus plan_localised_on(ContextState& s, const Plane& plane,
                            const std::vector<mesh::FaceHandle>& faces);

/// Plans the slice that cuts the loops through the given crossing faces (used by the slab).
CutStatus plan_from_faces(ContextState& s, const Plane& plane,
                          const std::vector<mesh::FaceHandle>& faces);

/// Plans the loops through `faces` and every loop nested inside one of them (a slab wall: the
/// loops that bound one slab component, with the canal loops inside them).
CutStatus plan_wall(ContextState& s, const Plane& plane,
                    const std::vector<mesh::FaceHandle>& faces);

/// Smallest triangle a cut may create (split parts and cap triangles), relative to the squared
/// mesh scale: the project's one degenerate threshold (mesh::kDegenerateTwiceAreaRelative is
/// twice the area) with a factor 2 of margin, so that validate() never counts a triangle a cut
/// made in double. Float32 rounding of a file can take more than that margin from a small
/// triangle (a 1 um cap triangle 9 nm high, 50 mm from the origin, lost 79 % of its area), so
/// ContextState::too_small() adds a rounding bound that grows with the triangle's size.
inline constexpr double kMinTriangleRelativeArea = mesh::kDegenerateTwiceAreaRelative;

/// Checks that splitting every face the selected loops cross leaves no triangle smaller than
/// kMinTriangleRelativeArea (either diagonal OpenMesh may choose for the quad part): a plane a
/// little beyond the tolerance from a vertex (the tiny corner its two crossing edges cut off) or
/// from a vertex of an already thin triangle (the band an earlier cut left just above a vertex
/// ring) would otherwise leave a sliver. kSliverSplit if not, with the corner nearest the plane of
/// every such face proposed for snapping (s.snap_candidates). O(points in the selected loops).
CutStatus check_split_areas(ContextState& s, const Plane& plane);

/// Proposes the vertex of `vertices` nearest the plane for snapping (s.snap_candidates) when it
/// lies beyond the tolerance and within kSnapTolerances tolerances.
void propose_snap(ContextState& s, const Plane& plane,
                  std::span<const mesh::VertexHandle> vertices);

/// Drops from the selected loops every edge cut point within tol of the point before it (or, for
/// an on-plane vertex after an edge point, the edge point: the existing vertex is reused), when
/// the collapse that follows the split is topologically safe; three edge points in a row within
/// tol merge both ends into the middle one (a kept point takes one merge from each side); loops
/// keep at least 3 points. So a cut never makes two vertices within tol of each other that
/// float32 files would merge (two limbs of a chevron meeting on thin cap triangles). O(points).
void merge_close_points(ContextState& s);

/// Checks the split parts round every merged point (merge_close_points) where the collapse leaves
/// them: each corner at the point it merges into. A merge moves a split vertex up to tol, and a
/// part that was thin before (a thin triangle of an earlier cap, split near its long edge) can be
/// left of zero area or flipped (2 of 12 random 60-cut sequences, issue 10 item 3). kSliverSplit if
/// so, with the corner nearest the plane of each such face proposed for snapping. O(merged points
/// + points in the selected loops × log) when anything merged, else O(1).
CutStatus check_merged_split_areas(ContextState& s, const Plane& plane);

/// What every plan needs before its edit: check_split_areas(), merge_close_points(),
/// check_merged_split_areas(), then plan_caps(). Each status is returned as is.
CutStatus finish_plan(ContextState& s, const Plane& plane);

/// Makes a plan with `plan()` (plan_full, plan_localised, plan_wall: it fills s.plan) and finishes
/// it (finish_plan), treating the vertices in `snapped` (sorted) as on the plane. When the plan is
/// refused for a sliver (a split part, or a cap triangle among cut points clustered round a
/// vertex just beyond the tolerance) and the checks proposed vertices within kSnapTolerances
/// tolerances of the plane, those join `snapped` and the plan is made again, at most
/// kMaxSnapRounds times. A snapped vertex is not moved: it becomes a rim vertex where it is, as
/// on-plane vertices do, so rims lie within kSnapTolerances tolerances of the plane (within one
/// tolerance when nothing was snapped) and every volume is conserved exactly. A plan still
/// refused for a split part is then, when `merges_first_last`, made once more with the merges of
/// close points before the split check (merge_close_points, then check_split_areas on the loops
/// they leave, then check_merged_split_areas): a needle of an earlier cap thinner than tol puts
/// two cut points within tol of each other, and the part between them goes with their merge.
/// Every plan that passed before passes the same way. `planned` (optional): the status of a
/// plan() just made with these `snapped` vertices, which the first round then uses as it is.
inline constexpr int kMaxSnapRounds = 8;
CutStatus plan_snapped(ContextState& s, const Plane& plane, std::vector<std::int32_t>& snapped,
                       const std::function<CutStatus()>& plan, bool merges_first_last = true,
                       const CutStatus* planned = nullptr);

/// Triangulates the selected loops into plan.cap_triangles, counter-clockwise about the normal
/// (kCapTriangulationFailed if a loop cannot be capped without slivers or tilted triangles).
CutStatus plan_caps(ContextState& s, const Plane& plane);

/// Whether loop `inner` lies inside loop `outer` (a majority of up to 9 of its points does);
/// remembered in plan.nesting.
bool loop_nested(const SectionPlan& plan, const PlanLoop& inner, const PlanLoop& outer);

/// Closest distance from `p` to triangle `f`, m.
double distance_to_face(const mesh::TriMesh& m, mesh::FaceHandle f, const Vec3& p);

}  // namespace kerf::cut::detail
