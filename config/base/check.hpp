// Kerf's assertions, in three strengths (like drake's DRAKE_DEMAND / DRAKE_ASSERT and iceoryx's
// IOX_ENFORCE / IOX_ASSERT, plus a form for the real-time loop):
//
//   KERF_ENFORCE(cond, msg)  always on, every build. On failure prints "file:line: check `cond`
//                            failed: msg" to stderr and aborts. For invariants whose breach
//                            leaves no safe way on, OUTSIDE real-time code.
//   KERF_ASSERT(cond, msg)   the same, but only in builds configured with -DKERF_DEBUG_CHECKS=ON
//                            (CI arms it: tools/setup.sh --debug-checks). Elsewhere `cond` is not
//                            evaluated (it must have no side effect). For checks too costly to
//                            keep in a release build.
//   KERF_RT_CHECK(cond, latch, code)
//                            for the 1 kHz loop: never aborts, never allocates, never blocks,
//                            never logs. Evaluates to `cond` as a bool; when false it records
//                            {file, line, code, condition text} in the caller-owned FaultLatch
//                            (wait-free, first fault kept, every failure counted), so the loop
//                            commands zero force this tick and reports the fault outside the loop.
//
// Real-time use (the loop owns the latch; `code` is any enum the module defines):
//
//   enum class LoopFault : std::uint16_t { kNonFiniteForce = 1, kStaleSample };
//   FaultLatch faults_;                                   // a member of the loop, built at start
//   ...
//   void Loop::tick() noexcept {                          // 1 kHz, SCHED_FIFO
//       Vec3 f = physics_.force(state_);
//       if (!KERF_RT_CHECK(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z),
//                          faults_, LoopFault::kNonFiniteForce)) {
//           f = Vec3{0, 0, 0};                            // zero force this tick
//       }
//       if (faults_.tripped()) f = Vec3{0, 0, 0};         // and every tick until cleared
//       device_.try_write({f, faults_.tripped()});
//   }
//   // outside the loop (e.g. the telemetry publisher, any thread):
//   if (auto fault = faults_.first()) log("{}:{}: {} (code {})", fault->file, fault->line,
//                                         fault->condition, fault->code);
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <type_traits>

namespace kerf {

/// One failed real-time check: where it is in the source and which fault it is.
struct Fault {
    const char* file = "";       ///< __FILE__ of the check (static storage)
    std::uint32_t line = 0;      ///< __LINE__ of the check
    std::uint16_t code = 0;      ///< the caller's fault enum, as its underlying value
    const char* condition = "";  ///< the checked condition as written (static storage)
};

/// A caller-owned, lock-free, allocation-free record of the first failed KERF_RT_CHECK and a
/// count of all of them. Any thread may record or read; nothing ever blocks or allocates.
class FaultLatch {
public:
    /// Keeps `fault` if none is latched (the first fault wins) and counts it. Wait-free, noexcept.
    void record(const Fault& fault) noexcept {
        failures_.fetch_add(1, std::memory_order_relaxed);
        std::uint32_t expected = kEmpty;
        if (!state_.compare_exchange_strong(expected, kWriting, std::memory_order_acquire,
                                            std::memory_order_relaxed)) {
            return;  // a fault is already latched (or being latched): keep the first
        }
        // A seqlock without fences (TSan cannot model them): the generation moves before the
        // fields, each field store releases it, so a reader that sees any new field sees the
        // new generation too and discards what it read.
        generation_.fetch_add(1, std::memory_order_relaxed);
        file_.store(fault.file, std::memory_order_release);
        line_.store(fault.line, std::memory_order_release);
        code_.store(fault.code, std::memory_order_release);
        condition_.store(fault.condition, std::memory_order_release);
        state_.store(kLatched, std::memory_order_release);
    }

    /// True once a fault is latched, until clear(). Wait-free, noexcept.
    bool tripped() const noexcept { return state_.load(std::memory_order_acquire) != kEmpty; }

    /// Failed checks since construction or the last clear(), including those not latched.
    std::uint32_t failures() const noexcept { return failures_.load(std::memory_order_relaxed); }

    /// The latched fault; empty when none is latched or when it changed while being read (a
    /// concurrent clear() and record(): call again). Lock-free, noexcept.
    std::optional<Fault> first() const noexcept {
        const std::uint64_t generation = generation_.load(std::memory_order_acquire);
        if (state_.load(std::memory_order_acquire) != kLatched) return std::nullopt;
        Fault f{file_.load(std::memory_order_acquire), line_.load(std::memory_order_acquire),
                code_.load(std::memory_order_acquire), condition_.load(std::memory_order_acquire)};
        if (generation_.load(std::memory_order_relaxed) != generation ||
            state_.load(std::memory_order_relaxed) != kLatched) {
            return std::nullopt;
        }
        return f;
    }

    /// Forgets the latched fault and the count (when the fault was reported and the loop may
    /// arm again). Wait-free, noexcept.
    void clear() noexcept {
        failures_.store(0, std::memory_order_relaxed);
        state_.store(kEmpty, std::memory_order_release);
    }

private:
    static constexpr std::uint32_t kEmpty = 0;
    static constexpr std::uint32_t kWriting = 1;
    static constexpr std::uint32_t kLatched = 2;

    std::atomic<std::uint32_t> state_{kEmpty};
    std::atomic<std::uint32_t> failures_{0};
    std::atomic<std::uint64_t> generation_{0};
    std::atomic<const char*> file_{""};
    std::atomic<std::uint32_t> line_{0};
    std::atomic<std::uint16_t> code_{0};
    std::atomic<const char*> condition_{""};
};
static_assert(std::atomic<std::uint64_t>::is_always_lock_free &&
                  std::atomic<const char*>::is_always_lock_free,
              "FaultLatch must be lock-free to be usable in the real-time loop");

namespace detail {

/// Prints "file:line: check `condition` failed: message" to stderr and aborts (KERF_ENFORCE,
/// KERF_ASSERT). Writes with one fputs-free fprintf call, allocates nothing.
[[noreturn]] inline void check_failed(const char* file, int line, const char* condition,
                                      std::string_view message) noexcept {
    std::fprintf(stderr, "%s:%d: check `%s` failed: %.*s\n", file, line, condition,
                 static_cast<int>(message.size()), message.data());
    std::fflush(stderr);
    std::abort();
}

/// Records a failed KERF_RT_CHECK and returns false; true when `ok`. noexcept, no allocation.
template <class Code>
inline bool rt_check(bool ok, FaultLatch& latch, Code code, const char* file, int line,
                     const char* condition) noexcept {
    static_assert(std::is_enum_v<Code> || std::is_integral_v<Code>,
                  "KERF_RT_CHECK's code is an enum (or integer) fault id");
    if (ok) [[likely]]
        return true;
    latch.record(
        Fault{file, static_cast<std::uint32_t>(line), static_cast<std::uint16_t>(code), condition});
    return false;
}

}  // namespace detail
}  // namespace kerf

/// Always-on check: aborts with file:line, the condition and `msg` when `cond` is false.
#define KERF_ENFORCE(cond, msg)                                                             \
    do {                                                                                    \
        if (!(cond)) [[unlikely]]                                                           \
            ::kerf::detail::check_failed(__FILE__, __LINE__, #cond, std::string_view{msg}); \
    } while (false)

#if defined(KERF_DEBUG_CHECKS) && KERF_DEBUG_CHECKS
/// Debug check (armed: KERF_DEBUG_CHECKS): aborts like KERF_ENFORCE when `cond` is false.
#define KERF_ASSERT(cond, msg) KERF_ENFORCE(cond, msg)
#else
/// Debug check (disarmed): `cond` and `msg` are type-checked but never evaluated.
#define KERF_ASSERT(cond, msg)       \
    do {                             \
        if (false) {                 \
            static_cast<void>(cond); \
            static_cast<void>(msg);  \
        }                            \
    } while (false)
#endif

/// Real-time check: evaluates to `cond`; when false records the fault in `latch` (a FaultLatch)
/// under `code` (the caller's fault enum). Never aborts, allocates, blocks or logs.
#define KERF_RT_CHECK(cond, latch, code) \
    (::kerf::detail::rt_check(static_cast<bool>(cond), (latch), (code), __FILE__, __LINE__, #cond))
