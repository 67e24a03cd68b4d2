// Scenes shared by the render tests and the frame-rate benchmark: a bone-like hollow tube
// (cortex outside, medullary canal inside) uncut, cut half-way with the kerf opening, and cut
// through with the far piece moved as a rigid body. Lengths in metres.
#pragma once

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <vector>

#include "display/cut/cut_context.hpp"
#include "display/cut/separate.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/shapes.hpp"
#include "display/render/camera.hpp"
#include "display/render/render_mesh.hpp"
#include "display/render/renderer.hpp"

namespace kerf::render::testing {

inline constexpr double kLength = 0.08, kOuter = 0.011, kInner = 0.0055, kKerf = 0.0012;

enum class SceneKind { kUncut, kMidCut, kSevered };

/// A scene ready to upload and draw.
struct Scene {
    mesh::TriMesh mesh;
    RenderMesh render;
    std::optional<PlannedCut> planned;
    BladePose blade;
    glm::dmat4 body1{1.0};
    Camera camera;
};

/// The tube with about `triangles` triangles (4 * segments * rings + 4 * segments).
inline mesh::TriMesh bone_tube(std::size_t triangles) {
    const int segments = std::max(16, static_cast<int>(std::sqrt(triangles / 4.0 * 0.5)));
    const int rings = std::max(1, static_cast<int>(triangles / (4.0 * segments)) - 1);
    return mesh::make_hollow_tube(kLength, kOuter, kInner, segments, rings);
}

/// The cutting plane of every scene: through the middle of the tube, tilted 20 degrees.
inline cut::Plane scene_plane() {
    return *cut::Plane::make({0.0, 0.0, kLength / 2}, {std::sin(0.35), 0.0, std::cos(0.35)});
}

inline Scene make_scene(SceneKind kind, std::size_t triangles = 60000) {
    Scene s{bone_tube(triangles), {}, {}, {}, glm::dmat4(1.0), {}};
    const cut::Plane plane = scene_plane();
    const glm::dvec3 n(plane.normal()[0], plane.normal()[1], plane.normal()[2]);
    const glm::dvec3 u(plane.u()[0], plane.u()[1], plane.u()[2]);
    const glm::dvec3 p0(0.0, 0.0, kLength / 2);
    // Blade lying in the plane, its body over the swept side (plane v < 2 mm), edge at v = 2 mm.
    const glm::dvec3 vp(plane.v()[0], plane.v()[1], plane.v()[2]);
    const glm::dmat3 frame(glm::cross(-vp, n), -vp, n);
    s.blade.orientation = glm::quat_cast(frame);
    s.blade.thickness_m = kKerf;
    s.blade.length_m = 0.03;
    s.blade.depth_m = 0.012;
    s.blade.visible = false;
    if (kind == SceneKind::kUncut) {
        s.planned = PlannedCut{p0, n, 0.02};
    } else {
        cut::CutContext ctx(s.mesh);
        cut::CrossSection cs;
        (void)cut::slice_by_plane(ctx, plane, cs);
        auto sep = cut::Separator::make(ctx, cs, kKerf);
        if (kind == SceneKind::kMidCut) {
            const std::vector<cut::Vec2> half = {
                {-1.0, -1.0}, {1.0, -1.0}, {1.0, 0.002}, {-1.0, 0.002}};
            sep->sweep(half);  // the blade has come up from -v to v = 2 mm
            s.blade.visible = true;
            s.blade.position_m = p0 + vp * 0.002;
        } else {
            sep->sweep_all();
        }
        s.mesh.update_normals();
        s.render = RenderMesh::build(s.mesh);
        if (kind == SceneKind::kSevered) {
            std::vector<mesh::VertexHandle> far;
            for (auto v : s.mesh.vertices()) {
                const auto& p = s.mesh.point(v);
                const glm::dvec3 q(p[0], p[1], p[2]);
                if (glm::dot(q - p0, n) > 0) far.push_back(v);
            }
            s.render.set_body(s.mesh, far, 1);
            s.body1 = glm::translate(glm::dmat4(1.0), glm::dvec3(0.010, 0.010, 0.004)) *
                      glm::rotate(glm::dmat4(1.0), 0.5, glm::dvec3(0, 1, 0.3));
        }
    }
    if (kind == SceneKind::kUncut) s.render = RenderMesh::build(s.mesh);
    s.camera =
        Camera::framing({-kOuter, -kOuter, 0}, {kOuter, kOuter, kLength}, CameraPreset::kIsometric);
    s.camera.orbit(0.3, kind == SceneKind::kSevered ? 0.3 : -0.15);
    if (kind == SceneKind::kSevered) s.camera.zoom(1.1);
    if (kind == SceneKind::kMidCut) {
        s.camera.set_target(p0);
        s.camera.orbit(-0.75, 0.25);
        s.camera.zoom(0.45);
    }
    return s;
}

/// Uploads and draws `s` with `renderer` (HUD with fixed text when `hud`).
inline void draw_scene(Renderer& r, Scene& s, bool hud) {
    r.upload(s.render);
    r.set_body_transform(1, s.body1);
    r.set_planned_cut(s.planned);
    r.begin_frame(s.camera);
    r.draw_blade(s.blade);
    if (hud) {
        HudState h;
        h.fps = 60;
        h.frame_p99_ms = 16.6;
        h.haptic_rate_hz = 1000;
        h.haptic_overruns = 3;
        h.wake_latency_us = 42;
        h.device_state = "connected";
        h.cut_state = "cutting";
        h.cut_depth_mm = 11.0;
        h.event_backlog = 2;
        h.triangles = s.render.triangle_count();
        r.draw_hud(h);
    }
    r.finish_frame();
}

}  // namespace kerf::render::testing
