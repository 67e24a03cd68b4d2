// Internal to kerf_egl: what each platform implements, and the EGL steps they share.
#pragma once

#ifndef EGL_NO_X11
#define EGL_NO_X11  // no Xlib macros (Status, None, Bool) in Kerf headers
#endif
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <string>

#include "display/egl/egl_output.hpp"

namespace kerf::egl {

struct EglOutput::Backend {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface surface = EGL_NO_SURFACE;
    EglPlatform platform = EglPlatform::kHeadless;
    int width = 0, height = 0;
    std::string description;
    WindowInput input;  ///< gathered by poll()

    virtual ~Backend();
    /// Unbinds and destroys the context and surface and terminates the display (idempotent);
    /// platforms call it before freeing what the surface draws into.
    void release_egl() noexcept;
    /// Blit + swap (+ page flip); headless: nothing.
    virtual bool present(render::Renderer& renderer) = 0;
    virtual bool poll() { return true; }
};

namespace detail {

/// "step failed (EGL_BAD_xxx)" for the last EGL error.
std::string egl_failure(const char* step);
/// True if `name` is a whole word of the space-separated `list`.
bool has_extension(const char* list, const char* name) noexcept;
/// eglInitialize + eglBindAPI(GLES); "" on success, else the step that failed.
std::string initialize(EGLDisplay display);
/// An EGLConfig for GLES 3 with RGBA8 + depth 24 for `surface_bit`, and the context on it.
std::string choose_config(EGLDisplay display, EGLint surface_bit, EGLConfig& config,
                          EGLint native_visual = -1);
std::string make_context(EGLDisplay display, EGLConfig config, EGLContext& context);
/// Fills description with the platform, GL_RENDERER and GL_VERSION (context must be current).
void describe(EglOutput::Backend& b);

Result<std::unique_ptr<EglOutput::Backend>, EglError> make_headless(const EglOptions& o);
Result<std::unique_ptr<EglOutput::Backend>, EglError> make_x11(const EglOptions& o);
Result<std::unique_ptr<EglOutput::Backend>, EglError> make_kms(const EglOptions& o);

}  // namespace detail
}  // namespace kerf::egl
