// kerf::Error<Code> and format_error(): the one printed form of every failure in Kerf.
#include "config/base/error.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string_view>

namespace kerf::test_error {

enum class SampleErrc : std::uint8_t { kBadValue, kMissing };
std::string_view to_string(SampleErrc c) noexcept {
    return c == SampleErrc::kBadValue ? "bad_value" : "missing";
}
using SampleError = Error<SampleErrc>;

enum class CharStarErrc { kA };
const char* to_string(CharStarErrc) noexcept { return "a"; }
enum class ThrowingErrc { kA };
std::string_view to_string(ThrowingErrc) { return "a"; }

// The concept admits only enums whose to_string is noexcept and returns std::string_view.
static_assert(ErrorCode<SampleErrc>);
static_assert(!ErrorCode<CharStarErrc>);
static_assert(!ErrorCode<ThrowingErrc>);
static_assert(!ErrorCode<int>);

TEST(Error, PrintsWhereWhatAndTheCodeName) {
    const SampleError e{SampleErrc::kBadValue, "scene.toml:12:3", "units = \"furlong\""};
    EXPECT_EQ(e.message(), "scene.toml:12:3: units = \"furlong\" (bad_value)");
    EXPECT_EQ(e.message(), format_error(e.where, e.what, to_string(e.code)));
}

TEST(Error, LeavesOutAnEmptyWhereOrWhat) {
    EXPECT_EQ((SampleError{SampleErrc::kMissing, "", "no slot free"}.message()),
              "no slot free (missing)");
    EXPECT_EQ((SampleError{SampleErrc::kMissing, "/dev/ttyUSB0", ""}.message()),
              "/dev/ttyUSB0 (missing)");
    EXPECT_EQ(format_error("", "", "missing"), "(missing)");
}

TEST(Error, DefaultIsTheFirstCodeWithNoText) {
    const SampleError e{};
    EXPECT_EQ(e.code, SampleErrc::kBadValue);
    EXPECT_TRUE(e.where.empty());
    EXPECT_TRUE(e.what.empty());
}

}  // namespace kerf::test_error
