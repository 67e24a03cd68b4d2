// kerf soak's plans: the --faults list and the random hand scripts (inside the device's
// workspace, as long as asked, the same for the same seed, every cut through its target).
#include "tools/kerf/soak_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace kerf::cli {
namespace {

std::vector<CutTarget> two_bones() {
    return {{0.01, 0.02, 0.012, -0.008}, {-0.02, -0.01, 0.010, -0.010}};
}

TEST(SoakFaultList, AllNoneAndNamesParse) {
    EXPECT_EQ(parse_fault_list("all")->size(), std::size_t(kSoakFaultCount));
    EXPECT_TRUE(parse_fault_list("none")->empty());
    const auto some = parse_fault_list("drop,display-kill,scribble,drop");
    ASSERT_TRUE(some);
    EXPECT_EQ(*some, (std::vector<SoakFault>{SoakFault::kDrop, SoakFault::kDisplayKill,
                                             SoakFault::kScribble}));
}

TEST(SoakFaultList, AnUnknownNameIsRefusedByName) {
    const auto bad = parse_fault_list("drop,unplugg");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("'unplugg'"), std::string::npos) << bad.error();
    EXPECT_NE(bad.error().find("stuck-encoder"), std::string::npos) << bad.error();
    EXPECT_FALSE(parse_fault_list(""));
}

TEST(SoakFaultList, DeviceFaultsHaveHapsimCommandsThatClear) {
    EXPECT_EQ(hapsim_on_command(SoakFault::kDelay), "fault delay 50");
    EXPECT_EQ(hapsim_off_command(SoakFault::kDelay), "fault delay off");
    EXPECT_EQ(hapsim_on_command(SoakFault::kStuckEncoder), "fault stuck_encoder on");
    EXPECT_EQ(hapsim_off_command(SoakFault::kUnplug), "fault unplug off");
    EXPECT_TRUE(is_device_fault(SoakFault::kEStop));
    EXPECT_FALSE(is_device_fault(SoakFault::kDisplayStop));
}

/// The script's moves, device frame.
std::vector<std::array<double, 3>> moves(const std::string& csv) {
    std::vector<std::array<double, 3>> out;
    std::istringstream in(csv);
    std::string line;
    while (std::getline(in, line)) {
        std::array<double, 3> p{};
        double s = 0;
        if (std::sscanf(line.c_str(), "move,%lf,%lf,%lf,%lf", &p[0], &p[1], &p[2], &s) == 4)
            out.push_back(p);
    }
    return out;
}

TEST(SoakRoundScript, StaysInTheWorkspaceAndLastsAboutAsLongAsAsked) {
    const mesh::Point origin{0, 0.032, 0};
    RoundScriptParams p;
    p.duration_s = 90;
    const auto script = make_round_script(two_bones(), origin, 7, p);
    ASSERT_TRUE(script) << script.error();
    EXPECT_GE(script->duration_s, 90 - 45);  // a chevron or a slab takes ~40 s
    EXPECT_LE(script->duration_s, 90 + 30);  // the last may be longer than the one before
    ASSERT_GE(script->cuts.size(), 3u);
    for (const auto& m : moves(script->csv))
        for (double c : m) EXPECT_LE(std::abs(c), p.workspace_half_m);
    for (const PlannedCut& c : script->cuts) {
        EXPECT_LE(std::abs(c.tilt_deg), p.max_tilt_deg);
        EXPECT_GE(c.feed_m_s, p.feed_min_m_s);
        EXPECT_LE(c.feed_m_s, p.feed_max_m_s);
        EXPECT_GT(c.feed_end_s, c.feed_start_s);
    }
}

TEST(SoakRoundScript, TheSameSeedGivesTheSameScriptAndAnotherSeedAnother) {
    const mesh::Point origin{0, 0.032, 0};
    const auto a = make_round_script(two_bones(), origin, 3);
    const auto b = make_round_script(two_bones(), origin, 3);
    const auto c = make_round_script(two_bones(), origin, 4);
    ASSERT_TRUE(a && b && c);
    EXPECT_EQ(a->csv, b->csv);
    EXPECT_NE(a->csv, c->csv);
}

TEST(SoakRoundScript, EveryFeedStartsAboveTheBoneAndEndsBelowIt) {
    const mesh::Point origin{0, 0.032, 0};
    const std::vector<CutTarget> one = {{0.0, 0.0, 0.012, -0.008}};
    const auto script = make_round_script(one, origin, 11);
    ASSERT_TRUE(script);
    // The saw is switched on just above the bone and off below it: the move between them is the
    // feed.
    std::istringstream in(script->csv);
    std::string line;
    bool saw_on = false;
    double y = 0;
    int feeds = 0;
    while (std::getline(in, line)) {
        double x, yy, z, s;
        if (std::sscanf(line.c_str(), "move,%lf,%lf,%lf,%lf", &x, &yy, &z, &s) == 4) {
            if (saw_on) {
                EXPECT_GT(y + origin[1], 0.012) << "feed starts inside the bone";
                EXPECT_LT(yy + origin[1], -0.008) << "feed ends inside the bone";
                ++feeds;
            }
            y = yy;
        }
        if (line == "button,0,down") saw_on = true;
        if (line == "button,0,up") saw_on = false;
    }
    EXPECT_EQ(feeds, int(script->cuts.size()));
}

TEST(SoakRoundScript, NoTargetIsAnError) {
    EXPECT_FALSE(make_round_script({}, mesh::Point{0, 0, 0}, 1));
}

}  // namespace
}  // namespace kerf::cli
