#include "display/app/display_app.hpp"

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>
#include <ctime>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include "config/data_dir.hpp"
#include "config/load_config.hpp"
#include "display/app/hud_feed.hpp"
#include "display/app/render_sync.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/app/session_follower.hpp"
#include "display/egl/egl_output.hpp"
#include "display/render/renderer.hpp"

namespace kerf::display {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

std::uint64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::uint64_t(ts.tv_sec) * 1'000'000'000ull + std::uint64_t(ts.tv_nsec);
}

/// What the cutting worker hands the frame loop (guarded by `mutex`).
struct Handover {
    std::mutex mutex;
    RenderSync sync;
    /// Batches handed over (written under `mutex`; read without it by a frame issuing draws).
    std::atomic<std::uint64_t> edits{0};
    std::uint64_t newest_event_ns = 0;  ///< newest event in an edit not yet drawn (0: none)
    std::uint64_t cuts_completed = 0;
};

/// Event -> pixels latencies and frame times, for the HUD, the status file and benchmarks.
struct Measures {
    render::FrameStats frames;
    std::vector<double> latency_ms;        ///< one per edit that reached the screen (bounded)
    std::vector<double> upload_bytes;      ///< bytes uploaded by the frame of each latency sample
    std::uint64_t whole_buffer_bytes = 0;  ///< vertex + index buffers at capacity
    std::vector<double> frame_ms;          ///< every frame time (bounded)
    std::vector<double> issue_ms;  ///< per frame: upload + draw calls, before glFinish (bounded)
    render::UploadStats last_upload;
    std::uint64_t uploads = 0;
    std::uint64_t restarts = 0;  ///< frames begun again to take an edit that came mid-issue
    std::uint64_t joins = 0;     ///< edits that came mid-issue and joined the frame in flight
};

double median(std::vector<double> v) {
    if (v.empty()) return -1;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

std::string json_array(const std::vector<double>& v) {
    std::string out = "[";
    char buf[32];
    for (std::size_t i = 0; i < v.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%s%.3f", i ? ", " : "", v[i]);
        out += buf;
    }
    return out + "]";
}

/// `text` as a JSON string literal (quotes, backslashes and control characters escaped).
std::string json_string(std::string_view text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
            out += buf;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string hex(std::uint64_t v) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

/// Writes the status JSON next to `path` and renames it into place.
void write_status(const std::string& path, const FollowerStatus& s, const Measures& m,
                  std::uint64_t frame, const std::string& hud) {
    if (path.empty()) return;
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::trunc);
        const double lat_max =
            m.latency_ms.empty() ? -1 : *std::max_element(m.latency_ms.begin(), m.latency_ms.end());
        f << "{\"frames\": " << frame << ", \"fps\": " << m.frames.fps()
          << ", \"frame_p99_ms\": " << m.frames.percentile_ms(0.99)
          << ", \"attached\": " << (s.attached ? "true" : "false") << ", \"session_id\": \""
          << hex(s.session_id) << "\""
          << ", \"next_sequence\": " << s.next_sequence << ", \"hash\": \"" << hex(s.hash)
          << "\", \"hash_valid\": " << (s.hash_valid ? "true" : "false")
          << ", \"hash_sequence\": " << s.hash_sequence << ", \"applied\": " << s.session.applied
          << ", \"refused\": " << s.session.refused << ", \"ignored\": " << s.session.ignored
          << ", \"cuts_completed\": " << s.session.cuts_completed << ", \"bodies\": " << s.bodies
          << ", \"cut_open\": " << (s.cut_open ? "true" : "false")
          << ", \"from_journal\": " << s.consumer.from_journal
          << ", \"ring_gaps\": " << s.consumer.ring_gaps << ", \"lost\": " << s.consumer.lost
          << ", \"rejected_records\": " << s.consumer.rejected_records
          << ", \"rejected_indices\": " << s.consumer.rejected_indices
          << ", \"publishes\": " << s.publishes << ", \"publish_failures\": " << s.publish_failures
          << ", \"publish_ms_last\": " << double(s.last_publish_ns) * 1e-6
          << ", \"last_batch_ms\": " << double(s.last_batch_ns) * 1e-6
          << ", \"latency_samples\": " << m.latency_ms.size()
          << ", \"latency_median_ms\": " << median(m.latency_ms)
          << ", \"latency_max_ms\": " << lat_max
          << ", \"upload_bytes_last\": " << m.last_upload.bytes
          << ", \"upload_calls_last\": " << m.last_upload.calls
          << ", \"whole_buffer_bytes\": " << m.whole_buffer_bytes
          << ", \"frame_median_ms\": " << median(m.frame_ms)
          << ", \"issue_median_ms\": " << median(m.issue_ms)
          << ", \"frame_restarts\": " << m.restarts << ", \"frame_joins\": " << m.joins
          << ", \"latency_samples_ms\": " << json_array(m.latency_ms)
          << ", \"upload_bytes_samples\": " << json_array(m.upload_bytes)
          << ", \"edit_ms\": " << json_array(s.edit_ms) << ", \"hud\": " << json_string(hud)
          << "}\n";
        if (!f) {
            spdlog::warn("kerf-display: cannot write status {}", tmp);
            return;
        }
    }
    std::rename(tmp.c_str(), path.c_str());
}

egl::EglPlatform platform_of(config::DisplayMode mode) {
    switch (mode) {
        case config::DisplayMode::kHeadless:
            return egl::EglPlatform::kHeadless;
        case config::DisplayMode::kWindow:
            return egl::EglPlatform::kX11;
        case config::DisplayMode::kKms:
            return egl::EglPlatform::kKms;
    }
    return egl::EglPlatform::kHeadless;
}

render::BladePose blade_of(const FollowerStatus& s) {
    render::BladePose b;
    b.visible = s.state_valid;
    if (!s.state_valid) return b;
    const auto& st = s.state;
    b.position_m = glm::dvec3(st.tool_position_m[0], st.tool_position_m[1], st.tool_position_m[2]);
    b.orientation = glm::dquat(st.tool_orientation_wxyz[0], st.tool_orientation_wxyz[1],
                               st.tool_orientation_wxyz[2], st.tool_orientation_wxyz[3]);
    return b;
}

/// What the frame takes from the worker's hand-over, under its lock.
struct FrameInput {
    std::uint64_t drawn_event_ns = 0;  ///< newest event in the edits this frame uploads (0: none)
    bool cut_ended = false;            ///< a cut completed since the previous frame
    std::uint32_t triangles = 0;
    std::uint64_t edits = 0;                                  ///< hand-overs included in this frame
    std::array<glm::dmat4, render::kMaxBodies> transforms{};  ///< body slots the frame draws with
};

/// What the last frame showed, for --on-demand: redraw only when it is out of date.
struct DrawnState {
    std::uint64_t edits = ~std::uint64_t{0};
    double pose[7] = {0, 0, 0, 1, 0, 0, 0};  ///< tool position (m) and orientation (w, x, y, z)
    std::uint64_t at_ns = 0;
};

/// On-demand frames: an edit not yet drawn, a moved blade, or a second since the last frame.
bool needs_frame(Handover& h, const FollowerStatus& s, const DrawnState& d, std::uint64_t now) {
    {
        const std::lock_guard lock(h.mutex);
        if (h.edits.load(std::memory_order_relaxed) != d.edits) return true;
    }
    if (now - d.at_ns > 1'000'000'000) return true;
    if (!s.state_valid) return false;
    for (int i = 0; i < 3; ++i)
        if (s.state.tool_position_m[i] != d.pose[i]) return true;
    for (int i = 0; i < 4; ++i)
        if (s.state.tool_orientation_wxyz[i] != d.pose[3 + i]) return true;
    return false;
}

/// Uploads the dirty ranges, places the bodies, frames the camera once. Short: under the lock.
FrameInput take_handover(Handover& h, egl::EglOutput& output, render::Renderer& renderer,
                         Measures& m, std::optional<render::Camera>& camera,
                         std::uint64_t& cuts_seen) {
    FrameInput in;
    const std::lock_guard lock(h.mutex);
    auto& rm = h.sync.mesh();
    if (rm) {
        m.last_upload = renderer.upload(*rm);
        ++m.uploads;
        m.whole_buffer_bytes = rm->vertices().size() * sizeof(render::RenderVertex) +
                               rm->indices().size() * sizeof(std::uint32_t);
        if (!camera) camera = render::Camera::framing(h.sync.bounds_min(), h.sync.bounds_max());
        const egl::WindowInput input = output.take_input();  // X11: drag, wheel, 1-4
        if (input.preset >= 0) {
            camera = render::Camera::framing(h.sync.bounds_min(), h.sync.bounds_max(),
                                             static_cast<render::CameraPreset>(input.preset));
        }
        camera->orbit(input.orbit_yaw_rad, input.orbit_pitch_rad);
        camera->zoom(input.zoom_factor);
        const auto& t = h.sync.transforms();
        for (int b = 0; b < render::kMaxBodies; ++b)
            renderer.set_body_transform(b, t[std::size_t(b)]);
        in.transforms = t;
        in.triangles = rm->triangle_count();
    }
    in.drawn_event_ns = std::exchange(h.newest_event_ns, 0);
    in.edits = h.edits.load(std::memory_order_relaxed);
    in.cut_ended = h.cuts_completed > cuts_seen;
    cuts_seen = h.cuts_completed;
    return in;
}

/// Mid-frame, under the hand-over lock: the newest edit joins the frame in flight when it changes
/// nothing the frame has drawn (Renderer::join_frame) and moved no body; true if it did.
bool join_newest_edit(Handover& h, render::Renderer& renderer, Measures& m, FrameInput& in,
                      std::uint64_t& cuts_seen) {
    const std::lock_guard lock(h.mutex);
    auto& rm = h.sync.mesh();
    if (!rm || h.sync.transforms() != in.transforms) return false;
    render::UploadStats up;
    if (!renderer.join_frame(*rm, up)) return false;
    m.last_upload = up;
    ++m.uploads;
    ++m.joins;
    in.drawn_event_ns = std::max(in.drawn_event_ns, std::exchange(h.newest_event_ns, 0));
    in.edits = h.edits.load(std::memory_order_relaxed);
    in.cut_ended = in.cut_ended || h.cuts_completed > cuts_seen;
    cuts_seen = h.cuts_completed;
    in.triangles = rm->triangle_count();
    return true;
}

/// Uploads the newest edit and issues the bone's draw calls. An edit handed over while they are
/// being issued (the frame's upload point already passed) would otherwise wait for the whole
/// frame and then one more: it joins the frame in flight when it touches nothing drawn yet (the
/// chunks a cut edits are drawn last, so the next edits of that cut usually can), else the frame
/// is begun again once to take it — not twice in a row, so a stream of edits (CutProgress every
/// few ms) cannot starve frames.
FrameInput begin_frame_with_newest_edit(Handover& h, egl::EglOutput& output,
                                        render::Renderer& renderer, Measures& m,
                                        std::optional<render::Camera>& camera,
                                        std::uint64_t& cuts_seen, bool& restarted_last) {
    FrameInput in = take_handover(h, output, renderer, m, camera, cuts_seen);
    bool may_restart = !restarted_last;
    restarted_last = false;
    const auto between_chunks = [&] {
        if (h.edits.load(std::memory_order_acquire) == in.edits) return false;
        if (join_newest_edit(h, renderer, m, in, cuts_seen)) return false;
        return may_restart;
    };
    if (renderer.begin_frame(*camera, between_chunks)) return in;
    ++m.restarts;
    restarted_last = true;
    may_restart = false;  // edits may still join the frame begun again
    const FrameInput again = take_handover(h, output, renderer, m, camera, cuts_seen);
    in.drawn_event_ns = std::max(in.drawn_event_ns, again.drawn_event_ns);
    in.cut_ended = in.cut_ended || again.cut_ended;
    in.triangles = again.triangles;
    in.transforms = again.transforms;
    in.edits = again.edits;
    renderer.begin_frame(*camera, between_chunks);
    return in;
}

bool scene_ready(Handover& h) {
    const std::lock_guard lock(h.mutex);
    return h.sync.mesh().has_value();
}

void record_frame(Measures& m, std::uint64_t t0, std::uint64_t t1, std::uint64_t event_ns) {
    m.frames.add(double(t1 - t0) * 1e-9);
    if (m.frame_ms.size() < 100'000) m.frame_ms.push_back(double(t1 - t0) * 1e-6);
    if (event_ns && t1 > event_ns && m.latency_ms.size() < 100'000) {
        m.latency_ms.push_back(double(t1 - event_ns) * 1e-6);
        m.upload_bytes.push_back(double(m.last_upload.bytes));
    }
}

bool wants_screenshot(const DisplayOptions& o, std::uint64_t frame, bool cut_ended,
                      bool last_frame) {
    if (o.screenshot.empty()) return false;
    if (o.screenshot_on_cut_end) return cut_ended;
    return o.screenshot_at_frame == frame || (o.screenshot_at_frame == 0 && last_frame);
}

Result<egl::EglOutput, egl::EglError> open_output(const DisplayOptions& o,
                                                  const config::Config& cfg) {
    config::DisplayMode mode = cfg.main.display.mode;
    if (o.mode) {
        mode = *o.mode == "window" ? config::DisplayMode::kWindow
               : *o.mode == "kms"  ? config::DisplayMode::kKms
                                   : config::DisplayMode::kHeadless;
    }
    egl::EglOptions eo;
    eo.platform = platform_of(mode);
    eo.width = o.width.value_or(static_cast<int>(cfg.main.display.width_px));
    eo.height = o.height.value_or(static_cast<int>(cfg.main.display.height_px));
    eo.vsync = cfg.main.display.vsync;
    return egl::EglOutput::create(eo);
}

}  // namespace

ParsedArgs parse_display_args(int argc, char** argv) {
    ParsedArgs out;
    DisplayOptions& o = out.options;
    CLI::App app{
        "kerf-display: applies the cuts from the session's events, renders the bone and "
        "publishes the collision mesh"};
    std::string size;
    app.add_option("--config", o.config_path,
                   "kerf.toml to read (default: $KERF_DATA_DIR, installed share/kerf or config/)")
        ->check(CLI::ExistingFile);
    app.add_option("--mode", o.mode, "headless | window | kms (overrides [display] mode)")
        ->check(CLI::IsMember({"headless", "window", "kms"}));
    app.add_option("--size", size, "WIDTHxHEIGHT in pixels (overrides [display])");
    app.add_option("--session", o.session, "session segment name (overrides [shm] session_name)");
    app.add_option("--frames", o.frames, "stop after N frames (0: run until closed)");
    auto* shot = app.add_option("--screenshot", o.screenshot, "write a PNG of one frame");
    app.add_option("--at-frame", o.screenshot_at_frame,
                   "1-based frame to shoot (default: the last, also when stopped by a signal)")
        ->needs(shot);
    app.add_flag("--on-cut-end", o.screenshot_on_cut_end, "shoot the first frame after a cut ends")
        ->needs(shot);
    app.add_option("--exit-after-events", o.exit_after_events,
                   "exit after N events are applied, printing the mesh hash");
    app.add_option("--status", o.status_path, "write counters as JSON to this file");
    app.add_flag("--on-demand", o.on_demand,
                 "draw only when an edit, the blade or a second calls for it (kiosk, latency)");
    app.add_flag("--hash", o.hash_in_status,
                 "keep the session's mesh hash in --status current when idle (O(mesh) each time)");
    try {
        app.parse(argc, argv);
        if (!size.empty()) {
            int w = 0, h = 0;
            char x = 0;
            if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 1 ||
                h < 1 || w > 8192 || h > 8192) {
                throw CLI::ValidationError("--size",
                                           "'" + size + "' is not WIDTHxHEIGHT (1..8192)");
            }
            o.width = w;
            o.height = h;
        }
    } catch (const CLI::ParseError& e) {
        out.exit_code = app.exit(e) == 0 ? 0 : 2;  // --help: 0; every usage error: 2
    }
    return out;
}

int run_display(const DisplayOptions& o) {
    auto cfg =
        config::load_config(o.config_path.empty() ? config::data_file("kerf.toml") : o.config_path);
    if (!cfg) {
        spdlog::error("kerf-display: {}", cfg.error().message());
        return 2;
    }
    auto output = open_output(o, *cfg);
    if (!output) {
        spdlog::error("kerf-display: {}", output.error().message());
        return 3;
    }
    auto renderer =
        render::Renderer::create({output->width(), output->height(), {0.10f, 0.12f, 0.15f}});
    if (!renderer) {
        spdlog::error("kerf-display: renderer: {}", renderer.error().message());
        return 3;
    }
    spdlog::info("kerf-display: {}", output->description());
    if (cfg->scene.has_planned_cut) {  // the scene's planned osteotomy, a translucent guide
        const config::PlannedCut& c = cfg->scene.planned_cut;
        renderer->set_planned_cut(render::PlannedCut{{c.point_m[0], c.point_m[1], c.point_m[2]},
                                                     {c.normal[0], c.normal[1], c.normal[2]},
                                                     c.half_extent_m});
    }

    Handover handover;
    const config::Config config = *cfg;
    auto follower = SessionFollower::start(
        FollowerOptions{o.session.value_or(cfg->main.shm.session_name), true,
                        std::uint64_t{cfg->main.shm.heartbeat_timeout_ms} * 1'000'000u, 1000,
                        o.exit_after_events ? o.exit_after_events : (o.hash_in_status ? 1u : 0u)},
        [config] { return build_scene_mesh(config); },
        [&handover](const cut::CutSession& session, const cut::SessionChanges& changes,
                    std::uint64_t newest_event_ns) {
            const std::lock_guard lock(handover.mutex);
            handover.sync.apply(session, changes);
            handover.edits.fetch_add(1, std::memory_order_release);
            if (newest_event_ns) handover.newest_event_ns = newest_event_ns;
            handover.cuts_completed = session.counters().cuts_completed;
        });
    if (!follower) {
        spdlog::error("kerf-display: {}", follower.error());
        return 4;
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);

    Measures measures;
    DrawnState drawn;
    std::optional<render::Camera> camera;
    std::uint64_t frame = 0, cuts_seen = 0, last_status_ns = 0;
    bool shot_taken = false, exiting = false, restarted_last = false;
    std::string backend = output->description();
    HapticRate haptic_rate;
    std::string hud_text;  // the last frame's HUD, for --status
    while (output->poll()) {
        if (g_stop.load()) {
            // SIGTERM/SIGINT: one more frame when a last-frame screenshot is still owed (kerf
            // demo stops the display this way and keeps display-last-frame.png), else stop.
            if (exiting || shot_taken || frame == 0 || !wants_screenshot(o, frame, false, true))
                break;
            exiting = true;
        }
        if (!scene_ready(handover)) {  // frames start once the worker has built the scene
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            continue;
        }
        if (o.on_demand && !exiting &&
            !needs_frame(handover, (*follower)->status(), drawn, monotonic_ns())) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            continue;
        }
        const std::uint64_t t0 = monotonic_ns();
        const FrameInput in = begin_frame_with_newest_edit(handover, *output, *renderer, measures,
                                                           camera, cuts_seen, restarted_last);
        const FollowerStatus status = (*follower)->status();  // the latest pose, after the bone
        renderer->draw_blade(blade_of(status));
        if (status.state_valid)
            haptic_rate.add(status.state.tick, status.state.time_ns, monotonic_ns());
        const render::HudState hud =
            make_hud(status, measures.frames, haptic_rate, in.triangles, backend);
        renderer->draw_hud(hud);
        const std::uint64_t t_issued = monotonic_ns();
        renderer->finish_frame();
        output->present(*renderer);
        ++frame;
        const std::uint64_t t1 = monotonic_ns();
        record_frame(measures, t0, t1, in.drawn_event_ns);
        if (measures.issue_ms.size() < 100'000)
            measures.issue_ms.push_back(double(t_issued - t0) * 1e-6);
        drawn = DrawnState{in.edits, {}, t1};
        if (status.state_valid) {
            for (int i = 0; i < 3; ++i) drawn.pose[i] = status.state.tool_position_m[i];
            for (int i = 0; i < 4; ++i) drawn.pose[3 + i] = status.state.tool_orientation_wxyz[i];
        } else {
            drawn.pose[3] = 1.0;  // identity orientation
        }

        const bool last_frame = (o.frames && frame >= o.frames) || exiting;
        if (!shot_taken && wants_screenshot(o, frame, in.cut_ended, last_frame)) {
            if (auto saved = renderer->save_png(o.screenshot); !saved) {
                spdlog::error("kerf-display: screenshot: {}", saved.error().message());
            }
            shot_taken = true;
        }
        hud_text = render::format_hud(hud);
        if (t1 - last_status_ns > 500'000'000) {
            write_status(o.status_path, status, measures, frame, hud_text);
            last_status_ns = t1;
        }
        if (last_frame) break;
        if (o.exit_after_events && status.next_sequence >= o.exit_after_events &&
            status.hash_valid && status.hash_sequence >= o.exit_after_events) {
            exiting = true;  // one more frame, so the screen shows the last edit
        }
    }
    (*follower)->stop();
    const FollowerStatus final_status = (*follower)->status();
    write_status(o.status_path, final_status, measures, frame, hud_text);
    if (o.exit_after_events) std::printf("mesh hash %s\n", hex(final_status.hash).c_str());
    std::printf(
        "kerf-display: %llu frames, %.1f fps, p99 %.2f ms, %llu events applied, "
        "event->pixels median %.2f ms (%zu samples)\n",
        static_cast<unsigned long long>(frame), measures.frames.fps(),
        measures.frames.percentile_ms(0.99),
        static_cast<unsigned long long>(final_status.next_sequence), median(measures.latency_ms),
        measures.latency_ms.size());
    return 0;
}

}  // namespace kerf::display
