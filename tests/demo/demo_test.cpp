// kerf demo end to end, as a person runs it: real processes, real shared memory, real EGL.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/// Names in /tmp and /dev/shm that the demo with process id `pid` may leave behind (its work
/// folder kerf-demo-PID-*, its session kerf-demo-PID: segment, journal, socket).
std::set<std::string> leftovers(pid_t pid) {
    const std::string mark = "kerf-demo-" + std::to_string(pid);
    std::set<std::string> out;
    for (const char* dir : {"/tmp", "/dev/shm"}) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(dir, ec)) {
            const std::string name = e.path().filename().string();
            if (name.find(mark) != std::string::npos) out.insert(e.path().string());
        }
    }
    // A child still running (its command line names the work folder or the session).
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc", ec)) {
        std::string cmdline = slurp(e.path() / "cmdline");
        std::replace(cmdline.begin(), cmdline.end(), '\0', ' ');
        if (cmdline.find(mark) != std::string::npos) out.insert("process " + cmdline);
    }
    return out;
}

/// Starts `kerf demo ARGS` with stdout+stderr into `log`; returns its pid.
pid_t start_demo(const std::vector<std::string>& args, const fs::path& log) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::freopen(log.c_str(), "w", stdout);
        dup2(fileno(stdout), 2);
        std::vector<char*> argv;
        static std::string exe = std::string(KERF_BIN_DIR) + "/kerf";
        argv.push_back(exe.data());
        static std::string demo = "demo";
        argv.push_back(demo.data());
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(exe.c_str(), argv.data());
        _exit(127);
    }
    return pid;
}

int wait_exit(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// The report's `key` as text ("true", "2", "\"0123...\"").
std::string value(const std::string& json, const std::string& key) {
    const auto doc = nlohmann::json::parse(json, nullptr, false);
    if (doc.is_discarded() || !doc.contains(key)) return {};
    const auto& v = doc[key];
    if (v.is_number_float()) return std::to_string(std::llround(v.get<double>()));
    return v.dump();
}

fs::path temp_out(const std::string& stem) {
    return fs::temp_directory_path() / (stem + "-" + std::to_string(getpid()));
}

/// The demo needs kerf-rt built beside it (the real-time process; it lands with its own issue).
bool have_rt() { return access((std::string(KERF_BIN_DIR) + "/kerf-rt").c_str(), X_OK) == 0; }

/// The two limbs freed the head (one more body: the first metatarsal's 2 pieces), the head is
/// the smaller piece and a plausible one, and the hand's grab moved it (BodyMoved, applied).
void expect_head_freed_and_shifted(const std::string& report) {
    const auto doc = nlohmann::json::parse(report, nullptr, false);
    ASSERT_FALSE(doc.is_discarded()) << report;
    EXPECT_EQ(doc.value("bodies_after", 0), doc.value("bodies_before", 0) + 1) << report;
    EXPECT_GT(doc.value("body_moves", 0), 10) << report;  // one per 0.1 mm of a 4 mm shift
    ASSERT_TRUE(doc.contains("pieces") && doc["pieces"].size() == 2u) << report;
    const auto& shaft = doc["pieces"][0];
    const auto& head = doc["pieces"][1];
    EXPECT_EQ(head.value("parent", -2), shaft.value("body", -1)) << report;
    EXPECT_EQ(head.value("severed_by_cut", 0), 2) << report;  // freed when the second limb ended
    const double head_mm3 = head.value("volume_mm3", 0.0);
    const double shaft_mm3 = shaft.value("volume_mm3", 0.0);
    // The head: the distal fifth of the bone and the chevron's wedges, about 3,000 mm^3 of the
    // metatarsal's 10,600; never a crumb, never most of the bone.
    EXPECT_GT(head_mm3, 0.15 * (head_mm3 + shaft_mm3)) << report;
    EXPECT_LT(head_mm3, 0.5 * (head_mm3 + shaft_mm3)) << report;
    // The head moved 4 mm laterally (towards the second ray: -x), the shaft stayed.
    ASSERT_EQ(head["position_mm"].size(), 3u) << report;
    EXPECT_NEAR(head["position_mm"][0].get<double>(), -4.0, 0.3) << report;
    EXPECT_NEAR(head["position_mm"][1].get<double>(), 0.0, 0.3) << report;
    EXPECT_NEAR(head["position_mm"][2].get<double>(), 0.0, 0.3) << report;
    EXPECT_EQ(shaft["position_mm"][0].get<double>(), 0.0) << report;
}

std::string run_lockstep(const std::string& stem) {
    const fs::path out = temp_out(stem);
    const pid_t pid = start_demo({"--lockstep", "--triangles", "20000", "--json", "-o", out},
                                 out.string() + ".log");
    const int rc = wait_exit(pid);
    EXPECT_TRUE(leftovers(pid).empty()) << "the demo left files behind";
    const std::string log = slurp(out.string() + ".log");
    EXPECT_EQ(rc, 0) << log;
    const std::string report = slurp(out / "report.json");
    for (const char* png : {"1-before.png", "2-mid-cut.png", "3-after.png"})
        EXPECT_TRUE(fs::exists(out / png) && fs::file_size(out / png) > 10'000u) << png;
    EXPECT_TRUE(fs::exists(out / "session.journal"));
    EXPECT_EQ(value(report, "hashes_equal"), "true") << report;
    // A true chevron: both limbs withdrawn inside the bone, none cut through.
    EXPECT_EQ(value(report, "cuts_completed"), "0") << report;
    EXPECT_EQ(value(report, "cuts_ended_otherwise"), "2") << report;
    EXPECT_EQ(value(report, "ticks"), std::to_string(std::stol(value(report, "surgery_s")) * 1000))
        << report;
    EXPECT_EQ(value(report, "cut_begins"), "2") << report;  // one per limb, none spurious
    EXPECT_EQ(value(report, "refused"), "0") << report;
    EXPECT_EQ(value(report, "safe_state_entries"), "0") << report;
    EXPECT_NE(value(report, "force_peak_n"), "0") << report;
    expect_head_freed_and_shifted(report);
    // --json prints exactly the report, one document.
    EXPECT_EQ(log, report) << log;
    EXPECT_FALSE(nlohmann::json::parse(log, nullptr, false).is_discarded()) << log;
    const std::string hash = value(report, "hash");
    std::error_code ec;
    fs::remove_all(out, ec);
    fs::remove(out.string() + ".log", ec);
    return hash;
}

TEST(KerfDemo, LockstepRunsFreeAndShiftTheHeadAndGiveTheSameHash) {
    if (!have_rt()) GTEST_SKIP() << "no kerf-rt in " << KERF_BIN_DIR;
    const std::string a = run_lockstep("kdemo-test-a");
    const std::string b = run_lockstep("kdemo-test-b");
    EXPECT_EQ(a.size(), 18u) << a;  // "0123456789abcdef" with its quotes
    EXPECT_EQ(a, b) << "two --lockstep demos gave different meshes";
}

TEST(KerfDemo, CtrlCMidRunStopsEverythingAndLeavesNothing) {
    if (!have_rt()) GTEST_SKIP() << "no kerf-rt in " << KERF_BIN_DIR;
    const fs::path out = temp_out("kdemo-test-int");
    // Real time: the surgery takes 49 s, so the signal lands while the saw is in use.
    const pid_t pid = start_demo({"--triangles", "20000", "-o", out}, out.string() + ".log");
    std::this_thread::sleep_for(std::chrono::seconds(8));
    kill(pid, SIGINT);
    const int rc = wait_exit(pid);
    const std::string log = slurp(out.string() + ".log");
    EXPECT_EQ(rc, 130) << log;
    EXPECT_NE(log.find("stopped by signal 2"), std::string::npos) << log;
    // No child left: kerf-rt's summary was written (it stopped in order, forces to zero).
    EXPECT_NE(log.find("kerf-rt summary"), std::string::npos) << log;
    EXPECT_TRUE(leftovers(pid).empty()) << log;
    std::error_code ec;
    fs::remove_all(out, ec);
    fs::remove(out.string() + ".log", ec);
}

}  // namespace
