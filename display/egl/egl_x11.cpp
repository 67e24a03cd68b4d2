// The development window: an Xlib window with an EGL window surface (Xvfb in CI).
#include <cstdlib>

#include "display/egl/egl_backend.hpp"
#include "display/render/renderer.hpp"
// Xlib last: it defines macros (Status, None, Bool) that Kerf's headers must not see.
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>

namespace kerf::egl::detail {

namespace {

struct X11 final : EglOutput::Backend {
    Display* x = nullptr;
    Window window = 0;
    Colormap colormap = 0;
    Atom wm_delete = 0;

    ~X11() override {
        // EGL first: the surface draws into the window, which goes next.
        release_egl();
        if (!x) return;
        if (window) XDestroyWindow(x, window);
        if (colormap) XFreeColormap(x, colormap);
        XCloseDisplay(x);
    }

    bool present(render::Renderer& renderer) override {
        renderer.present_to(0, width, height);
        return eglSwapBuffers(display, surface) == EGL_TRUE;
    }

    bool poll() override {
        while (XPending(x) > 0) {
            XEvent e;
            XNextEvent(x, &e);
            handle(e);
        }
        return !input.quit;
    }

    // Turns one X event into WindowInput (left drag: 0.01 rad per pixel; wheel: 10 % per step).
    void handle(const XEvent& e) {
        switch (e.type) {
            case ClientMessage:
                if (static_cast<Atom>(e.xclient.data.l[0]) == wm_delete) input.quit = true;
                break;
            case ButtonPress:
                if (e.xbutton.button == Button1) {
                    dragging = true;
                    last_x = e.xbutton.x;
                    last_y = e.xbutton.y;
                }
                if (e.xbutton.button == Button4) input.zoom_factor *= 0.9;
                if (e.xbutton.button == Button5) input.zoom_factor /= 0.9;
                break;
            case ButtonRelease:
                if (e.xbutton.button == Button1) dragging = false;
                break;
            case MotionNotify:
                if (!dragging) break;
                input.orbit_yaw_rad -= 0.01 * (e.xmotion.x - last_x);
                input.orbit_pitch_rad += 0.01 * (e.xmotion.y - last_y);
                last_x = e.xmotion.x;
                last_y = e.xmotion.y;
                break;
            case KeyPress: {
                const KeySym k = XLookupKeysym(const_cast<XKeyEvent*>(&e.xkey), 0);
                if (k >= XK_1 && k <= XK_4) input.preset = static_cast<int>(k - XK_1);
                if (k == XK_q || k == XK_Escape) input.quit = true;
                break;
            }
            default:
                break;
        }
    }

    bool dragging = false;
    int last_x = 0, last_y = 0;
};

}  // namespace

Result<std::unique_ptr<EglOutput::Backend>, EglError> make_x11(const EglOptions& o) {
    auto b = std::make_unique<X11>();
    b->platform = EglPlatform::kX11;
    b->width = o.width;
    b->height = o.height;
    const char* name = o.x11_display.empty() ? nullptr : o.x11_display.c_str();
    b->x = XOpenDisplay(name);
    if (!b->x) {
        const char* env = std::getenv("DISPLAY");
        return Err{EglError{EglErrc::kOpenFailed, "x11",
                            std::string("cannot open X display '") +
                                (name ? name : (env ? env : "(DISPLAY unset)")) + "'"}};
    }
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_KHR_platform_x11") &&
        !has_extension(client, "EGL_EXT_platform_x11")) {
        return Err{EglError{EglErrc::kUnavailable, "x11",
                            "EGL has no X11 platform (EGL_KHR_platform_x11)"}};
    }
    b->display = eglGetPlatformDisplay(EGL_PLATFORM_X11_KHR, b->x, nullptr);
    if (auto e = initialize(b->display); !e.empty())
        return Err{EglError{EglErrc::kEglCall, "x11", e}};
    EGLConfig config = nullptr;
    if (auto e = choose_config(b->display, EGL_WINDOW_BIT, config); !e.empty()) {
        return Err{EglError{EglErrc::kEglCall, "x11", e}};
    }
    EGLint visual_id = 0;
    eglGetConfigAttrib(b->display, config, EGL_NATIVE_VISUAL_ID, &visual_id);
    XVisualInfo want{};
    want.visualid = static_cast<VisualID>(visual_id);
    int count = 0;
    XVisualInfo* vi = XGetVisualInfo(b->x, VisualIDMask, &want, &count);
    if (!vi || count < 1)
        return Err{EglError{EglErrc::kUnavailable, "x11", "no X visual for the EGL config"}};
    const Window root = DefaultRootWindow(b->x);
    XSetWindowAttributes swa{};
    b->colormap = XCreateColormap(b->x, root, vi->visual, AllocNone);
    swa.colormap = b->colormap;
    swa.event_mask = StructureNotifyMask | KeyPressMask | ButtonPressMask | ButtonReleaseMask |
                     Button1MotionMask;
    b->window = XCreateWindow(b->x, root, 0, 0, static_cast<unsigned>(o.width),
                              static_cast<unsigned>(o.height), 0, vi->depth, InputOutput,
                              vi->visual, CWColormap | CWEventMask, &swa);
    XFree(vi);
    XStoreName(b->x, b->window, "kerf-display");
    b->wm_delete = XInternAtom(b->x, "WM_DELETE_WINDOW", False);
    XSetWMProtocols(b->x, b->window, &b->wm_delete, 1);
    XMapWindow(b->x, b->window);
    XSync(b->x, False);
    b->surface = eglCreatePlatformWindowSurface(b->display, config, &b->window, nullptr);
    if (b->surface == EGL_NO_SURFACE) {
        return Err{
            EglError{EglErrc::kEglCall, "x11", egl_failure("eglCreatePlatformWindowSurface")}};
    }
    if (auto e = make_context(b->display, config, b->context); !e.empty()) {
        return Err{EglError{EglErrc::kEglCall, "x11", e}};
    }
    if (!eglMakeCurrent(b->display, b->surface, b->surface, b->context)) {
        return Err{EglError{EglErrc::kEglCall, "x11", egl_failure("eglMakeCurrent(window)")}};
    }
    eglSwapInterval(b->display, o.vsync ? 1 : 0);
    describe(*b);
    return std::unique_ptr<EglOutput::Backend>(std::move(b));
}

}  // namespace kerf::egl::detail
