// The kiosk output: GBM + DRM atomic modesetting on the first connected connector, as kmscube
// does (thin: one mode, the CRTC's primary plane, a blocking commit per frame). Every step fails
// with one line. Not run on the development VMs (no /dev/dri); see display/egl/README.md.
#include <fcntl.h>
#include <gbm.h>
#include <unistd.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "display/egl/egl_backend.hpp"
#include "display/render/renderer.hpp"

namespace kerf::egl::detail {

namespace {

// Looks up a DRM property id by name on object `id` of `type`; 0 when absent.
std::uint32_t property_id(int fd, std::uint32_t id, std::uint32_t type, const char* name) {
    drmModeObjectProperties* props = drmModeObjectGetProperties(fd, id, type);
    std::uint32_t found = 0;
    for (std::uint32_t i = 0; props && i < props->count_props && !found; ++i) {
        drmModePropertyRes* p = drmModeGetProperty(fd, props->props[i]);
        if (p && std::strcmp(p->name, name) == 0) found = p->prop_id;
        drmModeFreeProperty(p);
    }
    drmModeFreeObjectProperties(props);
    return found;
}

struct Kms final : EglOutput::Backend {
    int fd = -1;
    gbm_device* gbm = nullptr;
    gbm_surface* gbm_surf = nullptr;
    gbm_bo* shown = nullptr;
    std::uint32_t shown_fb = 0;
    std::uint32_t connector = 0, crtc = 0, plane = 0, mode_blob = 0;
    drmModeModeInfo mode{};
    bool modeset_done = false;

    ~Kms() override {
        release_egl();
        if (shown_fb) drmModeRmFB(fd, shown_fb);
        if (shown) gbm_surface_release_buffer(gbm_surf, shown);
        if (mode_blob) drmModeDestroyPropertyBlob(fd, mode_blob);
        if (gbm_surf) gbm_surface_destroy(gbm_surf);
        if (gbm) gbm_device_destroy(gbm);
        if (fd >= 0) close(fd);
    }

    bool present(render::Renderer& renderer) override {
        renderer.present_to(0, width, height);
        if (!eglSwapBuffers(display, surface)) return false;
        gbm_bo* bo = gbm_surface_lock_front_buffer(gbm_surf);
        if (!bo) return false;
        std::uint32_t fb = 0;
        const std::uint32_t handles[4] = {gbm_bo_get_handle(bo).u32, 0, 0, 0};
        const std::uint32_t pitches[4] = {gbm_bo_get_stride(bo), 0, 0, 0};
        const std::uint32_t offsets[4] = {0, 0, 0, 0};
        if (drmModeAddFB2(fd, gbm_bo_get_width(bo), gbm_bo_get_height(bo), gbm_bo_get_format(bo),
                          handles, pitches, offsets, &fb, 0) != 0) {
            gbm_surface_release_buffer(gbm_surf, bo);
            return false;
        }
        drmModeAtomicReq* req = drmModeAtomicAlloc();
        const auto add = [&](std::uint32_t obj, std::uint32_t type, const char* name,
                             std::uint64_t value) {
            drmModeAtomicAddProperty(req, obj, property_id(fd, obj, type, name), value);
        };
        std::uint32_t flags = 0;
        if (!modeset_done) {
            add(connector, DRM_MODE_OBJECT_CONNECTOR, "CRTC_ID", crtc);
            add(crtc, DRM_MODE_OBJECT_CRTC, "MODE_ID", mode_blob);
            add(crtc, DRM_MODE_OBJECT_CRTC, "ACTIVE", 1);
            flags |= DRM_MODE_ATOMIC_ALLOW_MODESET;
        }
        const auto w = static_cast<std::uint64_t>(width), h = static_cast<std::uint64_t>(height);
        add(plane, DRM_MODE_OBJECT_PLANE, "FB_ID", fb);
        add(plane, DRM_MODE_OBJECT_PLANE, "CRTC_ID", crtc);
        add(plane, DRM_MODE_OBJECT_PLANE, "SRC_X", 0);
        add(plane, DRM_MODE_OBJECT_PLANE, "SRC_Y", 0);
        add(plane, DRM_MODE_OBJECT_PLANE, "SRC_W", w << 16);
        add(plane, DRM_MODE_OBJECT_PLANE, "SRC_H", h << 16);
        add(plane, DRM_MODE_OBJECT_PLANE, "CRTC_X", 0);
        add(plane, DRM_MODE_OBJECT_PLANE, "CRTC_Y", 0);
        add(plane, DRM_MODE_OBJECT_PLANE, "CRTC_W", w);
        add(plane, DRM_MODE_OBJECT_PLANE, "CRTC_H", h);
        const int rc = drmModeAtomicCommit(fd, req, flags, nullptr);  // blocking: waits vblank
        drmModeAtomicFree(req);
        if (rc != 0) {
            drmModeRmFB(fd, fb);
            gbm_surface_release_buffer(gbm_surf, bo);
            return false;
        }
        modeset_done = true;
        if (shown_fb) drmModeRmFB(fd, shown_fb);
        if (shown) gbm_surface_release_buffer(gbm_surf, shown);
        shown = bo;
        shown_fb = fb;
        return true;
    }
};

// The first /dev/dri/card* that opens, or "" with `why` set.
std::string find_card(std::string& why) {
    std::error_code ec;
    for (int i = 0; i < 16; ++i) {
        const std::string path = "/dev/dri/card" + std::to_string(i);
        if (std::filesystem::exists(path, ec)) return path;
    }
    why =
        "no DRM device (/dev/dri/card* absent): the KMS kiosk output needs a GPU with a "
        "display; use --display headless or x11";
    return {};
}

// Picks the first connected connector, its preferred mode, a CRTC its encoder can drive and that
// CRTC's primary plane. "" on success.
std::string pick_pipe(Kms& k) {
    drmModeRes* res = drmModeGetResources(k.fd);
    if (!res) return "drmModeGetResources failed (not a modesetting device?)";
    std::string why = "no connected connector with a mode";
    for (int i = 0; i < res->count_connectors && !k.connector; ++i) {
        drmModeConnector* c = drmModeGetConnector(k.fd, res->connectors[i]);
        if (c && c->connection == DRM_MODE_CONNECTED && c->count_modes > 0) {
            k.mode = c->modes[0];
            for (int m = 0; m < c->count_modes; ++m)
                if (c->modes[m].type & DRM_MODE_TYPE_PREFERRED) k.mode = c->modes[m];
            for (int e = 0; e < c->count_encoders && !k.crtc; ++e) {
                drmModeEncoder* enc = drmModeGetEncoder(k.fd, c->encoders[e]);
                for (int r = 0; enc && r < res->count_crtcs && !k.crtc; ++r)
                    if (enc->possible_crtcs & (1u << r)) k.crtc = res->crtcs[r];
                drmModeFreeEncoder(enc);
            }
            if (k.crtc) k.connector = c->connector_id;
        }
        drmModeFreeConnector(c);
    }
    drmModeFreeResources(res);
    if (!k.connector) return why;
    drmModePlaneRes* planes = drmModeGetPlaneResources(k.fd);
    for (std::uint32_t i = 0; planes && i < planes->count_planes && !k.plane; ++i) {
        drmModePlane* p = drmModeGetPlane(k.fd, planes->planes[i]);
        const std::uint32_t type_prop =
            property_id(k.fd, planes->planes[i], DRM_MODE_OBJECT_PLANE, "type");
        drmModeObjectProperties* props =
            drmModeObjectGetProperties(k.fd, planes->planes[i], DRM_MODE_OBJECT_PLANE);
        bool primary = false;
        for (std::uint32_t j = 0; props && j < props->count_props; ++j)
            if (props->props[j] == type_prop && props->prop_values[j] == DRM_PLANE_TYPE_PRIMARY)
                primary = true;
        drmModeFreeObjectProperties(props);
        if (p && primary && p->crtc_id == 0 ? true : p && p->crtc_id == k.crtc) {
            if (primary) k.plane = p->plane_id;
        }
        drmModeFreePlane(p);
    }
    drmModeFreePlaneResources(planes);
    if (!k.plane) return "no primary plane for the CRTC";
    if (drmModeCreatePropertyBlob(k.fd, &k.mode, sizeof k.mode, &k.mode_blob) != 0)
        return "cannot create the mode blob";
    return {};
}

}  // namespace

Result<std::unique_ptr<EglOutput::Backend>, EglError> make_kms(const EglOptions& o) {
    auto k = std::make_unique<Kms>();
    k->platform = EglPlatform::kKms;
    std::string why;
    const std::string path = o.drm_device.empty() ? find_card(why) : o.drm_device;
    if (path.empty()) return Err{EglError{EglErrc::kUnavailable, "kms", why}};
    k->fd = open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (k->fd < 0) return Err{EglError{EglErrc::kOpenFailed, path, std::strerror(errno)}};
    if (drmSetClientCap(k->fd, DRM_CLIENT_CAP_UNIVERSAL_PLANES, 1) != 0 ||
        drmSetClientCap(k->fd, DRM_CLIENT_CAP_ATOMIC, 1) != 0) {
        return Err{EglError{EglErrc::kUnavailable, path, "no atomic modesetting"}};
    }
    if (auto e = pick_pipe(*k); !e.empty()) return Err{EglError{EglErrc::kUnavailable, path, e}};
    k->width = k->mode.hdisplay;
    k->height = k->mode.vdisplay;
    k->gbm = gbm_create_device(k->fd);
    if (!k->gbm) return Err{EglError{EglErrc::kOpenFailed, path, "gbm_create_device failed"}};
    k->gbm_surf = gbm_surface_create(k->gbm, static_cast<std::uint32_t>(k->width),
                                     static_cast<std::uint32_t>(k->height), GBM_FORMAT_XRGB8888,
                                     GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
    if (!k->gbm_surf) return Err{EglError{EglErrc::kOpenFailed, path, "gbm_surface_create failed"}};
    k->display = eglGetPlatformDisplay(EGL_PLATFORM_GBM_KHR, k->gbm, nullptr);
    if (auto e = initialize(k->display); !e.empty())
        return Err{EglError{EglErrc::kEglCall, "kms", e}};
    EGLConfig config = nullptr;
    if (auto e = choose_config(k->display, EGL_WINDOW_BIT, config, GBM_FORMAT_XRGB8888);
        !e.empty()) {
        return Err{EglError{EglErrc::kEglCall, "kms", e}};
    }
    if (auto e = make_context(k->display, config, k->context); !e.empty()) {
        return Err{EglError{EglErrc::kEglCall, "kms", e}};
    }
    k->surface = eglCreatePlatformWindowSurface(k->display, config, k->gbm_surf, nullptr);
    if (k->surface == EGL_NO_SURFACE) {
        return Err{
            EglError{EglErrc::kEglCall, "kms", egl_failure("eglCreatePlatformWindowSurface(gbm)")}};
    }
    if (!eglMakeCurrent(k->display, k->surface, k->surface, k->context)) {
        return Err{EglError{EglErrc::kEglCall, "kms", egl_failure("eglMakeCurrent")}};
    }
    describe(*k);
    return std::unique_ptr<EglOutput::Backend>(std::move(k));
}

}  // namespace kerf::egl::detail
