// Shared by the kerf_physics benchmarks: the real bone refined to benchmark sizes, a slow walk
// over its surface, per-call timing into a preallocated array, and percentiles. A custom main
// (KERF_PHYSICS_BENCH_MAIN) runs small meshes only under the ctest smoke run
// (--benchmark_min_time=0.001), so the smoke test stays cheap on a loaded CI machine.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "rt_core/physics/collision_world.hpp"
#include "tests/physics/physics_test_shapes.hpp"

namespace kerf::physics::bench {

inline bool& quick_mode() {
    static bool quick = false;
    return quick;
}

/// The calcaneus (58,334 triangles, CT-segmented, mm -> m) refined `levels` times (x4 each),
/// cached per level. Empty when the shared meshes are absent.
inline const test::TestMesh& bone(int levels) {
    static std::map<int, std::unique_ptr<test::TestMesh>> cache;
    auto& slot = cache[levels];
    if (!slot) {
        const auto file =
            std::filesystem::path(KERF_SHARED_MESHES) / "jma_norm01_calcaneus_right.stl";
        const test::TestMesh raw = test::read_binary_stl(file.string(), 0.001);
        slot = std::make_unique<test::TestMesh>(raw.triangles() ? test::refine(raw, levels) : raw);
    }
    return *slot;
}

/// An icosphere of radius 3 cm with 20 * 4^levels triangles (levels 8: 1.31M), cached.
inline const test::TestMesh& sphere(int levels) {
    static std::map<int, std::unique_ptr<test::TestMesh>> cache;
    auto& slot = cache[levels];
    if (!slot) slot = std::make_unique<test::TestMesh>(test::make_sphere({}, 0.03, levels));
    return *slot;
}

using test::surface_walk;

/// Per-call timings of one pass, ns.
struct Timings {
    std::vector<double> ns;
    double percentile(double p) {
        std::sort(ns.begin(), ns.end());
        return ns.empty() ? 0 : ns[std::min(ns.size() - 1, std::size_t(p * double(ns.size())))];
    }
};

inline double now_ns() {
    return double(std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::steady_clock::now().time_since_epoch())
                      .count());
}

/// Minimum and maximum over repetitions (Google Benchmark adds mean, median, stddev).
template <class B>
B* with_min_max(B* b) {
    return b
        ->ComputeStatistics(
            "min",
            [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); })
        ->ComputeStatistics("max", [](const std::vector<double>& v) {
            return *std::max_element(v.begin(), v.end());
        });
}

}  // namespace kerf::physics::bench

/// main(): quick mode under the ctest smoke run, then Google Benchmark as usual.
#define KERF_PHYSICS_BENCH_MAIN(register_all)                              \
    int main(int argc, char** argv) {                                      \
        for (int i = 1; i < argc; ++i) {                                   \
            if (std::strcmp(argv[i], "--benchmark_min_time=0.001") == 0) { \
                kerf::physics::bench::quick_mode() = true;                 \
            }                                                              \
        }                                                                  \
        register_all();                                                    \
        benchmark::Initialize(&argc, argv);                                \
        if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;  \
        benchmark::RunSpecifiedBenchmarks();                               \
        benchmark::Shutdown();                                             \
        return 0;                                                          \
    }
