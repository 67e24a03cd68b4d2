#include "config/base/check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>

#include "tests/allocation_counter.hpp"

namespace kerf {
namespace {

enum class LoopFault : std::uint16_t { kNonFiniteForce = 7, kStaleSample = 9 };

TEST(KerfEnforce, PassingCheckDoesNothing) {
    int evaluated = 0;
    KERF_ENFORCE(++evaluated == 1, "evaluated once");
    EXPECT_EQ(evaluated, 1);
}

TEST(KerfEnforceDeathTest, FailingCheckPrintsFileLineConditionAndMessageThenAborts) {
    const int tool_count = 3;
    EXPECT_DEATH(KERF_ENFORCE(tool_count == 2, "a saw has two blades"),
                 "check_test\\.cpp:[0-9]+: check `tool_count == 2` failed: a saw has two blades");
}

TEST(KerfAssertDeathTest, IsArmedExactlyWhenTheBuildSaysSo) {
#if defined(KERF_DEBUG_CHECKS) && KERF_DEBUG_CHECKS
    EXPECT_DEATH(KERF_ASSERT(1 + 1 == 3, "arithmetic"), "check `1 \\+ 1 == 3` failed: arithmetic");
#else
    int evaluated = 0;
    KERF_ASSERT(++evaluated == 5, "never evaluated when disarmed");
    EXPECT_EQ(evaluated, 0);
#endif
}

TEST(KerfRtCheck, PassingCheckIsTrueAndRecordsNothing) {
    FaultLatch latch;
    EXPECT_TRUE(KERF_RT_CHECK(2 > 1, latch, LoopFault::kStaleSample));
    EXPECT_FALSE(latch.tripped());
    EXPECT_EQ(latch.failures(), 0u);
    EXPECT_FALSE(latch.first().has_value());
}

TEST(KerfRtCheck, FailingCheckIsFalseAndLatchesWhereAndWhich) {
    FaultLatch latch;
    const double force = std::numeric_limits<double>::quiet_NaN();
    const int line = __LINE__ + 1;
    const bool ok = KERF_RT_CHECK(std::isfinite(force), latch, LoopFault::kNonFiniteForce);
    EXPECT_FALSE(ok);
    ASSERT_TRUE(latch.tripped());
    const auto fault = latch.first();
    ASSERT_TRUE(fault.has_value());
    EXPECT_NE(std::string_view(fault->file).find("check_test.cpp"), std::string_view::npos);
    EXPECT_EQ(fault->line, static_cast<std::uint32_t>(line));
    EXPECT_EQ(fault->code, 7u);
    EXPECT_EQ(std::string_view(fault->condition), "std::isfinite(force)");
}

TEST(KerfRtCheck, FirstFaultWinsAndEveryFailureIsCounted) {
    FaultLatch latch;
    EXPECT_FALSE(KERF_RT_CHECK(false, latch, LoopFault::kStaleSample));
    EXPECT_FALSE(KERF_RT_CHECK(1 == 2, latch, LoopFault::kNonFiniteForce));
    EXPECT_FALSE(KERF_RT_CHECK(1 == 2, latch, LoopFault::kNonFiniteForce));
    EXPECT_EQ(latch.failures(), 3u);
    ASSERT_TRUE(latch.first().has_value());
    EXPECT_EQ(latch.first()->code, 9u);
    EXPECT_EQ(std::string_view(latch.first()->condition), "false");
}

TEST(KerfRtCheck, ClearRearmsTheLatch) {
    FaultLatch latch;
    EXPECT_FALSE(KERF_RT_CHECK(false, latch, LoopFault::kStaleSample));
    latch.clear();
    EXPECT_FALSE(latch.tripped());
    EXPECT_EQ(latch.failures(), 0u);
    EXPECT_FALSE(KERF_RT_CHECK(false, latch, LoopFault::kNonFiniteForce));
    ASSERT_TRUE(latch.first().has_value());
    EXPECT_EQ(latch.first()->code, 7u);
}

TEST(KerfRtCheck, NeverAllocatesPassingFailingOrReading) {
    FaultLatch latch;
    std::uint32_t passed = 0;
    double x = 0.0;
    test::arm_allocation_counter();
    for (int tick = 0; tick < 10'000; ++tick) {
        x += 1e-3;
        if (KERF_RT_CHECK(x < 5.0, latch, LoopFault::kNonFiniteForce)) ++passed;
        if (latch.first()) x += 0.0;  // the loop polls the latch every tick
    }
    const std::uint64_t allocations = test::disarm_allocation_counter();
    EXPECT_EQ(allocations, 0u);
    EXPECT_EQ(passed, 4999u);  // x < 5.0 holds for ticks 0..4998 (x = 0.001 .. 4.999)
    EXPECT_EQ(latch.failures(), 5001u);
    EXPECT_TRUE(latch.tripped());
}

TEST(FaultLatch, IsLockFreeAndSmall) {
    EXPECT_TRUE(std::atomic<std::uint32_t>::is_always_lock_free);
    EXPECT_LE(sizeof(FaultLatch), 64u);  // fits one cache line, lives inside the loop object
}

}  // namespace
}  // namespace kerf
