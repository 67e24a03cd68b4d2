// Mesh loading speed: Kerf's loader against OpenMesh's own IO::read_mesh on the same file
// (the reference, measured in the same run), plus validation and foot generation.
//   build/bin/bench_mesh --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "config/base/main_guard.hpp"
#include "display/mesh/foot_generator.hpp"
#include "display/mesh/mesh_io.hpp"
#include "display/mesh/validate.hpp"

namespace {

using namespace kerf::mesh;

const std::filesystem::path kCalcaneus =
    std::filesystem::path(KERF_SHARED_MESHES) / "jma_norm01_calcaneus_right.stl";

bool have_file(benchmark::State& state) {
    if (std::filesystem::exists(kCalcaneus)) return true;
    state.SkipWithError("shared meshes not present");
    return false;
}

// Reference: OpenMesh's STL reader (binary STL, welds by float coordinates) into the same type.
void BM_OpenMeshReadMeshCalcaneus(benchmark::State& state) {
    if (!have_file(state)) return;
    for (auto _ : state) {
        TriMesh mesh = make_mesh();
        const bool ok = OpenMesh::IO::read_mesh(mesh, kCalcaneus.string());
        if (!ok) state.SkipWithError("OpenMesh could not read the file");
        benchmark::DoNotOptimize(mesh.n_faces());
    }
    state.counters["triangles_per_s"] = benchmark::Counter(
        58334.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_OpenMeshReadMeshCalcaneus)->Unit(benchmark::kMillisecond);

// Kerf: read + parse + weld + build the half-edge mesh + normals.
void BM_KerfLoadMeshCalcaneus(benchmark::State& state) {
    if (!have_file(state)) return;
    for (auto _ : state) {
        auto loaded = load_mesh_file(kCalcaneus, kerf::LengthUnit::kMillimetre);
        if (!loaded) state.SkipWithError("kerf could not read the file");
        benchmark::DoNotOptimize(loaded->mesh.n_faces());
    }
    state.counters["triangles_per_s"] = benchmark::Counter(
        58334.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_KerfLoadMeshCalcaneus)->Unit(benchmark::kMillisecond);

// Kerf: parse + weld only, from bytes in memory.
void BM_KerfParseIndexedCalcaneus(benchmark::State& state) {
    if (!have_file(state)) return;
    std::ifstream in(kCalcaneus, std::ios::binary);
    const std::vector<char> data((std::istreambuf_iterator<char>(in)),
                                 std::istreambuf_iterator<char>());
    const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data.data()),
                                           data.size());
    for (auto _ : state) {
        auto m = parse_indexed(bytes, Format::kStl, kerf::LengthUnit::kMillimetre);
        benchmark::DoNotOptimize(m->triangles.data());
    }
}
BENCHMARK(BM_KerfParseIndexedCalcaneus)->Unit(benchmark::kMillisecond);

void BM_ValidateCalcaneus(benchmark::State& state) {
    if (!have_file(state)) return;
    const auto loaded = load_mesh_file(kCalcaneus, kerf::LengthUnit::kMillimetre);
    for (auto _ : state) {
        const ValidationReport r = validate(loaded->indexed);
        benchmark::DoNotOptimize(r.volume_m3);
    }
}
BENCHMARK(BM_ValidateCalcaneus)->Unit(benchmark::kMillisecond);

void BM_GenerateFoot(benchmark::State& state) {
    for (auto _ : state) {
        auto foot = generate_foot({static_cast<std::size_t>(state.range(0)), 1});
        benchmark::DoNotOptimize(foot->mesh.n_faces());
    }
}
BENCHMARK(BM_GenerateFoot)->Arg(200'000)->Unit(benchmark::kMillisecond);

}  // namespace

// Google Benchmark's main, with nothing escaping: an exception is a message and exit 1.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_mesh", [&] {
        benchmark::Initialize(&argc, argv);
        if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
        benchmark::RunSpecifiedBenchmarks();
        benchmark::Shutdown();
        return 0;
    });
}
