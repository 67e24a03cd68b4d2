// kerf-display and the real kerf-rt (kerf-hapsim as its device, all real processes) on the
// built-in foot at 1M triangles: the display publishes the whole collision mesh through the
// mailbox (layout version 3: 2^20 vertices, 2^21 triangles) and kerf-rt validates it, builds its
// collision world off the real-time thread and swaps it in — the surface the surgeon feels is the
// surface the display draws, not a decimated stand-in. Label stress: two processes each build a
// 1M-triangle scene (tens of seconds on a loaded 2-core machine).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "tests/display/process_support.hpp"

namespace kerf::display {
namespace {

namespace fs = std::filesystem;
using test::Child;

constexpr double kTimeout_s = 600.0;  // generous: CI runs this on a loaded 2-core machine

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "kerf.toml has no '" << from << "'";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

double status_value(const std::string& path, const std::string& key) {
    const std::string text = test::read_file(path);
    const auto at = text.find("\"" + key + "\": ");
    return at == std::string::npos ? -1 : std::atof(text.c_str() + at + key.size() + 4);
}

long long number_after(const std::string& text, const std::string& key) {
    std::smatch m;
    return std::regex_search(text, m, std::regex(key + " ([0-9]+)")) ? std::stoll(m[1].str()) : -1;
}

TEST(DisplayWithKerfRt, TheOneMillionTriangleCollisionMeshIsPublishedAndSwappedIn) {
    if (access(test::bin("kerf-rt").c_str(), X_OK) != 0) GTEST_SKIP() << "no kerf-rt built";
    char tmpl[] = "/tmp/kerf-display-rt-XXXXXX";
    const fs::path dir = mkdtemp(tmpl);
    const fs::path config = fs::path(KERF_SOURCE_DIR) / "config";
    for (const char* sub : {"devices", "force", "scenes"}) fs::create_directories(dir / sub);
    fs::copy_file(config / "devices/simulated.toml", dir / "devices/simulated.toml");
    fs::copy_file(config / "force/default.toml", dir / "force/default.toml");
    const std::string session = "kerfdisprt_" + std::to_string(getpid());
    std::string toml = test::read_file((config / "kerf.toml").string());
    toml = replaced(toml, "session_name = \"kerf\"", "session_name = \"" + session + "\"");
    toml = replaced(toml, "width_px = 1280", "width_px = 320");
    toml = replaced(toml, "height_px = 720", "height_px = 240");
    toml = replaced(toml, "cpu_affinity = [1]", "cpu_affinity = []");
    toml = replaced(toml, "dir = \"${tmp}/kerf-journal\"", "dir = \"" + dir.string() + "\"");
    std::ofstream(dir / "kerf.toml") << toml;
    std::ofstream(dir / "scenes/builtin_foot.toml")
        << replaced(test::read_file((config / "scenes/builtin_foot.toml").string()),
                    "target_triangles = 200_000", "target_triangles = 1_000_000");
    std::ofstream(dir / "hand.csv") << "hold,600\n";  // the device rests; no cut is needed here
    const std::string socket = (dir / "hapsim.sock").string();

    Child hapsim({test::bin("kerf-hapsim"), "--socket", socket, "--protocol", "kerf", "--realtime",
                  "--script", (dir / "hand.csv").string()},
                 (dir / "hapsim.out").string());
    ASSERT_TRUE(hapsim.wait_output("ready", 60)) << hapsim.output();
    Child rt({test::bin("kerf-rt"), "--config", (dir / "kerf.toml").string(), "--socket", socket},
             (dir / "rt.out").string());
    ASSERT_TRUE(rt.wait_output("real-time report", kTimeout_s)) << rt.output();
    const std::string status = (dir / "status.json").string();
    Child display({test::bin("kerf-display"), "--config", (dir / "kerf.toml").string(), "--status",
                   status, "--on-demand"},
                  (dir / "display.out").string());

    // The display publishes the scene's mesh once attached: all 19 bones, 999,666 triangles.
    ASSERT_TRUE(test::wait_for([&] { return status_value(status, "publishes") >= 1; }, kTimeout_s))
        << display.output() << test::read_file(status);
    EXPECT_EQ(status_value(status, "publish_failures"), 0.0) << test::read_file(status);
    // kerf-rt takes it from the mailbox, validates it, builds the world and swaps it in.
    ASSERT_TRUE(rt.wait_output("(19 bodies) swapped in", kTimeout_s)) << rt.output();
    rt.kill(SIGTERM);
    ASSERT_EQ(rt.wait_exit(60), std::optional<int>(0)) << rt.output();
    const std::string out = rt.output();
    EXPECT_GE(number_after(out, "worlds swapped"), 1) << out;
    EXPECT_EQ(number_after(out, "mailbox refused"), 0) << out;
    const std::regex swapped("generation ([0-9]+) \\(19 bodies\\) swapped in");
    std::smatch swap;
    ASSERT_TRUE(std::regex_search(out, swap, swapped)) << out;
    EXPECT_GE(std::stoll(swap[1].str()), 1) << "a generation the display published";
    std::printf("[ info ] kerf-rt: %s; %s\n", swap[0].str().c_str(),
                out.substr(out.find("worlds swapped")).c_str());
    std::smatch published;  // the display's line, with its export + publish time
    const std::string shown = display.output();
    if (std::regex_search(shown, published, std::regex("[^\n]*published \\([^\n]*")))
        std::printf("[ info ] %s\n", published[0].str().c_str());
    display.kill(SIGTERM);
    EXPECT_EQ(display.wait_exit(60), std::optional<int>(0)) << display.output();
    std::error_code ec;
    fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace kerf::display
