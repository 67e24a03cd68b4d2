// kerf::render::Renderer — draws the bone, the saw blade, the planned cut and the HUD with OpenGL
// ES 3 into its own framebuffer object. It has no window-system code: whoever made the EGL
// context current (display/egl) creates it, and presents the result by blitting it into the
// window's framebuffer (present_to()). Screenshots read that same FBO, so they are identical on
// every back-end.
//
//   auto r = Renderer::create({1280, 720});            // a GLES 3 context must be current
//   r->upload(render_mesh);                            // only the dirty ranges after an edit
//   r->begin_frame(camera);                            // clear + bone (+ planned cut guide)
//   r->draw_blade(blade_pose_sampled_now);             // the live pose, as late as possible
//   r->draw_hud(hud);                                  // text overlay
//   r->finish_frame();                                 // glFinish: frame time is real
//   r->save_png("shot.png");                           // optional, reads the FBO
//
// Not thread-safe: every call on the thread that owns the GL context.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"
#include "display/render/camera.hpp"
#include "display/render/chunk_issue.hpp"
#include "display/render/hud.hpp"
#include "display/render/render_mesh.hpp"
#include "rt_core/ipc/records.hpp"

namespace kerf::render {

/// Why the renderer could not do something.
enum class RenderErrc : std::uint8_t {
    kBadOption,  ///< an option outside its range (framebuffer size)
    kNoContext,  ///< no current OpenGL ES 3 context
    kGl,         ///< a GL object could not be made (framebuffer, shader, GL error)
    kIo,         ///< a screenshot could not be written
};
/// Stable snake_case name ("no_context").
std::string_view to_string(RenderErrc code) noexcept;

/// A renderer failure (kerf::Error): where is "render" or the screenshot's path, what the step
/// that failed and why.
using RenderError = Error<RenderErrc>;

struct RendererOptions {
    int width = 1280;                                      ///< framebuffer width, pixels (1..8192)
    int height = 720;                                      ///< framebuffer height, pixels (1..8192)
    std::array<float, 3> background{0.10f, 0.12f, 0.15f};  ///< clear colour, linear RGB
};

/// The saw blade's pose and size. Tool frame: the cutting edge runs along +x centred on the
/// origin (the tool tip), the blade body extends along +y to its back, thickness along z (the
/// cut plane's normal), then a hub and handle continue along +y.
struct BladePose {
    glm::dvec3 position_m{0.0};                  ///< tool tip, world frame, m
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  ///< tool -> world rotation (w, x, y, z)
    double length_m = 0.025;                     ///< cutting edge length, m
    double depth_m = 0.010;                      ///< edge to back, m
    double thickness_m = 0.0006;                 ///< kerf, m
    bool visible = true;
};

/// The blade at the tool pose of a kerf-rt LatestState sample (read it from the seqlock right
/// before draw_blade()); size and visibility come from `like`. A non-finite or zero quaternion
/// gives an invisible blade.
BladePose blade_pose_from(const ipc::LatestState& state, const BladePose& like = {}) noexcept;

/// A planned cut drawn as a translucent square of plane around `point_m`.
struct PlannedCut {
    glm::dvec3 point_m{0.0};      ///< a point on the plane, world frame, m
    glm::dvec3 normal{0, 0, 1};   ///< plane normal, world frame (normalised here)
    double half_extent_m = 0.02;  ///< half the side of the square drawn, m
};

/// What one upload() sent to GL.
struct UploadStats {
    std::uint64_t bytes = 0;   ///< bytes passed to glBufferSubData / glBufferData
    std::uint32_t calls = 0;   ///< glBufferSubData calls
    bool reallocated = false;  ///< buffers were (re)created at the mesh's capacity
};

class Renderer {
public:
    /// Compiles the shaders and makes the FBO and buffers. Needs a current OpenGL ES 3 context.
    static Result<Renderer, RenderError> create(const RendererOptions& options);

    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;
    ~Renderer();

    /// Sends what changed in `mesh` since its last upload (its dirty ranges, then clears them);
    /// (re)allocates the buffers at the mesh's capacity when it was built or rebuilt.
    UploadStats upload(RenderMesh& mesh);
    /// Totals over every upload() so far.
    const UploadStats& upload_totals() const noexcept;

    /// Places rigid body `body` (see RenderVertex::body) in the world: body -> world, metres.
    /// Ignored for body >= kMaxBodies.
    void set_body_transform(int body, const glm::dmat4& body_to_world) noexcept;
    /// The same from a column-major matrix (cut::RigidPose::matrix()).
    void set_body_transform(int body, const std::array<float, 16>& body_to_world) noexcept;
    /// The planned cut drawn as a translucent guide, or none.
    void set_planned_cut(const std::optional<PlannedCut>& cut) noexcept;

    /// Binds the FBO, clears it and draws the mesh (and the planned-cut guide) from `camera`.
    void begin_frame(const Camera& camera);
    /// The same, but calls `abandon` between chunks of kBoneChunkTriangles of the mesh (issued in
    /// ChunkIssue's order: chunks edited lately last). There an edit that arrived meanwhile can
    /// join the frame (join_frame()); if it cannot and `abandon` says true, this stops and returns
    /// false: upload the edit and begin again (what was issued is overdrawn by the new clear).
    /// Lets a frame whose draw calls are still being issued (on llvmpipe: vertex work and
    /// binning) show an edit that arrived meanwhile.
    bool begin_frame(const Camera& camera, const std::function<bool()>& abandon);
    /// From begin_frame()'s `abandon`: uploads `mesh`'s pending edit into the frame being issued
    /// when it changes nothing the frame has drawn (ChunkIssue::can_join); the rest of the frame
    /// draws it. False: nothing uploaded. Body transforms must not have changed.
    bool join_frame(RenderMesh& mesh, UploadStats& stats);
    /// Draws the blade at `pose` (sample it as late as possible: right before this call).
    void draw_blade(const BladePose& pose);
    /// Draws the HUD text over everything.
    void draw_hud(const HudState& hud);
    /// Waits for GL to finish the frame (so frame times are real on llvmpipe and GPUs alike).
    void finish_frame();

    /// Copies the frame into framebuffer `target` (0: the window) of `width` x `height`.
    void present_to(std::uint32_t target, int width, int height);

    /// The frame as RGBA8 rows, top row first (reads the FBO: same on every back-end).
    std::vector<std::uint8_t> read_pixels();
    /// Writes the frame as a PNG (temp file in the same folder, then rename).
    Status<RenderError> save_png(const std::string& path);

    int width() const noexcept;
    int height() const noexcept;

private:
    struct State;
    explicit Renderer(std::unique_ptr<State> s) noexcept;
    std::unique_ptr<State> s_;
};

/// Writes RGBA8 pixels (top row first) as a PNG at `path` via a temp file and rename.
Status<RenderError> write_png(const std::string& path, int width, int height,
                              const std::vector<std::uint8_t>& rgba);

}  // namespace kerf::render
