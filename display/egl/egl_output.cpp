#include "display/egl/egl_output.hpp"

#include <GLES3/gl3.h>

#include <cstdio>
#include <cstring>
#include <utility>

#include "display/egl/egl_backend.hpp"

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif

namespace kerf::egl {

std::string_view to_string(EglPlatform p) noexcept {
    switch (p) {
        case EglPlatform::kHeadless:
            return "headless";
        case EglPlatform::kX11:
            return "x11";
        case EglPlatform::kKms:
            return "kms";
    }
    return "unknown";
}

bool parse_platform(std::string_view text, EglPlatform& out) noexcept {
    for (EglPlatform p : {EglPlatform::kHeadless, EglPlatform::kX11, EglPlatform::kKms}) {
        if (text == to_string(p)) {
            out = p;
            return true;
        }
    }
    return false;
}

EglOutput::Backend::~Backend() { release_egl(); }

void EglOutput::Backend::release_egl() noexcept {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
    eglTerminate(display);
    display = EGL_NO_DISPLAY;
    context = EGL_NO_CONTEXT;
    surface = EGL_NO_SURFACE;
}

std::string_view to_string(EglErrc code) noexcept {
    switch (code) {
        case EglErrc::kUnavailable:
            return "unavailable";
        case EglErrc::kOpenFailed:
            return "open_failed";
        case EglErrc::kEglCall:
            return "egl_call";
        case EglErrc::kBadOption:
            return "bad_option";
    }
    return "unknown";
}

namespace detail {

std::string egl_failure(const char* step) {
    const EGLint e = eglGetError();
    const char* name = "unknown";
    switch (e) {
        case EGL_SUCCESS:
            name = "EGL_SUCCESS";
            break;
        case EGL_NOT_INITIALIZED:
            name = "EGL_NOT_INITIALIZED";
            break;
        case EGL_BAD_ACCESS:
            name = "EGL_BAD_ACCESS";
            break;
        case EGL_BAD_ALLOC:
            name = "EGL_BAD_ALLOC";
            break;
        case EGL_BAD_ATTRIBUTE:
            name = "EGL_BAD_ATTRIBUTE";
            break;
        case EGL_BAD_CONFIG:
            name = "EGL_BAD_CONFIG";
            break;
        case EGL_BAD_CONTEXT:
            name = "EGL_BAD_CONTEXT";
            break;
        case EGL_BAD_DISPLAY:
            name = "EGL_BAD_DISPLAY";
            break;
        case EGL_BAD_MATCH:
            name = "EGL_BAD_MATCH";
            break;
        case EGL_BAD_NATIVE_WINDOW:
            name = "EGL_BAD_NATIVE_WINDOW";
            break;
        case EGL_BAD_PARAMETER:
            name = "EGL_BAD_PARAMETER";
            break;
        case EGL_BAD_SURFACE:
            name = "EGL_BAD_SURFACE";
            break;
        default:
            break;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, " failed (%s, 0x%04x)", name, static_cast<unsigned>(e));
    return std::string(step) + buf;
}

bool has_extension(const char* list, const char* name) noexcept {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    }
    return false;
}

std::string initialize(EGLDisplay display) {
    if (display == EGL_NO_DISPLAY) return egl_failure("eglGetPlatformDisplay");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return egl_failure("eglInitialize");
    if (!eglBindAPI(EGL_OPENGL_ES_API)) return egl_failure("eglBindAPI(EGL_OPENGL_ES_API)");
    return {};
}

std::string choose_config(EGLDisplay display, EGLint surface_bit, EGLConfig& config,
                          EGLint native_visual) {
    const EGLint attrs[] = {EGL_SURFACE_TYPE, surface_bit, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                            EGL_RED_SIZE,     8,           EGL_GREEN_SIZE,      8,
                            EGL_BLUE_SIZE,    8,           EGL_DEPTH_SIZE,      24,
                            EGL_NONE};
    EGLConfig configs[64];
    EGLint n = 0;
    if (!eglChooseConfig(display, attrs, configs, 64, &n) || n < 1) {
        return egl_failure("eglChooseConfig(GLES3, RGB8, depth 24)");
    }
    config = configs[0];
    if (native_visual < 0) return {};
    for (EGLint i = 0; i < n; ++i) {  // GBM: the config whose visual is the scanout format
        EGLint id = 0;
        if (eglGetConfigAttrib(display, configs[i], EGL_NATIVE_VISUAL_ID, &id) &&
            id == native_visual) {
            config = configs[i];
            return {};
        }
    }
    return "eglChooseConfig: no config with the scanout format (XRGB8888)";
}

std::string make_context(EGLDisplay display, EGLConfig config, EGLContext& context) {
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, attrs);
    if (context == EGL_NO_CONTEXT) return egl_failure("eglCreateContext(OpenGL ES 3.0)");
    return {};
}

void describe(EglOutput::Backend& b) {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    b.description = std::string(to_string(b.platform)) + ": " + (renderer ? renderer : "?") + ", " +
                    (version ? version : "?");
}

namespace {

struct Headless final : EglOutput::Backend {
    bool present(render::Renderer&) override { return true; }
};

}  // namespace

Result<std::unique_ptr<EglOutput::Backend>, EglError> make_headless(const EglOptions& o) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_MESA_platform_surfaceless")) {
        return Err{EglError{EglErrc::kUnavailable, "headless",
                            "EGL has no EGL_MESA_platform_surfaceless (install libegl-mesa0)"}};
    }
    auto b = std::make_unique<Headless>();
    b->platform = EglPlatform::kHeadless;
    b->width = o.width;
    b->height = o.height;
    b->display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA,
                                       reinterpret_cast<void*>(EGL_DEFAULT_DISPLAY), nullptr);
    if (auto e = initialize(b->display); !e.empty())
        return Err{EglError{EglErrc::kEglCall, "headless", e}};
    const char* ext = eglQueryString(b->display, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_surfaceless_context")) {
        return Err{EglError{EglErrc::kUnavailable, "headless",
                            "display lacks EGL_KHR_surfaceless_context"}};
    }
    EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR when config-less contexts exist
    if (!has_extension(ext, "EGL_KHR_no_config_context")) {
        if (auto e = choose_config(b->display, EGL_PBUFFER_BIT, config); !e.empty()) {
            return Err{EglError{EglErrc::kEglCall, "headless", e}};
        }
    }
    if (auto e = make_context(b->display, config, b->context); !e.empty()) {
        return Err{EglError{EglErrc::kEglCall, "headless", e}};
    }
    if (!eglMakeCurrent(b->display, EGL_NO_SURFACE, EGL_NO_SURFACE, b->context)) {
        return Err{
            EglError{EglErrc::kEglCall, "headless", egl_failure("eglMakeCurrent(no surface)")}};
    }
    describe(*b);
    return std::unique_ptr<EglOutput::Backend>(std::move(b));
}

}  // namespace detail

Result<EglOutput, EglError> EglOutput::create(const EglOptions& o) {
    if (o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192) {
        return Err{EglError{EglErrc::kBadOption, "egl",
                            "size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                                " is outside 1..8192"}};
    }
    Result<std::unique_ptr<Backend>, EglError> b =
        o.platform == EglPlatform::kX11   ? detail::make_x11(o)
        : o.platform == EglPlatform::kKms ? detail::make_kms(o)
                                          : detail::make_headless(o);
    if (!b) return Err{b.error()};
    return EglOutput(std::move(*b));
}

EglOutput::EglOutput(std::unique_ptr<Backend> b) noexcept : b_(std::move(b)) {}
EglOutput::EglOutput(EglOutput&&) noexcept = default;
EglOutput& EglOutput::operator=(EglOutput&&) noexcept = default;
EglOutput::~EglOutput() = default;

bool EglOutput::present(render::Renderer& renderer) { return b_->present(renderer); }
bool EglOutput::poll() { return b_->poll(); }
WindowInput EglOutput::take_input() noexcept { return std::exchange(b_->input, WindowInput{}); }
EglPlatform EglOutput::platform() const noexcept { return b_->platform; }
int EglOutput::width() const noexcept { return b_->width; }
int EglOutput::height() const noexcept { return b_->height; }
const std::string& EglOutput::description() const noexcept { return b_->description; }

}  // namespace kerf::egl
