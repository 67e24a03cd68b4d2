// Force profiles: each kind of bad input gives the error that names it, and the validator the
// live-reload path uses reports every problem of an in-memory profile.
#include "config/force_profile.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/config/config_test_support.hpp"

namespace kerf::config {
namespace {

using test::edit;
using test::error_of;
using test::line_of;
using test::shipped;

const std::string kDefault = shipped("force/default.toml");

ConfigError parse_error(const std::string& text) {
    return error_of(parse_force_profile(text, "force/test.toml"));
}

TEST(ForceProfileParse, SyntaxErrorNamesFileLineAndColumn) {
    auto text = edit(kDefault, "[limits]", "[limits");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kSyntax);
    EXPECT_EQ(e.line, line_of(text, "[limits"));
    EXPECT_GT(e.column, 0u);
    EXPECT_NE(e.message().find("force/test.toml:" + std::to_string(e.line) + ":"),
              std::string::npos)
        << e.message();
    EXPECT_NE(e.message().find("syntax error"), std::string::npos);
}

TEST(ForceProfileParse, MisspeltKeyIsUnknownWithSuggestionAndReportedBeforeTheMissingKey) {
    auto text = edit(kDefault, "stiffness_n_per_m = 1500.0", "stifness_n_per_m = 1500.0");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kUnknownKey);
    EXPECT_EQ(e.key, "contact.stifness_n_per_m");
    EXPECT_EQ(e.line, line_of(text, "stifness_n_per_m"));
    EXPECT_EQ(e.column, 1u);
    EXPECT_NE(e.note.find("did you mean 'stiffness_n_per_m'?"), std::string::npos) << e.note;
    EXPECT_EQ(e.more_problems, 1u);  // the missing contact.stiffness_n_per_m
    EXPECT_NE(e.message().find("[and 1 more problem]"), std::string::npos);
}

TEST(ForceProfileParse, MisspeltTableIsUnknownWithSuggestion) {
    auto text = edit(kDefault, "[saw]", "[sawe]");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kUnknownKey);
    EXPECT_EQ(e.key, "sawe");
    EXPECT_NE(e.note.find("'saw'"), std::string::npos);
}

TEST(ForceProfileParse, StringWhereANumberBelongsIsAWrongType) {
    auto text = edit(kDefault, "damping_n_s_per_m = 2.0", "damping_n_s_per_m = \"2.0\"");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kWrongType);
    EXPECT_EQ(e.key, "contact.damping_n_s_per_m");
    EXPECT_EQ(e.value, "\"2.0\"");
    EXPECT_EQ(e.line, line_of(text, "damping_n_s_per_m"));
    EXPECT_NE(e.expected.find("a number"), std::string::npos);
    EXPECT_NE(e.note.find("got a string"), std::string::npos);
}

TEST(ForceProfileParse, FractionWhereAnIntegerBelongsIsAWrongType) {
    auto e = parse_error(edit(kDefault, "engage_quiet_ticks = 50", "engage_quiet_ticks = 50.5"));
    EXPECT_EQ(e.code, ConfigErrc::kWrongType);
    EXPECT_EQ(e.key, "limits.engage_quiet_ticks");
    EXPECT_NE(e.expected.find("an integer"), std::string::npos);
}

TEST(ForceProfileParse, NegativeStiffnessIsOutOfRangeAndSaysTheRange) {
    auto text = edit(kDefault, "stiffness_n_per_m = 1500.0", "stiffness_n_per_m = -1500.0");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.value, "-1500");
    EXPECT_EQ(e.expected, "0 < value <= 100000 N/m");
    EXPECT_EQ(e.message(), "force/test.toml:" + std::to_string(line_of(text, "stiffness_n")) +
                               ":21: contact.stiffness_n_per_m = -1500: out of range "
                               "(expected 0 < value <= 100000 N/m) (out_of_range)");
}

TEST(ForceProfileParse, MissingRequiredKeyIsNamedWithItsTable) {
    auto text = edit(kDefault, "ramp_in_s = 0.5", "");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kMissingKey);
    EXPECT_EQ(e.key, "limits.ramp_in_s");
    EXPECT_EQ(e.line, line_of(text, "[limits]"));
    EXPECT_NE(e.expected.find("0 <= value <= 10 s"), std::string::npos);
}

TEST(ForceProfileParse, MissingRequiredTableIsNamed) {
    auto text = kDefault.substr(0, kDefault.find("[saw]"));
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kMissingKey);
    EXPECT_EQ(e.key, "saw");
}

TEST(ForceProfileParse, InfinityAndNanAreNotFinite) {
    for (const char* bad : {"inf", "-inf", "nan", "+nan"}) {
        auto e =
            parse_error(edit(kDefault, "max_force_n = 8.0", std::string("max_force_n = ") + bad));
        EXPECT_EQ(e.code, ConfigErrc::kNonFinite) << bad;
        EXPECT_EQ(e.key, "limits.max_force_n");
        EXPECT_NE(e.expected.find("a finite number"), std::string::npos);
    }
}

TEST(ForceProfileParse, UnitSuffixOtherThanTheSchemaIsABadUnit) {
    auto text = edit(kDefault, "kerf_width_m = 0.0008", "kerf_width_mm = 0.8");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kBadUnit);
    EXPECT_EQ(e.key, "saw.kerf_width_mm");
    EXPECT_EQ(e.line, line_of(text, "kerf_width_mm"));
    EXPECT_NE(e.note.find("'kerf_width_m'"), std::string::npos) << e.note;
}

TEST(ForceProfileParse, KeyWithoutItsUnitIsABadUnit) {
    auto e = parse_error(edit(kDefault, "stiffness_n_per_m = 1500.0", "stiffness = 1500.0"));
    EXPECT_EQ(e.code, ConfigErrc::kBadUnit);
    EXPECT_EQ(e.key, "contact.stiffness");
    EXPECT_NE(e.note.find("'stiffness_n_per_m'"), std::string::npos);
}

TEST(ForceProfileParse, DynamicFrictionAboveStaticIsReportedAtTheDynamicKey) {
    auto text = edit(kDefault, "dynamic_friction_n = 0.25", "dynamic_friction_n = 0.5");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "contact.dynamic_friction_n");
    EXPECT_EQ(e.line, line_of(text, "dynamic_friction_n"));
    EXPECT_NE(e.expected.find("contact.static_friction_n (0.4 N)"), std::string::npos);
}

TEST(ForceProfileParse, KerfWiderThanTheBladeIsDeepIsRejected) {
    auto e = parse_error(
        edit(kDefault, "kerf_width_m = 0.0008", "kerf_width_m = 0.004")
            .replace(kDefault.find("blade_depth_m = 0.010"), 21, "blade_depth_m = 0.003"));
    EXPECT_EQ(e.code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(e.key, "saw.kerf_width_m");
}

TEST(ForceProfileParse, EveryProblemIsCounted) {
    auto text = edit(edit(edit(kDefault, "ramp_in_s = 0.5", "ramp_in_s = -1.0"),
                          "speed_rpm = 12000.0", "speed_rpm = \"fast\""),
                     "[saw]", "[saw]\nteeth = 24");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kUnknownKey);
    EXPECT_EQ(e.key, "saw.teeth");
    EXPECT_EQ(e.more_problems, 2u);
}

TEST(ForceProfileParse, EmptyAndBinaryInputAreErrorsNotCrashes) {
    EXPECT_EQ(parse_error("").code, ConfigErrc::kMissingKey);
    EXPECT_EQ(parse_error(std::string("\0\xff\xfe", 3)).code, ConfigErrc::kSyntax);
    EXPECT_EQ(parse_error("name = 3\n").code, ConfigErrc::kWrongType);
}

TEST(ForceProfileParse, DuplicateKeyIsASyntaxErrorAtTheSecondDefinition) {
    auto text = edit(kDefault, "ramp_in_s = 0.5", "ramp_in_s = 0.5\nramp_in_s = 0.7");
    auto e = parse_error(text);
    EXPECT_EQ(e.code, ConfigErrc::kSyntax);
    EXPECT_EQ(e.line, line_of(text, "ramp_in_s = 0.7"));
}

TEST(ForceProfileParse, HugeOrControlCharacterValuesAreQuotedAndTruncated) {
    std::string huge(5000, 'x');
    auto e = parse_error(edit(kDefault, "speed_rpm = 12000.0", "speed_rpm = \"" + huge + "\""));
    EXPECT_EQ(e.code, ConfigErrc::kWrongType);
    EXPECT_LE(e.value.size(), 60u);
    EXPECT_LT(e.message().size(), 400u);
    auto c = parse_error(edit(kDefault, "speed_rpm = 12000.0", "speed_rpm = \"a\\u0007b\""));
    EXPECT_EQ(c.value, "\"a\\x07b\"");
}

TEST(ForceProfileLoad, MissingFileIsAnIoErrorNamingThePath) {
    auto e = error_of(load_force_profile("/nonexistent/kerf/force.toml"));
    EXPECT_EQ(e.code, ConfigErrc::kIo);
    EXPECT_EQ(e.source, "/nonexistent/kerf/force.toml");
    EXPECT_NE(e.message().find("/nonexistent/kerf/force.toml: cannot read: no such file"),
              std::string::npos)
        << e.message();
}

TEST(ForceProfileLoad, DirectoryIsAnIoError) {
    auto e = error_of(load_force_profile(test::kConfigDir / "force"));
    EXPECT_EQ(e.code, ConfigErrc::kIo);
    EXPECT_NE(e.note.find("not a regular file"), std::string::npos);
}

ForceProfile valid_profile() {
    auto p = parse_force_profile(kDefault, "default");
    EXPECT_TRUE(p);
    return p ? *p : ForceProfile{};
}

TEST(ForceProfileValidator, ShippedProfileHasNoProblems) {
    EXPECT_TRUE(validate_force_profile(valid_profile()).empty());
}

TEST(ForceProfileValidator, ReportsEveryProblemWithKeyAndValue) {
    ForceProfile p = valid_profile();
    p.contact.stiffness_n_per_m = std::numeric_limits<double>::quiet_NaN();
    p.limits.slew_rate_n_per_s = -1.0;
    p.cancellous.plane_lock_stiffness_n_per_m = std::numeric_limits<double>::infinity();
    p.limits.engage_quiet_ticks = 20'000;
    auto problems = validate_force_profile(p);
    ASSERT_EQ(problems.size(), 4u);
    EXPECT_EQ(problems[0].code, ConfigErrc::kNonFinite);
    EXPECT_EQ(problems[0].key, "contact.stiffness_n_per_m");
    EXPECT_EQ(problems[0].value, "nan");
    EXPECT_EQ(problems[1].code, ConfigErrc::kOutOfRange);
    EXPECT_EQ(problems[1].key, "limits.slew_rate_n_per_s");
    EXPECT_EQ(problems[2].key, "cutting.cancellous.plane_lock_stiffness_n_per_m");
    EXPECT_EQ(problems[3].key, "limits.engage_quiet_ticks");
    for (const auto& e : problems) EXPECT_EQ(e.line, 0u);
}

TEST(ForceProfileValidator, ChecksCrossFieldRules) {
    ForceProfile p = valid_profile();
    p.limits.engage_threshold_n = p.limits.max_force_n + 1.0;
    auto problems = validate_force_profile(p);
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_EQ(problems[0].key, "limits.engage_threshold_n");
    EXPECT_NE(problems[0].message().find("<= limits.max_force_n (8 N)"), std::string::npos)
        << problems[0].message();
}

}  // namespace
}  // namespace kerf::config
