// kerf::rt::LatencyHistogram — a fixed-size histogram of durations (wake-up latency, tick compute
// time), filled by the real-time thread and read by anyone afterwards. No allocation, O(1) record.
//
//   bins: 1 µs wide from 0 to 2 ms, then 100 µs wide up to 100 ms, then one overflow bin
//   (whose percentiles report the largest value seen). Percentiles are the upper edge of the bin
//   holding the requested rank (never optimistic by more than one bin width).
#pragma once

#include <array>
#include <cstdint>

namespace kerf::rt {

class LatencyHistogram {
public:
    static constexpr std::uint32_t kFineBins = 2000;   ///< 1 µs each: 0 .. 2 ms
    static constexpr std::uint32_t kCoarseBins = 980;  ///< 100 µs each: 2 ms .. 100 ms
    static constexpr std::uint64_t kFineWidth_ns = 1'000;
    static constexpr std::uint64_t kCoarseWidth_ns = 100'000;

    /// Adds one duration, ns. Real-time safe: noexcept, O(1), no allocation.
    void record(std::uint64_t ns) noexcept {
        std::uint32_t bin;
        if (ns < kFineBins * kFineWidth_ns) {
            bin = std::uint32_t(ns / kFineWidth_ns);
        } else if (ns < kFineBins * kFineWidth_ns + kCoarseBins * kCoarseWidth_ns) {
            bin = kFineBins + std::uint32_t((ns - kFineBins * kFineWidth_ns) / kCoarseWidth_ns);
        } else {
            bin = kFineBins + kCoarseBins;
        }
        ++bins_[bin];
        ++count_;
        if (ns > max_ns_) max_ns_ = ns;
    }

    /// The duration below which a fraction `q` (0..1) of the samples fall, ns; 0 when empty.
    std::uint64_t percentile(double q) const noexcept {
        if (count_ == 0) return 0;
        auto rank = std::uint64_t(q * double(count_));
        if (rank >= count_) rank = count_ - 1;
        std::uint64_t seen = 0;
        for (std::uint32_t b = 0; b < bins_.size(); ++b) {
            seen += bins_[b];
            if (seen > rank) return upper_edge(b) < max_ns_ ? upper_edge(b) : max_ns_;
        }
        return max_ns_;
    }

    std::uint64_t count() const noexcept { return count_; }
    std::uint64_t max_ns() const noexcept { return max_ns_; }
    /// Samples at or above `ns` (to the resolution of the bins).
    std::uint64_t count_at_least(std::uint64_t ns) const noexcept {
        std::uint64_t n = 0;
        for (std::uint32_t b = 0; b < bins_.size(); ++b) {
            if (upper_edge(b) > ns) n += bins_[b];
        }
        return n;
    }
    /// Forgets every sample. noexcept.
    void clear() noexcept { *this = LatencyHistogram{}; }

    static constexpr std::uint32_t kBins = kFineBins + kCoarseBins + 1;  ///< the last: overflow
    /// Samples in bin `b` (< kBins).
    std::uint64_t bin(std::uint32_t b) const noexcept { return bins_[b]; }
    /// Upper edge of bin `b`, ns (the overflow bin's is ~0).
    static std::uint64_t upper_edge(std::uint32_t b) noexcept {
        if (b < kFineBins) return (b + 1) * kFineWidth_ns;
        if (b < kFineBins + kCoarseBins)
            return kFineBins * kFineWidth_ns + (b - kFineBins + 1) * kCoarseWidth_ns;
        return ~std::uint64_t{0};
    }

private:
    std::array<std::uint64_t, kBins> bins_{};
    std::uint64_t count_ = 0;
    std::uint64_t max_ns_ = 0;
};

}  // namespace kerf::rt
