#include "tools/kerf/soak_checks.hpp"

#include <algorithm>

#include "firmware_host/safety/force_safety.hpp"
#include "rt_core/ipc/records.hpp"

namespace kerf::cli {
namespace {

bool bad(const TickSample& s) {
    return (s.safety_reasons & bad_input_reasons()) != 0 ||
           (s.loop_flags & ipc::kLoopFlagDeviceFault) != 0;
}

std::size_t first_at_or_after(const std::vector<TickSample>& ticks, std::uint64_t ns) {
    return std::size_t(
        std::lower_bound(ticks.begin(), ticks.end(), ns,
                         [](const TickSample& s, std::uint64_t t) { return s.time_ns < t; }) -
        ticks.begin());
}

std::uint64_t median(std::vector<std::uint64_t> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

void judge(FaultVerdict& v, const std::vector<TickSample>& ticks, double recovery_limit_s) {
    const FaultWindow& w = v.window;
    const std::size_t on = first_at_or_after(ticks, w.on_ns);
    const std::size_t off = first_at_or_after(ticks, w.off_ns);
    v.covered = on < off && on < ticks.size();
    if (!v.covered) return;
    for (std::size_t i = first_at_or_after(ticks, w.on_ns - 50'000'000); i < on; ++i)
        v.pushing = v.pushing || ticks[i].force_n > 0.05f;
    std::size_t first = on;
    while (first < off && !bad(ticks[first])) ++first;
    if (first == off) {
        v.problem = "kerf-rt never saw the fault";
        return;
    }
    v.seen = true;
    v.first_bad_tick = ticks[first].tick;
    for (std::size_t i = first; i < ticks.size() && bad(ticks[i]); ++i) {
        if (ticks[i].force_n == 0.0f && v.ticks_to_zero < 0)
            v.ticks_to_zero = std::int64_t(ticks[i].tick - v.first_bad_tick);
        if (ticks[i].tick >= v.first_bad_tick + 2 && ticks[i].force_n != 0.0f)
            ++v.nonzero_while_bad;
    }
    const auto limit_ns = w.off_ns + std::uint64_t(recovery_limit_s * 1e9);
    for (std::size_t i = off; i < ticks.size() && ticks[i].time_ns <= limit_ns; ++i) {
        if (!bad(ticks[i])) {
            v.recovered = true;
            v.recovery_s = double(ticks[i].time_ns - w.off_ns) * 1e-9;
            break;
        }
    }
    if (v.ticks_to_zero < 0 || v.ticks_to_zero > 2)
        v.problem = "force not zero within 2 ticks";
    else if (v.nonzero_while_bad)
        v.problem = std::to_string(v.nonzero_while_bad) + " ticks with force while input was bad";
    else if (!v.recovered)
        v.problem = "no recovery within " + std::to_string(int(recovery_limit_s)) + " s";
}

}  // namespace

std::uint32_t bad_input_reasons() noexcept {
    using namespace firmware_host;
    return kReasonStale | kReasonInvalidInput | kReasonNonFinite | kReasonEStop |
           kReasonDeviceFault | kReasonDisconnected;
}

bool force_reaches_hand(const TickSample& s) noexcept {
    using namespace firmware_host;
    const std::uint32_t zeroing = bad_input_reasons() | kReasonNotHomed | kReasonWaitingToEngage;
    const std::uint32_t loop_zero =
        ipc::kLoopFlagSafeState | ipc::kLoopFlagDeviceFault | ipc::kLoopFlagCheckFailed;
    return (s.safety_reasons & zeroing) == 0 && (s.loop_flags & loop_zero) == 0;
}

std::vector<FaultVerdict> check_device_faults(const std::vector<TickSample>& ticks,
                                              const std::vector<FaultWindow>& windows,
                                              double recovery_limit_s) {
    std::vector<FaultVerdict> out;
    for (const FaultWindow& w : windows) {
        FaultVerdict v;
        v.window = w;
        judge(v, ticks, recovery_limit_s);
        out.push_back(v);
    }
    return out;
}

ForceVerdict check_force_limit(const std::vector<TickSample>& ticks, double limit_n) {
    ForceVerdict v;
    v.limit_n = limit_n;
    for (const TickSample& s : ticks) {
        v.peak_n = std::max(v.peak_n, double(s.force_n));
        if (double(s.force_n) > limit_n * (1 + 1e-5)) ++v.over;
    }
    return v;
}

SequenceVerdict compare_sequences(const std::vector<SeenEvent>& journal,
                                  const std::vector<SeenEvent>& delivered) {
    SequenceVerdict v;
    v.journal = journal.size();
    v.delivered = delivered.size();
    const std::size_t n = std::min(journal.size(), delivered.size());
    for (std::size_t i = 0; i < n && v.first_difference < 0; ++i) {
        const SeenEvent &a = journal[i], &b = delivered[i];
        if (a.sequence != b.sequence || a.checksum != b.checksum || a.type != b.type)
            v.first_difference = std::int64_t(i);
    }
    if (v.first_difference < 0 && journal.size() != delivered.size())
        v.first_difference = std::int64_t(n);
    return v;
}

MemoryVerdict memory_growth(const std::vector<double>& t_s, const std::vector<std::uint64_t>& kb,
                            double warmup_s) {
    MemoryVerdict v;
    std::vector<std::uint64_t> warm, tail;
    for (std::size_t i = 0; i < kb.size(); ++i) {
        v.peak_kb = std::max(v.peak_kb, kb[i]);
        if (t_s[i] >= warmup_s && t_s[i] < warmup_s + 5) warm.push_back(kb[i]);
    }
    for (std::size_t i = kb.size() >= 5 ? kb.size() - 5 : 0; i < kb.size(); ++i)
        if (t_s[i] >= warmup_s + 5) tail.push_back(kb[i]);
    v.measured = !warm.empty() && !tail.empty();
    if (!v.measured) return v;
    v.warm_kb = median(warm);
    v.end_kb = median(tail);
    v.growth_pct = 100.0 * (double(v.end_kb) - double(v.warm_kb)) / double(v.warm_kb);
    return v;
}

}  // namespace kerf::cli
