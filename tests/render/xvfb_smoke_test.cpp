// The X11 window output under a real X server (Xvfb, started here on a free display): a window
// opens, a frame is presented into it, and the window shows what the renderer's FBO holds.
// Skips with a visible message when Xvfb is not installed (CI installs it: tools/setup.sh).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "display/egl/egl_output.hpp"
#include "tests/render/render_scenes.hpp"
// Xlib last (its macros must not meet Kerf's headers).
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>

namespace kerf::render {
namespace {

constexpr int kW = 320, kH = 240;

// An Xvfb child on a display it picks itself (-displayfd), stopped on destruction.
class Xvfb {
public:
    // Starts Xvfb and waits until it says which display it serves; "" on failure (`why` set).
    std::string start(std::string& why) {
        int fds[2];
        if (pipe(fds) != 0) return why = "pipe failed", "";
        pid_ = fork();
        if (pid_ == 0) {
            close(fds[0]);
            const std::string fd = std::to_string(fds[1]);
            execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "640x480x24",
                   "-nolisten", "tcp", static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        std::string number;
        char c = 0;
        pollfd p{fds[0], POLLIN, 0};
        // Lockstep: wait (up to a generous minute on a loaded machine) for the number + newline.
        while (poll(&p, 1, 60000) > 0 && read(fds[0], &c, 1) == 1 && c != '\n') number += c;
        close(fds[0]);
        if (number.empty()) why = "Xvfb did not report a display within 60 s";
        return number.empty() ? "" : ":" + number;
    }
    ~Xvfb() {
        if (pid_ <= 0) return;
        kill(pid_, SIGTERM);
        int status = 0;
        waitpid(pid_, &status, 0);
    }

private:
    pid_t pid_ = -1;
};

bool xvfb_installed() {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = dirs.find(':', start);
        const std::string dir = dirs.substr(start, end - start);
        if (access((dir + "/Xvfb").c_str(), X_OK) == 0) return true;
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return false;
}

TEST(XvfbSmoke, AWindowOpensAndShowsThePresentedFrame) {
    if (!xvfb_installed()) GTEST_SKIP() << "Xvfb not installed (apt-get install xvfb; CI has it)";
    Xvfb server;
    std::string why;
    const std::string display = server.start(why);
    ASSERT_FALSE(display.empty()) << why;

    egl::EglOptions options;
    options.platform = egl::EglPlatform::kX11;
    options.width = kW;
    options.height = kH;
    options.x11_display = display;
    auto out = egl::EglOutput::create(options);
    ASSERT_TRUE(out) << out.error().message();
    EXPECT_NE(out->description().find("x11: "), std::string::npos);
    auto r = Renderer::create({kW, kH});
    ASSERT_TRUE(r) << r.error().message();
    auto scene = testing::make_scene(testing::SceneKind::kSevered, 20000);
    testing::draw_scene(*r, scene, true);
    const auto fbo = r->read_pixels();
    ASSERT_TRUE(out->present(*r));
    EXPECT_TRUE(out->poll());

    // What the X server shows at the window's place (no window manager: it sits at 0, 0).
    Display* x = XOpenDisplay(display.c_str());
    ASSERT_NE(x, nullptr);
    XSync(x, False);
    XImage* img = XGetImage(x, DefaultRootWindow(x), 0, 0, kW, kH, AllPlanes, ZPixmap);
    ASSERT_NE(img, nullptr);
    int same = 0, lit = 0;
    for (int y = 0; y < kH; ++y) {
        for (int px = 0; px < kW; ++px) {
            const unsigned long v = XGetPixel(img, px, y);
            const int rr = static_cast<int>((v >> 16) & 0xff),
                      gg = static_cast<int>((v >> 8) & 0xff), bb = static_cast<int>(v & 0xff);
            const std::size_t i = (static_cast<std::size_t>(y) * kW + px) * 4;
            same += std::abs(rr - fbo[i]) <= 2 && std::abs(gg - fbo[i + 1]) <= 2 &&
                    std::abs(bb - fbo[i + 2]) <= 2;
            lit += rr > 100;
        }
    }
    XDestroyImage(img);
    XCloseDisplay(x);
    EXPECT_GT(lit, kW * kH / 20);         // the bone is there, not a black window
    EXPECT_GT(same, kW * kH * 95 / 100);  // and it is the renderer's frame
}

TEST(KmsOutput, WithoutADrmDeviceFailsWithOneClearLine) {
    if (std::filesystem::exists("/dev/dri")) GTEST_SKIP() << "/dev/dri exists: not this case";
    egl::EglOptions options;
    options.platform = egl::EglPlatform::kKms;
    auto out = egl::EglOutput::create(options);
    ASSERT_FALSE(out);
    const std::string m = out.error().message();
    EXPECT_EQ(m.rfind("kms: no DRM device", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(X11Output, WithoutAServerFailsByName) {
    egl::EglOptions options;
    options.platform = egl::EglPlatform::kX11;
    options.x11_display = ":987";
    auto out = egl::EglOutput::create(options);
    ASSERT_FALSE(out);
    EXPECT_NE(out.error().message().find("x11: cannot open X display ':987'"), std::string::npos)
        << out.error().message();
}

}  // namespace
}  // namespace kerf::render
