// bench_render — the display's frame rate against the reference renderer, in one run.
//
//   build/bin/bench_render --ref /tmp/egl_ref [--tris 100000,1000000] [--frames 100] [--reps 5]
//                          [--shot PREFIX]   (PREFIX_<tris>.png: Kerf's frame at each size)
//
// For each size: Kerf's renderer draws a bone-like tube of that many triangles, cut through with
// the kerf open and the severed piece moved (cap faces shaded as cancellous bone), the blade and
// the HUD (both halves side by side, cut faces up), headless 1280x720, each frame ended by
// glFinish(); the reference (egl-bench, `-p surfaceless -c 1`, an ellipsoid whose cut cap is shaded
// on its back faces) draws the same number of triangles at the same size. The two alternate, rep by
// rep, in this one process tree so that both see the same load (llvmpipe uses every core). Kerf's
// camera is zoomed until the bone covers as many pixels as the reference's ellipsoid (fill rate
// dominates on llvmpipe); the coverage of both is printed. Then the upload cost after a cut: the
// dirty ranges of one more slice vs the whole used buffers, each followed by glFinish(). Prints the
// median of the reps with min-max, and the ratio of medians.
#include <stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "config/base/main_guard.hpp"
#include "display/egl/egl_output.hpp"
#include "tests/render/render_scenes.hpp"

namespace {

using namespace kerf::render;
using Clock = std::chrono::steady_clock;

struct Args {
    std::string ref;
    std::vector<long> tris{100000, 1000000};
    int frames = 100;
    int reps = 5;
    std::string shot;  ///< PNG of Kerf's first frame at each size: <shot>_<tris>.png
};

struct Summary {
    double median, min, max;
};
Summary summarise(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return {v[v.size() / 2], v.front(), v.back()};
}

// Share of pixels that differ from the background colour by more than a little.
double coverage(const unsigned char* rgba, std::size_t pixels, const unsigned char bg[3]) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        const unsigned char* p = rgba + i * 4;
        n += std::abs(p[0] - bg[0]) + std::abs(p[1] - bg[1]) + std::abs(p[2] - bg[2]) > 12;
    }
    return static_cast<double>(n) / static_cast<double>(pixels);
}

// Runs the reference once; returns its fps (< 0 on failure) and its triangle count.
// With `png`: no overlay (-q), so that the screenshot's coverage is the ellipsoid's alone.
double run_reference(const Args& a, long tris, int frames, const char* png, long& ref_tris) {
    std::string cmd = a.ref + " -p surfaceless -c 1 -t " + std::to_string(tris) + " -n " +
                      std::to_string(frames) + (png ? std::string(" -q -o ") + png : "") + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return -1;
    char line[1024];
    double fps = -1;
    while (std::fgets(line, sizeof line, p)) {
        if (std::strncmp(line, "RESULT", 6) != 0) continue;
        std::istringstream in(line);
        std::string kv;
        while (in >> kv) {
            if (kv.rfind("fps=", 0) == 0) fps = std::atof(kv.c_str() + 4);
            if (kv.rfind("tris=", 0) == 0) ref_tris = std::atol(kv.c_str() + 5);
        }
    }
    pclose(p);
    return fps;
}

double now_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

// Draws `frames` frames of `s`, orbiting a little each frame like the reference; returns fps.
// `extras`: the blade and the HUD too (off only for measuring the bone's coverage).
double run_kerf(Renderer& r, testing::Scene& s, int frames, FrameStats& stats, bool extras = true) {
    HudState hud;
    hud.device_state = "connected";
    hud.cut_state = "severed";
    hud.triangles = s.render.triangle_count();
    const Camera start = s.camera;
    const double t0 = now_s();
    for (int f = 0; f < frames; ++f) {
        const double fs = now_s();
        s.camera.orbit(0.02, 0.0);
        r.upload(s.render);
        r.set_body_transform(1, s.body1);
        r.begin_frame(s.camera);
        if (extras) {
            r.draw_blade(s.blade);
            hud.fps = stats.fps();
            hud.frame_p99_ms = stats.percentile_ms(0.99);
            r.draw_hud(hud);
        }
        r.finish_frame();
        stats.add(now_s() - fs);
    }
    const double total = now_s() - t0;
    s.camera = start;
    return frames / total;
}

bool parse(int argc, char** argv, Args& a) {
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
        if (!v) {
            std::fprintf(stderr, "bench_render: %s needs a value\n", k.c_str());
            return false;
        }
        ++i;
        if (k == "--ref") {
            a.ref = v;
        } else if (k == "--shot") {
            a.shot = v;
        } else if (k == "--frames") {
            a.frames = std::max(1, std::atoi(v));
        } else if (k == "--reps") {
            a.reps = std::max(1, std::atoi(v));
        } else if (k == "--tris") {
            a.tris.clear();
            std::stringstream in(v);
            std::string t;
            while (std::getline(in, t, ','))
                a.tris.push_back(std::max(1000L, std::atol(t.c_str())));
        } else {
            std::fprintf(stderr, "bench_render: unknown argument '%s'\n", k.c_str());
            return false;
        }
    }
    return true;
}

}  // namespace

static int program_main(int argc, char** argv) {
    Args a;
    if (!parse(argc, argv, a)) return 2;
    if (!a.ref.empty() && access(a.ref.c_str(), X_OK) != 0) {
        std::fprintf(stderr,
                     "bench_render: reference '%s' is not an executable (build it with "
                     "../shared/reference/egl-bench/build.sh)\n",
                     a.ref.c_str());
        return 2;
    }
    auto out = kerf::egl::EglOutput::create({});
    if (!out) {
        std::fprintf(stderr, "bench_render: %s\n", out.error().message().c_str());
        return 1;
    }
    constexpr int kW = 1280, kH = 720;
    auto r = Renderer::create({kW, kH});
    if (!r) {
        std::fprintf(stderr, "bench_render: %s\n", r.error().message().c_str());
        return 1;
    }
    std::printf("bench_render: %s, %dx%d, %d frames x %d reps, nproc %ld\n",
                out->description().c_str(), kW, kH, a.frames, a.reps,
                sysconf(_SC_NPROCESSORS_ONLN));
    double load[3] = {0, 0, 0};
    if (getloadavg(load, 3) == 3)
        std::printf("load average at start: %.2f %.2f %.2f\n", load[0], load[1], load[2]);
    const unsigned char bg[3] = {26, 31, 38};  // both clear to (0.10, 0.12, 0.15)
    for (long tris : a.tris) {
        auto s = testing::make_scene(testing::SceneKind::kSevered, static_cast<std::size_t>(tris));
        // Both halves side by side, cut faces up, seen from above at 57 degrees: more of the
        // frame is cut surface (pores) than in the reference's frame, every triangle in view.
        const glm::dvec3 p0(0.0, 0.0, testing::kLength / 2), side(2.6 * testing::kOuter, 0, 0);
        s.body1 = glm::translate(glm::dmat4(1.0), p0 + side) *
                  glm::rotate(glm::dmat4(1.0), 3.14159265358979, glm::dvec3(1, 0, 0)) *
                  glm::translate(glm::dmat4(1.0), -p0);
        s.camera =
            Camera::framing({-testing::kOuter, -testing::kOuter, 0},
                            {3.6 * testing::kOuter, testing::kOuter, testing::kLength * 0.6});
        s.camera.orbit(0.0, 0.4);
        s.blade.visible = true;
        s.blade.position_m = p0 + glm::dvec3(1.3 * testing::kOuter, -3.2 * testing::kOuter, 0.0);
        r->upload(s.render);
        // Match the reference's screen coverage (measured from its screenshot).
        double ref_cov = -1;
        long ref_tris = 0;
        if (!a.ref.empty()) {
            const std::string png = "/tmp/bench_render_ref_" + std::to_string(getpid()) + ".png";
            if (run_reference(a, tris, 3, png.c_str(), ref_tris) > 0) {
                int w = 0, h = 0, n = 0;
                unsigned char* img = stbi_load(png.c_str(), &w, &h, &n, 4);
                if (img) ref_cov = coverage(img, static_cast<std::size_t>(w) * h, bg);
                stbi_image_free(img);
            }
            std::remove(png.c_str());
        }
        FrameStats warm;
        double cov = 0;
        for (int it = 0; it < 4; ++it) {
            run_kerf(*r, s, 1, warm, false);  // the bone alone
            const auto px = r->read_pixels();
            cov = coverage(px.data(), px.size() / 4, bg);
            if (ref_cov <= 0 || std::abs(cov - ref_cov) < 0.01) break;
            s.camera.zoom(std::sqrt(cov / ref_cov));
        }
        if (!a.shot.empty()) {
            const std::string path = a.shot + "_" + std::to_string(tris) + ".png";
            if (auto st = r->save_png(path); !st)
                std::fprintf(stderr, "%s\n", st.error().message().c_str());
        }
        std::vector<double> ours, ref;
        FrameStats stats;
        for (int rep = 0; rep < a.reps; ++rep) {
            const bool ref_first = rep % 2 == 1;  // alternate the order
            double f = -1;
            if (ref_first && !a.ref.empty())
                f = run_reference(a, tris, a.frames, nullptr, ref_tris);
            ours.push_back(run_kerf(*r, s, a.frames, stats));
            if (!ref_first && !a.ref.empty())
                f = run_reference(a, tris, a.frames, nullptr, ref_tris);
            if (f > 0) ref.push_back(f);
        }
        const Summary o = summarise(ours);
        std::printf("RESULT tris=%u kerf_fps=%.2f (min %.2f max %.2f) p99_ms=%.1f coverage=%.3f",
                    s.render.triangle_count(), o.median, o.min, o.max, stats.percentile_ms(0.99),
                    cov);
        if (!ref.empty()) {
            const Summary f = summarise(ref);
            std::printf(
                " ref_tris=%ld ref_fps=%.2f (min %.2f max %.2f) ref_coverage=%.3f ratio=%.2f",
                ref_tris, f.median, f.min, f.max, ref_cov, o.median / f.median);
        }
        std::printf("\n");

        // Upload after a cut: one more slice's dirty ranges vs the whole used buffers.
        std::vector<double> dirty_ms, whole_ms;
        std::uint64_t dirty_bytes = 0, whole_bytes = 0;
        kerf::cut::CutContext ctx(s.mesh);
        for (int rep = 0; rep < a.reps; ++rep) {
            kerf::cut::CrossSection cs;
            const double z = testing::kLength * (0.15 + 0.05 * rep);
            (void)kerf::cut::slice_by_plane(ctx, *kerf::cut::Plane::make({0, 0, z}, {0, 0, 1}), cs);
            s.render.update_after_edit(s.mesh);
            r->finish_frame();
            double t0 = now_s();
            const UploadStats u = r->upload(s.render);
            r->finish_frame();
            dirty_ms.push_back((now_s() - t0) * 1e3);
            dirty_bytes = u.bytes;
            // The whole used buffers, as an upload without dirty tracking would send them.
            s.render.dirty_vertices().mark_range(0,
                                                 static_cast<std::uint32_t>(s.mesh.n_vertices()));
            s.render.dirty_vertices().mark_range(s.render.vertex_capacity(),
                                                 s.render.cap_vertex_count());
            s.render.dirty_indices().mark_range(0, s.render.triangle_count() * 3);
            t0 = now_s();
            const UploadStats w = r->upload(s.render);
            r->finish_frame();
            whole_ms.push_back((now_s() - t0) * 1e3);
            whole_bytes = w.bytes;
        }
        const Summary d = summarise(dirty_ms), w = summarise(whole_ms);
        std::printf(
            "RESULT upload tris=%u dirty_bytes=%llu dirty_ms=%.3f (min %.3f max %.3f) "
            "whole_bytes=%llu whole_ms=%.3f (min %.3f max %.3f) ratio=%.3f\n",
            s.render.triangle_count(), static_cast<unsigned long long>(dirty_bytes), d.median,
            d.min, d.max, static_cast<unsigned long long>(whole_bytes), w.median, w.min, w.max,
            d.median / w.median);
        std::fflush(stdout);
    }
    if (getloadavg(load, 3) == 3)
        std::printf("load average at end: %.2f %.2f %.2f\n", load[0], load[1], load[2]);
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_render", [&] { return program_main(argc, argv); });
}
