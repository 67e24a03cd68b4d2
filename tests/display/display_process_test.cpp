// kerf-display as a real process against a real session segment (a test producer standing in for
// kerf-rt): the mesh it reaches from a recorded event stream is the mesh CutSession reaches in
// this test from the same records; so is the mesh after kill -9 mid-cut and a restart; so is the
// mesh while another process scribbles over the segment.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "config/load_config.hpp"
#include "display/app/scene_mesh.hpp"
#include "display/app/session_events_ipc.hpp"
#include "display/mesh/mesh_io.hpp"
#include "tests/display/event_script.hpp"
#include "tests/display/process_support.hpp"
#include "tests/display/session_scenes.hpp"

namespace kerf::display {
namespace {

namespace fs = std::filesystem;
using test::Child;

constexpr double kTimeout_s = 120.0;  // generous: CI runs this on a loaded 2-core machine

std::string replace(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

/// A scratch folder with kerf.toml (scene: two tubes from tubes.ply), the profiles it names,
/// the recorded events, and a unique session name.
struct Scratch {
    Scratch() {
        char tmpl[] = "/tmp/kerf-display-XXXXXX";
        dir = mkdtemp(tmpl);
        static std::atomic<int> counter{0};
        session = "kerfdisp_" + std::to_string(getpid()) + "_" + std::to_string(counter++);
        const fs::path config = fs::path(KERF_SOURCE_DIR) / "config";
        fs::create_directories(dir / "devices");
        fs::create_directories(dir / "force");
        fs::create_directories(dir / "scenes");
        fs::copy_file(config / "devices/simulated.toml", dir / "devices/simulated.toml");
        fs::copy_file(config / "force/default.toml", dir / "force/default.toml");
        std::string toml = test::read_file((config / "kerf.toml").string());
        toml = replace(toml, "scene = \"builtin_foot\"", "scene = \"tubes\"");
        toml = replace(toml, "session_name = \"kerf\"", "session_name = \"" + session + "\"");
        toml = replace(toml, "width_px = 1280", "width_px = 320");
        toml = replace(toml, "height_px = 720", "height_px = 240");
        std::ofstream(dir / "kerf.toml") << toml;
        std::ofstream(dir / "scenes/tubes.toml")
            << "name = \"tubes\"\ndescription = \"two bone-like tubes\"\n[[bodies]]\n"
               "name = \"tubes\"\nmaterial = \"cortical\"\n[bodies.mesh]\nsource = \"file\"\n"
               "path = \"${config}/tubes.ply\"\nunits = \"m\"\n[bodies.transform]\n"
               "translation_m = [0.0, 0.0, 0.0]\nrotation_quaternion_wxyz = [1.0, 0.0, 0.0, 0.0]\n";
        const auto saved =
            mesh::save_mesh(cut::test::two_tubes(), dir / "tubes.ply", LengthUnit::kMetre);
        EXPECT_TRUE(saved.has_value());
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    std::string path(const char* name) const { return (dir / name).string(); }

    fs::path dir;
    std::string session;
};

/// The hash CutSession reaches in this process from the scene and `records`.
std::string reference_hash(const Scratch& s, const std::vector<ipc::EventRecord>& records) {
    auto config = config::load_config(s.dir / "kerf.toml");
    EXPECT_TRUE(config.has_value()) << (config ? "" : config.error().message());
    auto scene = build_scene_mesh(*config);
    EXPECT_TRUE(scene.has_value());
    cut::CutSession session(std::move(*scene));
    EXPECT_EQ(session.bodies().size(), 2u);
    for (const auto& r : records) apply_record(session, r);
    EXPECT_EQ(session.counters().refused, 0u) << "the script must cut, not be refused";
    EXPECT_EQ(session.bodies().size(), 3u);
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(session.hash()));
    return buf;
}

void write_records(const std::string& path, const std::vector<ipc::EventRecord>& records) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(records.data()),
              static_cast<std::streamsize>(records.size() * sizeof(ipc::EventRecord)));
}

std::string hash_printed(const std::string& output) {
    std::smatch m;
    return std::regex_search(output, m, std::regex("mesh hash ([0-9a-f]{16})")) ? m[1].str() : "";
}

std::vector<std::string> producer_args(const Scratch& s, std::vector<std::string> extra = {}) {
    std::vector<std::string> args{test::bin("display_test_producer"),
                                  "--segment",
                                  s.session,
                                  "--journal-dir",
                                  s.dir.string(),
                                  "--records",
                                  s.path("events.bin")};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

std::vector<std::string> display_args(const Scratch& s, const char* status,
                                      std::vector<std::string> extra = {}) {
    std::vector<std::string> args{test::bin("kerf-display"), "--config", s.path("kerf.toml"),
                                  "--status", s.path(status)};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

/// The number after `"key": ` in the display's status JSON, or -1.
double status_value(const Scratch& s, const char* file, const std::string& key) {
    const std::string text = test::read_file(s.path(file));
    const auto at = text.find("\"" + key + "\": ");
    return at == std::string::npos ? -1 : std::atof(text.c_str() + at + key.size() + 4);
}

TEST(DisplayProcess, AppliesARecordedStreamToTheSameMeshAsCutSessionInTheTest) {
    Scratch s;
    const auto records = test::script();
    write_records(s.path("events.bin"), records);
    const std::string expected = reference_hash(s, records);

    Child producer(producer_args(s), s.path("producer.out"));
    ASSERT_TRUE(producer.wait_output("ready", kTimeout_s)) << producer.output();
    const std::string n = std::to_string(records.size());
    Child display(
        display_args(s, "status.json",
                     {"--exit-after-events", n, "--screenshot", s.path("cut.png"), "--on-cut-end"}),
        s.path("display.out"));
    ASSERT_EQ(display.wait_exit(kTimeout_s), std::optional<int>(0)) << display.output();
    EXPECT_EQ(hash_printed(display.output()), expected) << display.output();
    EXPECT_GE(status_value(s, "status.json", "publishes"), 1.0) << "collision mesh published";
    EXPECT_EQ(status_value(s, "status.json", "refused"), 0.0);
    EXPECT_GT(fs::file_size(s.path("cut.png")), 1000u) << "the frame after the completed cut";
    if (const char* keep = std::getenv("KERF_KEEP_SCREENSHOT"))
        fs::copy_file(s.path("cut.png"), keep);
    producer.kill(SIGTERM);
}

TEST(DisplayProcess, KilledMidCutAndRestartedItCatchesUpToTheSameMesh) {
    Scratch s;
    const auto records = test::script();
    write_records(s.path("events.bin"), records);
    const std::string expected = reference_hash(s, records);
    const std::size_t hold = 6;  // CutBegin and five progress events: mid-cut

    Child producer(producer_args(s, {"--hold-after", std::to_string(hold), "--go", s.path("go")}),
                   s.path("producer.out"));
    ASSERT_TRUE(producer.wait_output("published " + std::to_string(hold), kTimeout_s))
        << producer.output();
    {
        Child first(display_args(s, "first.json"), s.path("first.out"));
        ASSERT_TRUE(test::wait_for(
            [&] { return status_value(s, "first.json", "next_sequence") >= double(hold); },
            kTimeout_s))
            << first.output();
        EXPECT_NE(test::read_file(s.path("first.json")).find("\"cut_open\": true"),
                  std::string::npos)
            << "killed mid-cut";
        first.kill(SIGKILL);
        ASSERT_EQ(first.wait_exit(kTimeout_s), std::optional<int>(128 + SIGKILL));
    }
    std::ofstream(s.path("go")) << "go\n";
    ASSERT_TRUE(producer.wait_output("published " + std::to_string(records.size()), kTimeout_s));
    Child second(
        display_args(s, "second.json", {"--exit-after-events", std::to_string(records.size())}),
        s.path("second.out"));
    ASSERT_EQ(second.wait_exit(kTimeout_s), std::optional<int>(0)) << second.output();
    EXPECT_EQ(hash_printed(second.output()), expected) << second.output();
    EXPECT_GE(status_value(s, "second.json", "from_journal"), 1.0) << "caught up from the journal";
    producer.kill(SIGTERM);
}

TEST(DisplayProcess, AScribblerInTheSegmentChangesNothing) {
    Scratch s;
    const auto records = test::script();
    write_records(s.path("events.bin"), records);
    const std::string expected = reference_hash(s, records);

    // Events arrive slowly (every 50 ms) while the scribbler works for two seconds.
    Child producer(producer_args(s, {"--period-ms", "50"}), s.path("producer.out"));
    ASSERT_TRUE(producer.wait_output("ready", kTimeout_s)) << producer.output();
    Child display(
        display_args(s, "status.json",
                     {"--exit-after-events", std::to_string(records.size()), "--on-demand"}),
        s.path("display.out"));
    Child scribbler({test::bin("display_test_scribbler"), "--segment", s.session, "--seconds", "2"},
                    s.path("scribbler.out"));
    ASSERT_EQ(scribbler.wait_exit(kTimeout_s), std::optional<int>(0)) << scribbler.output();
    ASSERT_EQ(display.wait_exit(kTimeout_s), std::optional<int>(0)) << display.output();
    EXPECT_EQ(hash_printed(display.output()), expected) << display.output();
    const double rejected = status_value(s, "status.json", "rejected_records") +
                            status_value(s, "status.json", "rejected_indices") +
                            status_value(s, "status.json", "ring_gaps");
    std::printf("scribbler: %s; display counted %.0f rejections and gaps\n",
                scribbler.output().c_str(), rejected);
    producer.kill(SIGTERM);
}

/// The string value of `"key": "..."` in the display's status JSON, or "".
std::string status_string(const Scratch& s, const char* file, const std::string& key) {
    const std::string text = test::read_file(s.path(file));
    std::smatch m;
    return std::regex_search(text, m, std::regex("\"" + key + "\": \"([^\"]*)\"")) ? m[1].str()
                                                                                   : "";
}

/// kerf-rt's loop rate on the HUD line of the status ("haptics  N Hz"), or -1 when not shown.
double hud_haptic_hz(const Scratch& s, const char* file) {
    std::smatch m;
    const std::string text = test::read_file(s.path(file));
    return std::regex_search(text, m, std::regex("haptics  ([0-9]+) Hz")) ? std::stod(m[1].str())
                                                                          : -1;
}

ipc::EventRecord session_reset_record() {
    ipc::EventRecord r{};
    r.header.type = ipc::EventType::kSessionReset;
    r.reset.scene_id = 1;
    r.reset.reason = 1;  // scene loaded
    return r;
}

// Session 1 (a producer standing in for kerf-rt): the whole script, a SessionReset, then cut 1
// again on the reloaded scene. Then that producer dies (kill -9) and another starts the same
// segment name with a new session id and a new journal: the whole script. The display, started
// once, must show after each session exactly what a fresh CutSession shows for that session's
// events after its last reset — nothing carried over.
TEST(DisplayProcess, FollowsASessionResetAndAKerfRtRestartedWithANewSession) {
    Scratch s;
    const auto script = test::script();
    const std::vector<ipc::EventRecord> cut1(script.begin(), script.begin() + 15);  // to CutEnd
    ASSERT_EQ(cut1.back().header.type, ipc::EventType::kCutEnd);
    std::vector<ipc::EventRecord> first = script;
    first.push_back(session_reset_record());
    first.insert(first.end(), cut1.begin(), cut1.end());
    const std::string after_reset = reference_hash(s, cut1);
    const std::string after_restart = reference_hash(s, script);
    ASSERT_NE(after_reset, after_restart);

    write_records(s.path("first.bin"), first);
    write_records(s.path("second.bin"), script);
    const auto producer = [&](const char* records, const char* out) {
        return std::make_unique<Child>(
            std::vector<std::string>{test::bin("display_test_producer"), "--segment", s.session,
                                     "--journal-dir", s.dir.string(), "--records", s.path(records)},
            s.path(out));
    };
    auto one = producer("first.bin", "first.out");
    ASSERT_TRUE(one->wait_output("published " + std::to_string(first.size()), kTimeout_s))
        << one->output();
    Child display(display_args(s, "status.json",
                               {"--hash", "--on-demand", "--screenshot", s.path("last.png")}),
                  s.path("display.out"));
    const auto shows = [&](const std::string& hash, std::size_t events) {
        return status_string(s, "status.json", "hash") == hash &&
               status_value(s, "status.json", "hash_sequence") == double(events) &&
               status_value(s, "status.json", "next_sequence") == double(events);
    };
    ASSERT_TRUE(test::wait_for([&] { return shows(after_reset, first.size()); }, kTimeout_s))
        << display.output() << test::read_file(s.path("status.json"));
    const std::string session_one = status_string(s, "status.json", "session_id");
    EXPECT_EQ(status_value(s, "status.json", "refused"), 0.0);
    // The HUD's sources: the loop rate from the producer's ticks, the depth from cut events.
    EXPECT_TRUE(test::wait_for([&] { return hud_haptic_hz(s, "status.json") > 0; }, kTimeout_s))
        << test::read_file(s.path("status.json"));
    EXPECT_NE(test::read_file(s.path("status.json")).find("depth 12.0 mm"), std::string::npos)
        << "cut 1 ended 12 mm deep";

    one->kill(SIGKILL);  // kerf-rt crashed
    ASSERT_EQ(one->wait_exit(kTimeout_s), std::optional<int>(128 + SIGKILL));
    auto two = producer("second.bin", "second.out");
    ASSERT_TRUE(two->wait_output("published " + std::to_string(script.size()), kTimeout_s))
        << two->output();
    ASSERT_TRUE(test::wait_for([&] { return shows(after_restart, script.size()); }, kTimeout_s))
        << display.output() << test::read_file(s.path("status.json"));
    EXPECT_NE(status_string(s, "status.json", "session_id"), session_one);
    EXPECT_EQ(status_value(s, "status.json", "refused"), 0.0);
    EXPECT_NE(test::read_file(s.path("status.json")).find("depth 4.8 mm"), std::string::npos)
        << "cut 2 withdrawn 4.8 mm deep";
    display.kill(SIGTERM);
    EXPECT_EQ(display.wait_exit(kTimeout_s), std::optional<int>(0)) << display.output();
    // A stop signal still draws the last frame owed to --screenshot (kerf demo keeps it).
    ASSERT_TRUE(fs::is_regular_file(s.path("last.png"))) << display.output();
    EXPECT_GT(fs::file_size(s.path("last.png")), 1000u);
    two->kill(SIGTERM);
}

}  // namespace
}  // namespace kerf::display

namespace kerf::display {
namespace {

TEST(DisplayProcess, RunsInAnX11WindowUnderXvfb) {
    if (!std::filesystem::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run not installed";
    Scratch s;
    Child display({"/usr/bin/xvfb-run", "-a", test::bin("kerf-display"), "--config",
                   s.path("kerf.toml"), "--mode", "window", "--frames", "3"},
                  s.path("window.out"));
    ASSERT_EQ(display.wait_exit(kTimeout_s), std::optional<int>(0)) << display.output();
    EXPECT_NE(display.output().find("3 frames"), std::string::npos) << display.output();
    EXPECT_NE(display.output().find("x11"), std::string::npos) << display.output();
}

}  // namespace
}  // namespace kerf::display
