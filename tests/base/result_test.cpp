#include "config/base/result.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace kerf {
namespace {

Result<int, std::string> parse_positive(int v) {
    if (v <= 0) return Err{std::string("not positive")};
    return v;
}

TEST(Result, HoldsTheValueOrTheError) {
    auto ok = parse_positive(3);
    ASSERT_TRUE(ok);
    EXPECT_EQ(*ok, 3);
    auto bad = parse_positive(-1);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error(), "not positive");
}

TEST(Result, MovesOutMoveOnlyValues) {
    Result<std::unique_ptr<int>, std::string> r = std::make_unique<int>(5);
    ASSERT_TRUE(r.has_value());
    std::unique_ptr<int> p = std::move(r).value();
    EXPECT_EQ(*p, 5);
}

TEST(Status, DefaultIsSuccessAndErrCarriesTheError) {
    Status<std::string> ok;
    EXPECT_TRUE(ok);
    Status<std::string> bad = Err{std::string("no")};
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error(), "no");
}

TEST(ResultDeathTest, ReadingTheWrongSideIsCaughtWhenDebugChecksAreArmed) {
#if defined(KERF_DEBUG_CHECKS) && KERF_DEBUG_CHECKS
    auto bad = parse_positive(0);
    EXPECT_DEATH(static_cast<void>(bad.value()), "value\\(\\) of a Result holding an error");
    auto ok = parse_positive(1);
    EXPECT_DEATH(static_cast<void>(ok.error()), "error\\(\\) of a Result holding a value");
#else
    GTEST_SKIP() << "KERF_DEBUG_CHECKS is off in this build (CI arms it)";
#endif
}

}  // namespace
}  // namespace kerf
