#include "display/cut/cut_session.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <optional>

#include "config/base/check.hpp"
#include "display/cut/components.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/cross_section.hpp"
#include "display/cut/cut_context.hpp"
#include "display/cut/mesh_hash.hpp"
#include "display/cut/seed.hpp"
#include "display/cut/separate.hpp"
#include "display/cut/slice_by_plane.hpp"

namespace kerf::cut {
namespace {

constexpr double kMaxPoseNormError = 1e-3;  // |q| may differ from 1 by this much (then normalised)

std::int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

bool finite(const Vec3& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    return h * 0xBF58476D1CE4E5B9ull;
}

std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d); }

ApplyReport refused(const char* why, CutStatus status = CutStatus::kInvalidArgument) {
    return ApplyReport{EventOutcome::kRefused, status, why, 0, 0, 0, {}};
}
ApplyReport ignored(const char* why) {
    return ApplyReport{EventOutcome::kIgnored, CutStatus::kOk, why, 0, 0, 0, {}};
}

}  // namespace

std::string_view to_string(EventOutcome outcome) noexcept {
    switch (outcome) {
        case EventOutcome::kApplied:
            return "applied";
        case EventOutcome::kRefused:
            return "refused";
        case EventOutcome::kIgnored:
            return "ignored";
    }
    return "unknown";
}

/// The cut between its CutBegin and its CutEnd.
struct OpenCut {
    std::uint32_t id = 0;
    std::uint32_t body = 0;
    CrossSection section;
    std::optional<Separator> separator;
    std::vector<std::uint8_t> rim_swept;  ///< per rim point (loops concatenated): blade went there
    double kerf_m = 0;                    ///< the blade's kerf width (CutBegin)
};

namespace {

// Marks the rim points inside the swept rectangle `quad` (plane coordinates, either orientation,
// grown by `tol`) as swept. O(rim points).
void mark_swept(OpenCut& cut, const Vec2 (&quad)[4], double tol) {
    double area = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec2 &p = quad[i], &q = quad[(i + 1) % 4];
        area += p[0] * q[1] - p[1] * q[0];
    }
    if (!(std::abs(area) > 0)) return;  // empty or non-finite
    const double sign = area > 0 ? 1.0 : -1.0;
    std::size_t k = 0;
    for (const auto& loop : cut.section.loops_2d)
        for (const Vec2& x : loop) {
            bool inside = true;
            for (int i = 0; i < 4 && inside; ++i) {
                const Vec2 &p = quad[i], &q = quad[(i + 1) % 4];
                const Vec2 edge = q - p;
                const double cross = edge[0] * (x[1] - p[1]) - edge[1] * (x[0] - p[0]);
                inside = sign * cross >= -tol * edge.norm();
            }
            if (inside) cut.rim_swept[k] = 1;
            ++k;
        }
}

}  // namespace

struct CutSession::State {
    std::unique_ptr<mesh::TriMesh> owned;  // never null while the session lives
    mesh::TriMesh& mesh;
    OpenMesh::FPropHandleT<std::uint32_t> face_body;
    OpenMesh::VPropHandleT<std::uint32_t> vertex_body;
    std::unique_ptr<CutContext> ctx;
    std::unique_ptr<PieceFinder> finder;
    std::vector<SessionBody> bodies;
    std::optional<OpenCut> open;
    SessionCounters counters;
    // Rim vertex pairs of partial cuts where the blade never went: the material there is whole,
    // so the pieces on both sides are one (sorted, both ways; see PieceFinder).
    std::vector<Glue> glue;
    // Withdrawn or aborted cuts and both copies of each of their rim points, swept or not (one
    // way, in cut order): what the collision export closes (withdrawn_cuts()).
    std::vector<WithdrawnCut> withdrawn;
    std::vector<Glue> withdrawn_pairs;
    double withdrawn_kerf_max_m = 0;  // the widest kerf among them

    // Body-local triangle numbering (what the collision mesh publishes), built when needed.
    std::vector<std::vector<mesh::FaceHandle>> body_faces;
    bool body_faces_stale = true;

    // Changes since the last take.
    bool everything = true;
    bool poses = false;
    bool bodies_changed = true;
    std::vector<std::uint32_t> dirty_vertices;
    std::vector<std::uint32_t> dirty_faces;

    explicit State(std::unique_ptr<mesh::TriMesh> scene) : owned(std::move(scene)), mesh(*owned) {}

    void find_scene_bodies();
    void mark_new_elements(std::size_t old_vertices, std::size_t old_faces, std::uint32_t body);
    void mark_around(std::span<const mesh::VertexHandle> vertices, bool refresh_normals);
    void mark_section(const CrossSection& cs);
    std::uint32_t sever(const OpenCut& cut);
    void glue_unswept(const OpenCut& cut);
    void relabel(const Body& piece, std::uint32_t body);
    mesh::FaceHandle hinted_face(std::uint32_t body, std::int64_t hint);
    void close_open_cut(CutEndKind kind, ApplyReport& report);
};

void CutSession::State::find_scene_bodies() {
    const std::vector<Body> pieces = group_cavities(find_components(mesh));
    for (const Body& piece : pieces) {
        const auto id = static_cast<std::uint32_t>(bodies.size());
        bodies.push_back(SessionBody{id, RigidPose{}, kNoBody, 0});
        relabel(piece, id);
    }
}

void CutSession::State::relabel(const Body& piece, std::uint32_t body) {
    for (const auto f : piece.faces) mesh.property(face_body, f) = body;
    for (const auto v : piece.vertices) mesh.property(vertex_body, v) = body;
}

void CutSession::State::mark_new_elements(std::size_t old_vertices, std::size_t old_faces,
                                          std::uint32_t body) {
    for (std::size_t i = old_vertices; i < mesh.n_vertices(); ++i) {
        mesh.property(vertex_body, mesh::VertexHandle(static_cast<int>(i))) = body;
        dirty_vertices.push_back(static_cast<std::uint32_t>(i));
    }
    for (std::size_t i = old_faces; i < mesh.n_faces(); ++i) {
        mesh.property(face_body, mesh::FaceHandle(static_cast<int>(i))) = body;
        dirty_faces.push_back(static_cast<std::uint32_t>(i));
    }
}

void CutSession::State::mark_around(std::span<const mesh::VertexHandle> vertices,
                                    bool refresh_normals) {
    for (const auto v : vertices) {
        dirty_vertices.push_back(static_cast<std::uint32_t>(v.idx()));
        for (const auto f : mesh.vf_range(v)) {
            if (refresh_normals) mesh.set_normal(f, mesh.calc_face_normal(f));
            dirty_faces.push_back(static_cast<std::uint32_t>(f.idx()));
        }
    }
}

void CutSession::State::mark_section(const CrossSection& cs) {
    for (const auto* side : {&cs.positive, &cs.negative}) {
        for (const auto& loop : side->loops) mark_around(loop, false);
        for (const auto f : side->cap_faces)
            dirty_faces.push_back(static_cast<std::uint32_t>(f.idx()));
    }
}

mesh::FaceHandle CutSession::State::hinted_face(std::uint32_t body, std::int64_t hint) {
    if (hint < 0) return mesh::FaceHandle();
    if (body_faces_stale) {
        body_faces.assign(bodies.size(), {});
        for (const auto f : mesh.faces()) {
            const std::uint32_t b = mesh.property(face_body, f);
            if (b < body_faces.size()) body_faces[b].push_back(f);
        }
        body_faces_stale = false;
    }
    const auto& faces = body_faces[body];
    return static_cast<std::uint64_t>(hint) < faces.size() ? faces[static_cast<std::size_t>(hint)]
                                                           : mesh::FaceHandle();
}

void CutSession::State::glue_unswept(const OpenCut& cut) {
    const CrossSection& cs = cut.section;
    std::size_t k = 0;
    for (std::size_t i = 0; i < cs.positive.loops.size(); ++i)
        for (std::size_t j = 0; j < cs.positive.loops[i].size(); ++j, ++k) {
            if (cut.rim_swept[k] != 0) continue;
            glue.push_back(Glue{cs.positive.loops[i][j], cs.negative.loops[i][j]});
            glue.push_back(Glue{cs.negative.loops[i][j], cs.positive.loops[i][j]});
        }
    std::sort(glue.begin(), glue.end());
}

std::uint32_t CutSession::State::sever(const OpenCut& cut) {
    SeverReport report = finder->find_pieces(cut.section, glue);
    if (report.severed.empty()) return 0;
    std::size_t keep = report.severed.size();  // index of the piece that keeps the parent's id
    const bool remainder_open =
        std::any_of(report.piece_of_seed.begin(), report.piece_of_seed.end(),
                    [](std::uint32_t p) { return p == SeverReport::kRemainder; });
    if (!remainder_open) {
        keep = 0;
        for (std::size_t i = 1; i < report.severed.size(); ++i) {
            if (report.severed[i].volume_m3 > report.severed[keep].volume_m3) keep = i;
        }
    }
    std::uint32_t created = 0;
    const RigidPose pose = bodies[cut.body].pose;
    for (std::size_t i = 0; i < report.severed.size(); ++i) {
        if (i == keep) continue;
        const auto id = static_cast<std::uint32_t>(bodies.size());
        bodies.push_back(SessionBody{id, pose, cut.body, cut.id});
        relabel(report.severed[i], id);
        for (const auto v : report.severed[i].vertices)
            dirty_vertices.push_back(static_cast<std::uint32_t>(v.idx()));
        for (const auto f : report.severed[i].faces)
            dirty_faces.push_back(static_cast<std::uint32_t>(f.idx()));
        ++created;
    }
    body_faces_stale = true;
    bodies_changed = true;
    return created;
}

void CutSession::State::close_open_cut(CutEndKind kind, ApplyReport& report) {
    OpenCut& cut = *open;
    if (kind == CutEndKind::kCompleted) {
        if (cut.separator) {
            cut.separator->sweep_all();
            const auto moved = cut.separator->moved_vertices();
            mark_around(moved, true);
            report.vertices_moved = static_cast<std::uint32_t>(moved.size());
        }
        ++counters.cuts_completed;
    } else {
        glue_unswept(cut);  // withdrawn or aborted: where the blade never went, the bone is whole
        const CrossSection& cs = cut.section;
        WithdrawnCut closed{cs.plane, cut.kerf_m, cut.body, withdrawn_pairs.size(), 0};
        for (std::size_t i = 0; i < cs.positive.loops.size(); ++i)
            for (std::size_t j = 0; j < cs.positive.loops[i].size(); ++j)
                withdrawn_pairs.push_back(Glue{cs.positive.loops[i][j], cs.negative.loops[i][j]});
        closed.pair_count = withdrawn_pairs.size() - closed.first_pair;
        withdrawn.push_back(closed);
        withdrawn_kerf_max_m = std::max(withdrawn_kerf_max_m, cut.kerf_m);
    }
    // Pieces bounded by this cut and earlier partial ones (a chevron's two limbs) come free too.
    report.bodies_created = sever(cut);
    open.reset();
}

CutSession::CutSession(const mesh::TriMesh& scene)
    : CutSession(std::make_unique<mesh::TriMesh>(scene)) {}

CutSession::CutSession(std::unique_ptr<mesh::TriMesh> scene) {
    KERF_ENFORCE(scene != nullptr, "CutSession needs a mesh");
    s_ = std::make_unique<State>(std::move(scene));
    State& s = *s_;
    s.mesh.add_property(s.face_body, "kerf:body");
    s.mesh.add_property(s.vertex_body, "kerf:vertex_body");
    for (const auto f : s.mesh.all_faces()) s.mesh.property(s.face_body, f) = kNoBody;
    for (const auto v : s.mesh.all_vertices()) s.mesh.property(s.vertex_body, v) = kNoBody;
    s.find_scene_bodies();
    s.ctx = std::make_unique<CutContext>(s.mesh);
    s.finder = std::make_unique<PieceFinder>(s.mesh);
}

CutSession::~CutSession() = default;
CutSession::CutSession(CutSession&&) noexcept = default;
CutSession& CutSession::operator=(CutSession&&) noexcept = default;

ApplyReport CutSession::begin(const CutBegin& e) {
    State& s = *s_;
    ApplyReport report;
    if (s.open) s.close_open_cut(CutEndKind::kWithdrawn, report);
    if (e.body_id >= s.bodies.size()) return ++s.counters.refused, refused("no such body");
    if (!(std::isfinite(e.kerf_width_m) && e.kerf_width_m >= 0.0))
        return ++s.counters.refused, refused("kerf width negative or not finite");
    if (!finite(e.blade.point_m) || !finite(e.blade.normal) || !finite(e.seed_m))
        return ++s.counters.refused, refused("non-finite plane or seed");
    const RigidPose& pose = s.bodies[e.body_id].pose;
    auto plane = Plane::make(pose.to_body(e.blade.point_m), pose.direction_to_body(e.blade.normal));
    if (!plane) return ++s.counters.refused, refused("zero plane normal", plane.error());

    const std::int64_t t0 = now_ns();
    const std::size_t old_vertices = s.mesh.n_vertices(), old_faces = s.mesh.n_faces();
    OpenCut cut{e.cut_id, e.body_id, {}, std::nullopt, {}, e.kerf_width_m};
    // kerf-rt finds the seed on the collision mesh, where the export closes withdrawn cuts: it
    // moves vertices by up to half a kerf from where this mesh has them (the opened kerf), so a
    // blade entering an earlier withdrawn kerf touches a point up to that far from this surface.
    const double seed_tolerance_m =
        kSeedRelativeTolerance * s.ctx->scale_m() + 0.5 * s.withdrawn_kerf_max_m;
    Seed seed{
        pose.to_body(e.seed_m), s.hinted_face(e.body_id, e.triangle_hint), seed_tolerance_m, {}};
    // The seed lies on the body being cut: a piece freed nearby (in the kerf) may be nearer.
    if (s.bodies.size() > 1)
        seed.accepts = [&s, body = e.body_id](mesh::FaceHandle f) {
            return s.mesh.property(s.face_body, f) == body;
        };
    // Chords into earlier caps (cap_chords.hpp) only while no cut was withdrawn: a withdrawn
    // cut's caps were opened part way by the separation (their corners moved off the plane, the
    // rim held glued), and chords flipped into them folded the opened walls through each other
    // (WithdrawnCutProbe.TheSequencesThatOpenCleanlyStayClean: faces crossed after 19 of 84 cuts).
    // The guard is here, not in cap_chords' own checks: refusing chords only where a crossed quad
    // has a corner more than 32 tol off its cap's plane left the 19 crossings as they were.
    s.ctx->state().cap_chords = s.withdrawn.empty();
    const CutResult r = slice_by_plane(*s.ctx, *plane, seed, cut.section);
    if (!r.ok()) return ++s.counters.refused, refused("slice refused", r.status);

    for (const auto& loop : cut.section.positive.loops)
        cut.rim_swept.resize(cut.rim_swept.size() + loop.size(), 0);
    s.mark_new_elements(old_vertices, old_faces, e.body_id);
    s.mark_section(cut.section);
    s.body_faces_stale = true;
    if (e.kerf_width_m > 0.0) {
        auto separator = Separator::make(*s.ctx, cut.section, e.kerf_width_m);
        if (separator) {
            // An earlier withdrawn cut this one reaches may be sliced on one side only (the
            // localised slice follows one loop): neither of its sides may pass through the other.
            const double grow = e.kerf_width_m + s.withdrawn_kerf_max_m;
            for (const WithdrawnCut& w : s.withdrawn) {
                Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
                for (std::size_t i = w.first_pair; i < w.first_pair + w.pair_count; ++i)
                    for (const auto v : {s.withdrawn_pairs[i].a, s.withdrawn_pairs[i].b}) {
                        lo.minimize(s.mesh.point(v));
                        hi.maximize(s.mesh.point(v));
                    }
                if (w.pair_count == 0) continue;
                separator->keep_off(w.plane, lo - Vec3(grow, grow, grow),
                                    hi + Vec3(grow, grow, grow));
            }
            cut.separator.emplace(std::move(*separator));
        }
    }
    s.open.emplace(std::move(cut));
    ++s.counters.applied;
    report.outcome = EventOutcome::kApplied;
    report.time_ns = now_ns() - t0;
    report.slice = r.stats;
    return report;
}

ApplyReport CutSession::progress(const CutProgress& e) {
    State& s = *s_;
    if (!s.open || s.open->id != e.cut_id) return ++s.counters.ignored, ignored("no such open cut");
    const std::int64_t t0 = now_ns();
    // The swept rectangle's corners, blade frame -> body frame -> the locked Plane's (u, v).
    const RigidPose& pose = s.bodies[s.open->body].pose;
    const Plane& plane = s.open->section.plane;
    const Vec3 n = plane.normal();
    Vec3 u = pose.direction_to_body(e.blade.u);
    u -= n * OpenMesh::dot(u, n);
    if (!finite(u) || !finite(e.blade.point_m) || u.norm() < 1e-6)
        return ++s.counters.refused, refused("blade axis not in the cut plane");
    u /= u.norm();
    const Vec3 v = OpenMesh::cross(n, u);
    const Vec3 origin = pose.to_body(e.blade.point_m);
    const SweptRect& r = e.swept;
    const double us[4] = {r.u_min_m, r.u_max_m, r.u_max_m, r.u_min_m};
    const double vs[4] = {r.v_min_m, r.v_min_m, r.v_max_m, r.v_max_m};
    Vec2 polygon[4];
    for (int i = 0; i < 4; ++i) polygon[i] = plane.to_2d(origin + u * us[i] + v * vs[i]);
    mark_swept(*s.open, polygon, s.ctx->tolerance_m());
    if (!s.open->separator) return ++s.counters.ignored, ignored("cut has no separation");
    if (!s.open->separator->sweep(polygon))
        return ++s.counters.ignored, ignored("empty or non-finite swept region");
    const auto moved = s.open->separator->moved_vertices();
    s.mark_around(moved, true);
    ++s.counters.applied;
    ApplyReport report;
    report.outcome = EventOutcome::kApplied;
    report.vertices_moved = static_cast<std::uint32_t>(moved.size());
    report.time_ns = now_ns() - t0;
    return report;
}

ApplyReport CutSession::end(const CutEnd& e) {
    State& s = *s_;
    if (!s.open || s.open->id != e.cut_id) return ++s.counters.ignored, ignored("no such open cut");
    const std::int64_t t0 = now_ns();
    ApplyReport report;
    s.close_open_cut(e.kind, report);
    ++s.counters.applied;
    report.outcome = EventOutcome::kApplied;
    report.time_ns = now_ns() - t0;
    return report;
}

ApplyReport CutSession::move_body(const BodyMoved& e) {
    State& s = *s_;
    if (e.body_id >= s.bodies.size()) return ++s.counters.refused, refused("no such body");
    auto q = e.pose.orientation_wxyz;
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!finite(e.pose.position_m) || !std::isfinite(norm) ||
        std::abs(norm - 1.0) > kMaxPoseNormError)
        return ++s.counters.refused, refused("pose not finite or not a unit quaternion");
    for (double& c : q) c /= norm;
    s.bodies[e.body_id].pose = RigidPose{e.pose.position_m, q};
    s.poses = true;
    ++s.counters.applied;
    ApplyReport report;
    report.outcome = EventOutcome::kApplied;
    return report;
}

bool CutSession::idle(std::size_t min_spare_faces) {
    if (!s_->ctx->grow_step(min_spare_faces)) return false;
    ++s_->counters.capacity_grown;
    return true;
}

std::uint64_t CutSession::hash() const {
    const State& s = *s_;
    std::uint64_t h = mix(0x6B657266ull, mesh_hash(s.mesh));
    h = mix(h, s.bodies.size());
    for (const SessionBody& b : s.bodies) {
        for (int i = 0; i < 3; ++i) h = mix(h, bits(b.pose.position_m[i]));
        for (const double c : b.pose.orientation_wxyz) h = mix(h, bits(c));
        h = mix(h, (std::uint64_t{b.parent} << 32) | b.severed_by_cut);
    }
    for (const auto f : s.mesh.faces()) h = mix(h, s.mesh.property(s.face_body, f));
    return h;
}

const mesh::TriMesh& CutSession::mesh() const noexcept { return s_->mesh; }
std::span<const SessionBody> CutSession::bodies() const noexcept { return s_->bodies; }

std::uint32_t CutSession::body_of(mesh::FaceHandle f) const noexcept {
    if (!f.is_valid() || static_cast<std::size_t>(f.idx()) >= s_->mesh.n_faces()) return kNoBody;
    return s_->mesh.property(s_->face_body, f);
}

std::uint32_t CutSession::body_of(mesh::VertexHandle v) const noexcept {
    if (!v.is_valid() || static_cast<std::size_t>(v.idx()) >= s_->mesh.n_vertices()) return kNoBody;
    return s_->mesh.property(s_->vertex_body, v);
}

std::uint32_t CutSession::body_at(const Vec3& p) const noexcept {
    const State& s = *s_;
    double best = 1e300;
    std::uint32_t body = kNoBody;
    // Every body at rest (a fresh session, `kerf cut`): R q + t is q itself there, bit for bit
    // where q is finite (1 x + 0 y + 0 z + 0), and a vertex with a non-finite coordinate is never
    // the nearest either way; so the scan skips the pose, whose rotation matrix to_world builds
    // from the quaternion per vertex (most of this O(V) scan).
    const bool at_rest = std::all_of(s.bodies.begin(), s.bodies.end(), [](const SessionBody& b) {
        const auto& q = b.pose.orientation_wxyz;
        return b.pose.position_m == Vec3(0.0, 0.0, 0.0) && q[0] == 1.0 && q[1] == 0.0 &&
               q[2] == 0.0 && q[3] == 0.0;
    });
    const auto nearest = [&](auto&& position) {
        for (const auto v : s.mesh.vertices()) {
            const std::uint32_t b = s.mesh.property(s.vertex_body, v);
            if (b >= s.bodies.size()) continue;
            const double d = (position(b, s.mesh.point(v)) - p).sqrnorm();
            if (d < best) {
                best = d;
                body = b;
            }
        }
        return body;
    };
    if (at_rest) return nearest([](std::uint32_t, const Vec3& q) { return q; });
    return nearest([&](std::uint32_t b, const Vec3& q) { return s.bodies[b].pose.to_world(q); });
}

std::unique_ptr<mesh::TriMesh> CutSession::release_owned() && {
    State& s = *s_;
    s.open.reset();
    s.finder.reset();
    s.ctx.reset();
    s.mesh.remove_property(s.face_body);
    s.mesh.remove_property(s.vertex_body);
    std::unique_ptr<mesh::TriMesh> out = std::move(s.owned);
    s_.reset();
    return out;
}

mesh::TriMesh CutSession::release() && { return *std::move(*this).release_owned(); }

bool CutSession::cut_open() const noexcept { return s_->open.has_value(); }
std::uint32_t CutSession::open_cut_id() const noexcept { return s_->open ? s_->open->id : 0; }
const SessionCounters& CutSession::counters() const noexcept { return s_->counters; }
std::span<const WithdrawnCut> CutSession::withdrawn_cuts() const noexcept { return s_->withdrawn; }
std::span<const Glue> CutSession::withdrawn_rim_pairs() const noexcept {
    return s_->withdrawn_pairs;
}

bool CutSession::has_changes() const noexcept {
    const State& s = *s_;
    return s.everything || s.poses || s.bodies_changed || !s.dirty_vertices.empty() ||
           !s.dirty_faces.empty();
}

void CutSession::take_changes(SessionChanges& out) {
    State& s = *s_;
    out.everything = s.everything;
    out.poses = s.poses;
    out.bodies = s.bodies_changed;
    out.vertex_count = static_cast<std::uint32_t>(s.mesh.n_vertices());
    out.face_count = static_cast<std::uint32_t>(s.mesh.n_faces());
    to_ranges(s.dirty_vertices, kRangeMergeGap, out.vertices);
    to_ranges(s.dirty_faces, kRangeMergeGap, out.faces);
    s.dirty_vertices.clear();
    s.dirty_faces.clear();
    s.everything = s.poses = s.bodies_changed = false;
}

}  // namespace kerf::cut
