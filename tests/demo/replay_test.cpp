// kerf replay of a recorded demo: kerf-rt re-run in lockstep on the recorded device input, with
// kerf-display and without one, reproduces the event stream, the per-tick force trace and the
// final mesh hash bit for bit; a tampered input stream is caught; a folder that is not a
// recording is refused by name.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "tests/run_process.hpp"

namespace {

namespace fs = std::filesystem;
using kerf::test::run_program;

nlohmann::json parse(const std::string& text) {
    return nlohmann::json::parse(text, nullptr, false);
}

class KerfReplay : public ::testing::Test {
protected:
    void SetUp() override {
        if (access(KERF_BIN_DIR "/kerf-rt", X_OK) != 0) GTEST_SKIP() << "no kerf-rt built";
        root_ = fs::temp_directory_path() / ("kerf-replay-test-" + std::to_string(getpid()));
        fs::create_directories(root_);
    }
    void TearDown() override {
        std::error_code ec;
        if (!root_.empty()) fs::remove_all(root_, ec);
    }
    fs::path root_;
};

TEST_F(KerfReplay, ReplayOfARecordedDemoReproducesEventsForcesAndHash) {
    const fs::path out = root_ / "demo";
    const auto demo = run_program(
        root_, "kerf", {"demo", "--lockstep", "--triangles", "20000", "--json", "-o", out},
        std::chrono::seconds(240));
    ASSERT_EQ(demo.exit_code, 0) << demo.out << demo.err;
    const auto report = parse(demo.out);
    ASSERT_FALSE(report.is_discarded()) << demo.out;
    const std::string hash = report["hash"];
    const auto meta = parse(kerf::test::slurp(out / "recording/recording.json"));
    ASSERT_FALSE(meta.is_discarded());
    EXPECT_EQ(meta["hash"], hash);
    EXPECT_EQ(meta["ticks"], report["ticks"]);
    EXPECT_EQ(fs::file_size(out / "recording/input.rec"),
              64u + 128u * meta["ticks"].get<std::uint64_t>());
    // The recording keeps kerf.toml and the profiles it names, not the whole config folder (the
    // replays below need nothing else).
    std::set<std::string> kept;
    for (const auto& e : fs::recursive_directory_iterator(out / "recording/config"))
        if (e.is_regular_file()) kept.insert(fs::relative(e.path(), out / "recording/config"));
    EXPECT_EQ(kept, (std::set<std::string>{"devices/simulated.toml", "force/default.toml",
                                           "kerf.toml", "scenes/builtin_foot.toml"}));

    for (const bool with_display : {true, false}) {
        std::vector<std::string> args = {"replay", (out / "recording").string(), "--json"};
        if (!with_display) args.push_back("--no-display");
        const auto replay = run_program(root_, "kerf", args, std::chrono::seconds(240));
        ASSERT_EQ(replay.exit_code, 0) << replay.out << replay.err;
        const auto r = parse(replay.out);
        ASSERT_FALSE(r.is_discarded()) << replay.out;
        EXPECT_EQ(r["ticks"], meta["ticks"]) << replay.out;
        EXPECT_EQ(r["events"], report["events"]) << replay.out;
        EXPECT_EQ(r["events_equal"], true) << replay.out;
        EXPECT_EQ(r["trace_compared"], true) << replay.out;
        EXPECT_EQ(r["trace_equal"], true) << replay.out;
        EXPECT_EQ(r["hash"], hash) << replay.out;
        EXPECT_EQ(r["hash_equal"], true) << replay.out;
        EXPECT_EQ(r["worlds_not_ready"], 0) << replay.out;
    }

    // The comparison is not vacuous: move the tool 2 mm for 50 ticks mid-surgery.
    const fs::path tampered = root_ / "tampered";
    fs::copy(out / "recording", tampered, fs::copy_options::recursive);
    {
        std::fstream f(tampered / "input.rec", std::ios::in | std::ios::out | std::ios::binary);
        const std::uint64_t ticks = meta["ticks"];
        for (std::uint64_t t = ticks / 2; t < ticks / 2 + 50; ++t) {
            const std::streamoff at = 64 + std::streamoff(t) * 128 + 40;  // position_m[0]
            double x = 0;
            f.seekg(at);
            f.read(reinterpret_cast<char*>(&x), sizeof x);
            x += 0.002;
            f.seekp(at);
            f.write(reinterpret_cast<const char*>(&x), sizeof x);
        }
        ASSERT_TRUE(f.good());
    }
    const auto bad =
        run_program(root_, "kerf", {"replay", tampered.string(), "--json", "--no-display"},
                    std::chrono::seconds(240));
    EXPECT_EQ(bad.exit_code, 1) << bad.out << bad.err;
    const auto b = parse(bad.out);
    ASSERT_FALSE(b.is_discarded()) << bad.out << bad.err;
    EXPECT_EQ(b["trace_equal"], false) << bad.out;

    // An input stream that stops before the session's last tick (format 2 stopped where a device
    // was lost; a cut-short file) is refused up front, saying why.
    const fs::path cut_short = root_ / "cut-short";
    fs::copy(out / "recording", cut_short, fs::copy_options::recursive);
    fs::resize_file(cut_short / "input.rec", fs::file_size(cut_short / "input.rec") - 128 * 1000);
    const auto refused = run_program(root_, "kerf", {"replay", cut_short.string(), "--no-display"});
    EXPECT_EQ(refused.exit_code, 1) << refused.out << refused.err;
    EXPECT_NE(refused.err.find("ticks recorded: the input stream stops there"), std::string::npos)
        << refused.err;
}

TEST_F(KerfReplay, AFolderThatIsNotARecordingIsRefusedByName) {
    const auto r = run_program(root_, "kerf", {"replay", root_.string()});
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find((root_ / "recording.json").string()), std::string::npos) << r.err;
    std::ofstream(root_ / "recording.json") << "{\"device\": \"simulated\"";
    const auto broken = run_program(root_, "kerf", {"replay", root_.string()});
    EXPECT_EQ(broken.exit_code, 1);
    EXPECT_NE(broken.err.find("not valid JSON"), std::string::npos) << broken.err;
}

}  // namespace
