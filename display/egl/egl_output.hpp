// kerf::egl::EglOutput — where the display's frames go: an EGL display, an OpenGL ES 3 context
// made current on the calling thread, and a way to present a rendered frame.
//
//   auto out = EglOutput::create({.platform = EglPlatform::kHeadless});  // the default
//   auto r = render::Renderer::create({out->width(), out->height()});
//   ... r->begin_frame(cam); ...; out->present(*r);
//
// Platforms (kmscube-style: each step fails with one line naming the step):
//   kHeadless  eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY), no
//              surface; the renderer's FBO is the output (tests, screenshots, benchmarks). Needs no
//              environment variable, no X server, no /dev/dri (Mesa llvmpipe renders).
//   kX11       an Xlib window (DISPLAY, or Xvfb in CI) with an EGL window surface.
//   kKms       GBM + DRM atomic modesetting on the first connected connector (kiosks; needs
//              /dev/dri/card*; fails with one clear line where there is none).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "config/base/error.hpp"
#include "config/base/result.hpp"

namespace kerf::render {
class Renderer;
}

namespace kerf::egl {

enum class EglPlatform : std::uint8_t { kHeadless, kX11, kKms };
std::string_view to_string(EglPlatform p) noexcept;
/// Parses "headless" / "x11" / "kms"; false for anything else.
bool parse_platform(std::string_view text, EglPlatform& out) noexcept;

/// Why an output could not be made.
enum class EglErrc : std::uint8_t {
    kUnavailable,  ///< the platform, an extension or the device is missing here
    kOpenFailed,   ///< the X display, DRM device or GBM device could not be opened
    kEglCall,      ///< an EGL call failed (initialize, config, context, surface, make current)
    kBadOption,    ///< an option outside its range (size)
};
/// Stable snake_case name ("egl_call").
std::string_view to_string(EglErrc code) noexcept;

/// An output failure (kerf::Error): where is the platform ("headless", "x11", "kms") or the
/// device, what is the step that failed and why.
using EglError = Error<EglErrc>;

struct EglOptions {
    EglPlatform platform = EglPlatform::kHeadless;
    int width = 1280;  ///< pixels (headless, X11 window); KMS uses the connector's mode
    int height = 720;
    bool vsync = false;       ///< X11: swap interval 1 instead of 0 (KMS always waits for vblank)
    std::string x11_display;  ///< X11: display name, empty = $DISPLAY
    std::string drm_device;   ///< KMS: e.g. "/dev/dri/card0", empty = first card found
};

/// What the user did in the window since the last take_input() (X11; other platforms: nothing).
/// Left-drag orbits, the wheel zooms, keys 1-4 pick a camera preset, q / Escape quit.
struct WindowInput {
    double orbit_yaw_rad = 0.0;    ///< accumulated drag, rad (to Camera::orbit)
    double orbit_pitch_rad = 0.0;  ///< rad
    double zoom_factor = 1.0;      ///< product of wheel steps (to Camera::zoom)
    int preset = -1;               ///< last key 1..4 as 0..3 (CameraPreset order), -1 for none
    bool quit = false;             ///< window closed or q / Escape pressed
};

class EglOutput {
public:
    /// Opens the platform and makes a GLES 3 context current on this thread.
    static Result<EglOutput, EglError> create(const EglOptions& options);

    EglOutput(EglOutput&&) noexcept;
    EglOutput& operator=(EglOutput&&) noexcept;
    ~EglOutput();

    /// Shows the renderer's frame: blits it into the window / scanout buffer and swaps (X11, KMS);
    /// headless: nothing to show (the frame stays in the renderer's FBO). False on a lost output.
    bool present(render::Renderer& renderer);

    /// Handles pending window-system events; false once the user closed the window (or quit).
    bool poll();
    /// The input gathered by poll() since the last call, then starts afresh.
    WindowInput take_input() noexcept;

    EglPlatform platform() const noexcept;
    int width() const noexcept;
    int height() const noexcept;
    /// e.g. "headless: Mesa llvmpipe (LLVM 15.0.6, 256 bits), OpenGL ES 3.2 Mesa 22.3.6".
    const std::string& description() const noexcept;

    /// Back-end interface (implemented per platform in this folder).
    struct Backend;

private:
    explicit EglOutput(std::unique_ptr<Backend> b) noexcept;
    std::unique_ptr<Backend> b_;
};

}  // namespace kerf::egl
