#include "tools/kerf/demo_replay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <optional>

#include "display/app/render_sync.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/app/session_events_ipc.hpp"
#include "display/cut/cut_session.hpp"
#include "display/egl/egl_output.hpp"
#include "display/render/camera.hpp"
#include "display/render/renderer.hpp"
#include "rt_core/ipc/journal_reader.hpp"

namespace kerf::cli {
namespace {

/// Signed volume of every body (divergence theorem over its faces), m^3.
std::map<std::uint32_t, double> body_volumes(const cut::CutSession& session) {
    std::map<std::uint32_t, double> out;
    const mesh::TriMesh& m = session.mesh();
    for (const auto f : m.faces()) {
        if (m.has_face_status() && m.status(f).deleted()) continue;
        mesh::Point p[3];
        int k = 0;
        for (const auto v : m.fv_range(f)) {
            if (k < 3) p[k] = m.point(v);
            ++k;
        }
        if (k != 3) continue;
        out[session.body_of(f)] += OpenMesh::dot(p[0], OpenMesh::cross(p[1], p[2])) / 6.0;
    }
    return out;
}

/// The headless renderer and the camera the pictures share.
struct Pictures {
    std::optional<egl::EglOutput> output;
    std::optional<render::Renderer> renderer;
    display::RenderSync sync;
    std::optional<render::Camera> camera;
    std::optional<mesh::Point> focus;
    std::size_t bodies_at_start = 0;  ///< the scene's bodies: more later means a piece came free

    Result<bool, std::string> open() {
        auto out = egl::EglOutput::create({});
        if (!out) return Err{"headless EGL: " + out.error().message()};
        output.emplace(std::move(*out));
        auto r =
            render::Renderer::create({output->width(), output->height(), {0.10f, 0.12f, 0.15f}});
        if (!r) return Err{"renderer: " + r.error().message()};
        renderer.emplace(std::move(*r));
        return true;
    }

    /// The blade where the open cut's last record put it: the edge's centre on the swept
    /// region's front (the blade feeds along -v), edge along u, back along v, thickness along
    /// the plane normal (the tool frame of render::BladePose).
    static render::BladePose blade_of(const ipc::CutPayload& c) {
        const glm::dvec3 o(c.plane_point_m[0], c.plane_point_m[1], c.plane_point_m[2]);
        const glm::dvec3 u = glm::normalize(glm::dvec3(c.plane_u[0], c.plane_u[1], c.plane_u[2]));
        const glm::dvec3 n =
            glm::normalize(glm::dvec3(c.plane_normal[0], c.plane_normal[1], c.plane_normal[2]));
        const glm::dvec3 v = glm::cross(n, u);
        render::BladePose b;
        b.position_m = o + u * (0.5 * (double(c.swept_u_min_m) + double(c.swept_u_max_m))) +
                       v * double(c.swept_v_min_m);
        b.orientation = glm::quat_cast(glm::dmat3(u, v, n));
        b.length_m = c.blade_length_m;
        b.depth_m = c.blade_depth_m;
        b.thickness_m = c.kerf_width_m;
        b.visible = std::isfinite(glm::length(b.position_m));
        return b;
    }

    Result<bool, std::string> shoot(cut::CutSession& session, const ReplayShot& shot,
                                    const std::optional<ipc::CutPayload>& open_cut) {
        cut::SessionChanges changes;
        session.take_changes(changes);
        sync.apply(session, changes);
        auto& rm = sync.mesh();
        if (!rm) return Err{std::string("no mesh to draw")};
        renderer->upload(*rm);
        if (!camera) {
            camera = render::Camera::framing(sync.bounds_min(), sync.bounds_max());
            if (focus) {  // close on the cut
                camera->set_target(glm::dvec3((*focus)[0], (*focus)[1], (*focus)[2]));
                camera->zoom(0.3);
            }
        }
        for (int b = 0; b < render::kMaxBodies; ++b)
            renderer->set_body_transform(b, sync.transforms()[std::size_t(b)]);
        renderer->begin_frame(*camera);
        if (open_cut) renderer->draw_blade(blade_of(*open_cut));
        render::HudState hud;
        hud.backend = shot.caption;
        // A withdrawn limb of a chevron completes no cut, yet frees the head: count the bodies.
        const bool severed =
            session.counters().cuts_completed != 0 || session.bodies().size() > bodies_at_start;
        hud.cut_state = session.cut_open() ? "cutting" : severed ? "severed" : "idle";
        hud.device_state = "journal replay";
        hud.triangles = rm->triangle_count();
        if (open_cut) hud.cut_depth_mm = double(open_cut->feed_depth_m) * 1e3;
        renderer->draw_hud(hud);
        renderer->finish_frame();
        if (auto saved = renderer->save_png(shot.png.string()); !saved)
            return Err{shot.png.string() + ": " + saved.error().message()};
        return true;
    }
};

}  // namespace

std::string hash_hex(std::uint64_t hash) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash));
    return buf;
}

Result<ReplayResult, std::string> replay_journal(const config::Config& config,
                                                 const std::filesystem::path& journal,
                                                 std::vector<ReplayShot> shots,
                                                 std::optional<mesh::Point> focus) {
    auto reader = ipc::JournalReader::open(journal.string(), 0);
    if (!reader) return Err{reader.error().message()};
    auto scene = display::build_scene_mesh(config);
    if (!scene) return Err{"scene: " + scene.error()};
    cut::CutSession session(std::move(*scene));
    std::sort(shots.begin(), shots.end(),
              [](const ReplayShot& a, const ReplayShot& b) { return a.events < b.events; });
    Pictures pictures;
    pictures.focus = focus;
    pictures.bodies_at_start = session.bodies().size();
    if (!shots.empty()) {
        if (auto opened = pictures.open(); !opened) return Err{opened.error()};
    }
    ReplayResult out;
    out.bodies_before = session.bodies().size();
    std::size_t next_shot = 0;
    std::optional<ipc::CutPayload> open_cut;  // the blade in the pictures
    const auto take_due = [&]() -> Result<bool, std::string> {
        while (next_shot < shots.size() && shots[next_shot].events <= out.events) {
            if (auto shot = pictures.shoot(session, shots[next_shot], open_cut); !shot) return shot;
            out.shots.push_back(shots[next_shot].png.string());
            ++next_shot;
        }
        return true;
    };
    const std::uint64_t total = reader->record_count();
    ipc::EventRecord record{};
    for (std::uint64_t seq = 0; seq < total; ++seq) {
        if (auto due = take_due(); !due) return Err{due.error()};
        const ipc::JournalRead r = reader->try_read(seq, record);
        if (r == ipc::JournalRead::kNotYet) break;
        if (r == ipc::JournalRead::kCorrupt)
            return Err{journal.string() + ": record " + std::to_string(seq) + " is corrupt"};
        if (record.header.sequence != seq)
            return Err{journal.string() + ": sequence " + std::to_string(seq) + " missing"};
        switch (record.header.type) {
            case ipc::EventType::kCutBegin:
                ++out.cut_begins;
                open_cut = record.cut;
                break;
            case ipc::EventType::kCutProgress:
                ++out.cut_progress;
                open_cut = record.cut;
                break;
            case ipc::EventType::kCutEnd:
                open_cut.reset();
                if (record.cut.end_reason == ipc::CutEndReason::kCompleted)
                    ++out.cut_ends_completed;
                else
                    ++out.cut_ends_other;
                if (!out.first_cut_end_sequence) out.first_cut_end_sequence = seq + 1;
                break;
            case ipc::EventType::kBodyMoved:
                ++out.body_moves;
                break;
            default:
                break;
        }
        display::apply_record(session, record);
        session.idle();
        ++out.events;
    }
    for (std::size_t k = next_shot; k < shots.size(); ++k) shots[k].events = out.events;
    if (auto due = take_due(); !due) return Err{due.error()};
    const cut::SessionCounters& c = session.counters();
    out.applied = c.applied;
    out.refused = c.refused;
    out.ignored = c.ignored;
    out.hash = session.hash();
    out.bodies_after = session.bodies().size();
    const auto volumes = body_volumes(session);
    std::vector<bool> wanted(session.bodies().size(), false);
    for (const cut::SessionBody& b : session.bodies()) {
        if (b.severed_by_cut == 0) continue;
        wanted[b.id] = true;
        if (b.parent < wanted.size()) wanted[b.parent] = true;
    }
    for (const cut::SessionBody& b : session.bodies()) {
        if (!wanted[b.id]) continue;
        const auto it = volumes.find(b.id);
        ReplayPiece piece{b.id, b.parent, b.severed_by_cut, it == volumes.end() ? 0 : it->second};
        for (int i = 0; i < 3; ++i) piece.position_m[i] = b.pose.position_m[i];
        out.pieces.push_back(piece);
    }
    return out;
}

}  // namespace kerf::cli
