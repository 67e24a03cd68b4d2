#include <gtest/gtest.h>

#include "tools/hapsim/faults.hpp"
#include "tools/hapsim/hand_script.hpp"

namespace kerf::hapsim {
namespace {

TEST(HandScript, ParsesEveryActionWithCommentsAndBlankLines) {
    auto s = parse_hand_script(
        "# a script\n\nmove, 0.01, 0, 0.1, 0.5  # go\nhold,0.25\nbutton,3,down\n"
        "sweep,0.01,0,0,2,1.5\nfault,drop,on\n",
        "t.csv");
    ASSERT_TRUE(s) << s.error().message();
    ASSERT_EQ(s->size(), 5U);
    EXPECT_EQ((*s)[0].kind, ScriptAction::Kind::kMove);
    EXPECT_DOUBLE_EQ((*s)[0].vec[2], 0.1);
    EXPECT_EQ((*s)[0].line, 3);
    EXPECT_EQ((*s)[2].button, 3);
    EXPECT_DOUBLE_EQ((*s)[3].frequency_hz, 2.0);
    EXPECT_EQ((*s)[4].fault_name, "drop");
}

TEST(HandScript, EveryBadLineIsNamedWithFileLineAndReason) {
    const struct {
        const char* text;
        const char* expected;
    } cases[] = {
        {"move,1,2\n", "t.csv:1: move: expected 4 values"},
        {"hold,0.1\nhold,abc\n", "t.csv:2: hold: value 1 'abc' is not a finite number"},
        {"hold,nan\n", "not a finite number"},
        {"hold,-1\n", "hold: duration_s must be >= 0"},
        {"jump,1\n", "unknown action 'jump'"},
        {"button,16,down\n", "button: expected index 0..15"},
        {"button,1,maybe\n", "button: expected index 0..15 and down|up"},
        {"sweep,0,0,0,0,1\n", "sweep: frequency_hz must be > 0"},
        {"fault,drop\n", "fault: expected a name and on|off"},
    };
    for (const auto& c : cases) {
        auto s = parse_hand_script(c.text, "t.csv");
        ASSERT_FALSE(s) << c.text;
        EXPECT_NE(s.error().message().find(c.expected), std::string::npos) << s.error().message();
    }
}

TEST(HandScript, AMissingFileIsAClearError) {
    auto s = load_hand_script("/nonexistent/script.csv");
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().message(), "/nonexistent/script.csv: no such file (unreadable)");
}

TEST(HandPlayer, MovesHoldsSweepsAndFiresFaultsOnTime) {
    auto s = parse_hand_script(
        "move,0.1,0,0,1\nfault,corrupt,on\nhold,1\nbutton,0,down\nsweep,0,0.01,0,1,1\n", "t");
    ASSERT_TRUE(s);
    HandPlayer hand(*s, {0, 0, 0});
    std::vector<FaultEvent> events;
    hand.advance(0.5, events);
    EXPECT_NEAR(hand.position_m()[0], 0.05, 1e-12);
    EXPECT_NEAR(hand.velocity_m_per_s()[0], 0.1, 1e-12);
    EXPECT_TRUE(events.empty());
    hand.advance(1.5, events);
    EXPECT_NEAR(hand.position_m()[0], 0.1, 1e-12);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].name, "corrupt");
    hand.advance(2.25, events);
    EXPECT_EQ(hand.buttons(), 1U);
    EXPECT_NEAR(hand.position_m()[1], 0.01, 1e-9);  // quarter period of a 1 Hz sweep
    hand.advance(10, events);
    EXPECT_TRUE(hand.finished());
}

TEST(Faults, RefusesUnknownNamesAndBadValues) {
    Faults f;
    EXPECT_EQ(apply_fault(f, "drop", "on"), "");
    EXPECT_TRUE(f.drop);
    EXPECT_EQ(apply_fault(f, "delay", "40"), "");
    EXPECT_EQ(f.delay_ms, 40U);
    EXPECT_NE(apply_fault(f, "delay", "-3").find("milliseconds"), std::string::npos);
    EXPECT_NE(apply_fault(f, "drop", "sometimes").find("on or off"), std::string::npos);
    EXPECT_NE(apply_fault(f, "meteor", "on").find("unknown fault 'meteor'"), std::string::npos);
}

}  // namespace
}  // namespace kerf::hapsim
