// kerf::cut::CutSession — the rules that turn a stream of blade events into mesh edits, in one
// place, so that the display process, the CLI and the tests are thin callers of the same code.
//
//   CutSession session(std::move(scene_mesh));   // bodies = connected pieces (+ their cavities)
//   session.begin(cut_begin);                     // localised uniplanar slice: nothing visible yet
//   session.progress(cut_progress);               // the swept region of the kerf opens
//   session.end(cut_end);                         // completed: kerf fully open, pieces -> bodies
//   session.move_body(body_moved);                // a body's rigid pose
//   session.idle();                               // between events: grow capacity ahead of cuts
//   session.hash();                               // same scene + same ordered events => same hash
//
// Frames. Mesh coordinates are each body's own frame: every body starts at the identity pose, a
// severed piece starts with its parent's pose (its vertices stay where they were), and BodyMoved
// replaces a pose. Event geometry is in the world frame; the session maps it into the body's
// frame, and maps the blade's (u, v) frame (events: u = blade length axis) onto the frame Plane
// derives from the normal by converting the swept rectangle's corners point by point.
//
// Seeds. A CutBegin's seed lies on the named body (a piece nearer to it is not cut), within the
// library's seed tolerance plus half the widest withdrawn kerf so far: kerf-rt finds it on the
// collision mesh, which has withdrawn kerfs closed where this mesh has them open.
//
// Rules. One cut is open at a time: a CutBegin while one is open first ends that one as withdrawn.
// A refused slice (a CutStatus) leaves the mesh unchanged and no cut open; progress or end for a
// cut that is not open is ignored. Both are counted, never fatal. Completed: the separation is
// swept to the end (gap = kerf: the biplanar result, see separate.hpp) and the pieces cut free
// (PieceFinder) become new bodies with ids bodies().size(), ... in the order they closed; when
// every piece closed, the largest keeps the parent's id. Withdrawn or aborted: the slice and the
// separation so far stay; where the blade never went (rim points outside every swept rectangle)
// the bone is whole, so the session glues the two copies of those rim vertices and the sides
// stay one body. After every CutEnd, whatever its kind, the pieces the cut bounds are searched
// across cuts and glue alike (PieceFinder with the session's glue), so two partial cuts that
// meet inside the bone and together sever a piece (a chevron's limbs, each withdrawn once the
// blade reached the other) free it: one new body. Normals of faces the separation moved are
// refreshed. Not thread-safe: one thread applies events (the display's worker).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "display/cut/components.hpp"
#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"
#include "display/cut/session_changes.hpp"
#include "display/cut/session_events.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

inline constexpr std::uint32_t kNoBody = 0xFFFFFFFFu;

/// Spare faces idle() keeps ahead of the cuts (a cut on a bone adds a few thousand).
inline constexpr std::size_t kMinSpareFaces = 1u << 16;

/// One rigid body of the scene.
struct SessionBody {
    std::uint32_t id = 0;              ///< index in CutSession::bodies()
    RigidPose pose;                    ///< world from body
    std::uint32_t parent = kNoBody;    ///< body it was severed from (kNoBody for scene bodies)
    std::uint32_t severed_by_cut = 0;  ///< cut id that severed it (0 for scene bodies)
};

/// A cut that ended withdrawn or aborted, as it was when it ended.
struct WithdrawnCut {
    Plane plane;                 ///< its plane, mesh coordinates (the cut body's frame)
    double kerf_m = 0;           ///< the blade's kerf width (CutBegin)
    std::uint32_t body = 0;      ///< the body it cut
    std::size_t first_pair = 0;  ///< its first rim pair in CutSession::withdrawn_rim_pairs()
    std::size_t pair_count = 0;  ///< its rim pairs
};

/// What one event did.
enum class EventOutcome : std::uint8_t {
    kApplied,  ///< the mesh, a body or the open cut changed
    kRefused,  ///< invalid event or a cut the geometry refused (`status`); nothing changed
    kIgnored,  ///< nothing to do (no open cut with that id, an empty swept region)
};
std::string_view to_string(EventOutcome outcome) noexcept;

struct ApplyReport {
    EventOutcome outcome = EventOutcome::kIgnored;
    CutStatus status = CutStatus::kOk;  ///< the slice's status when refused by the geometry
    const char* why = "";               ///< one static line when refused or ignored
    std::uint32_t bodies_created = 0;   ///< pieces that became bodies (completed cuts)
    std::uint32_t vertices_moved = 0;   ///< by the separation
    std::int64_t time_ns = 0;           ///< wall time of the edit
    CutStats slice;                     ///< begin: what the slice made
};

/// Events applied so far, by outcome.
struct SessionCounters {
    std::uint64_t applied = 0;
    std::uint64_t refused = 0;
    std::uint64_t ignored = 0;
    std::uint64_t cuts_completed = 0;
    std::uint64_t capacity_grown = 0;  ///< idle() growth steps
};

class CutSession {
public:
    /// Takes the scene (vertices in the world frame) and finds its bodies: connected pieces,
    /// cavities joined to the piece around them (group_cavities), ordered by lowest face. O(n).
    /// The mesh is used where it lives: no copy (OpenMesh meshes have no move constructor, so
    /// moving a TriMesh copies it: a 1M-triangle scene is 136 MiB).
    explicit CutSession(std::unique_ptr<mesh::TriMesh> scene);
    /// The same from a mesh value: one copy of it (to the heap).
    explicit CutSession(const mesh::TriMesh& scene);
    ~CutSession();
    CutSession(CutSession&&) noexcept;
    CutSession& operator=(CutSession&&) noexcept;

    ApplyReport begin(const CutBegin& event);        ///< localised uniplanar slice
    ApplyReport progress(const CutProgress& event);  ///< opens the kerf over the swept region
    ApplyReport end(const CutEnd& event);            ///< completes or leaves the open cut
    ApplyReport move_body(const BodyMoved& event);   ///< replaces a body's pose

    /// Between events: one bounded step of capacity growth (CutContext::grow_step: one element
    /// kind, when its headroom runs below half of an eighth of the mesh, at least
    /// `min_spare_faces` faces), so a cut never has to grow. Returns true when it grew.
    bool idle(std::size_t min_spare_faces = kMinSpareFaces);

    /// Fingerprint of the mesh (mesh_hash), every face's body and every body's pose and parent.
    std::uint64_t hash() const;

    const mesh::TriMesh& mesh() const noexcept;
    std::span<const SessionBody> bodies() const noexcept;
    std::uint32_t body_of(mesh::FaceHandle face) const noexcept;      ///< kNoBody if out of range
    std::uint32_t body_of(mesh::VertexHandle vertex) const noexcept;  ///< kNoBody if out of range
    /// The body owning the vertex nearest to `world_point_m` (kNoBody for an empty mesh). O(V):
    /// for tools and tests that have a point and no body id.
    std::uint32_t body_at(const Vec3& world_point_m) const noexcept;
    bool cut_open() const noexcept;
    std::uint32_t open_cut_id() const noexcept;  ///< valid when cut_open()
    const SessionCounters& counters() const noexcept;
    /// The withdrawn and aborted cuts so far, in order. Their caps stay separated where the blade
    /// swept, and with rim-only caps that opening runs as thin wedges across the whole section:
    /// the collision export closes them (see collision_export.hpp).
    std::span<const WithdrawnCut> withdrawn_cuts() const noexcept;
    /// The two copies of every rim point of those cuts, swept or not (a = positive side,
    /// b = negative side), each cut's as WithdrawnCut::first_pair, pair_count say.
    std::span<const Glue> withdrawn_rim_pairs() const noexcept;

    /// True when something changed since the last take_changes().
    bool has_changes() const noexcept;
    /// Moves the changes since the last call into `out` (vertex and face index ranges to upload,
    /// poses) and starts collecting afresh. The first call after construction reports everything.
    void take_changes(SessionChanges& out);

    /// Ends the session and hands the mesh back, without the session's properties: as it lives
    /// (no copy), or as a value (one copy).
    std::unique_ptr<mesh::TriMesh> release_owned() &&;
    mesh::TriMesh release() &&;

private:
    struct State;
    std::unique_ptr<State> s_;
};

}  // namespace kerf::cut
