// Cutting benchmarks. Figures are reported as ratios measured in the same run (the table printed
// after Google Benchmark's own): localised slice + caps flat in mesh size, full-plane slice + caps
// against VTK's vtkClipClosedSurface (two calls, one per half) and CGAL's PMP::clip with
// clip_volume (two calls), a flat pass over every vertex position as the physical floor, one
// gradual-separation step, caps alone, and a real bone refined to ~1M triangles by Loop
// subdivision. VTK and CGAL are optional (tools/setup.sh --bench-peers).
//
//   build/bin/bench_cut                       # everything, 5 repetitions, then the ratio table
//   build/bin/bench_cut --benchmark_filter=Localised
//   build/bin/bench_cut --benchmark_report_aggregates_only   # console: aggregates and ratios
// The ratios need every repetition: --benchmark_report_aggregates_only and
// --benchmark_display_aggregates_only are taken by this program, which shows only the aggregates
// on the console and still reports every repetition to the ratio table (and to --benchmark_out).
// Each ratio is median(a) / median(b) over the repetitions, with the widest range the
// repetitions allow (min a / max b .. max a / min b).
#include <benchmark/benchmark.h>

#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/main_guard.hpp"
#include "display/cut/cut_context.hpp"
#include "display/cut/separate.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "display/cut/triangulate.hpp"
#include "display/mesh/foot_generator.hpp"
#include "display/mesh/mesh_io.hpp"
#include "display/mesh/shapes.hpp"

#ifdef KERF_BENCH_HAVE_VTK
#include <vtkCellArray.h>
#include <vtkClipClosedSurface.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPlaneCollection.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#endif
#ifdef KERF_BENCH_HAVE_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Surface_mesh.h>
#endif

namespace {

using kerf::cut::CrossSection;
using kerf::cut::CutContext;
using kerf::cut::Plane;
using kerf::cut::Seed;
using kerf::cut::Vec2;
using kerf::cut::Vec3;
using kerf::mesh::TriMesh;

constexpr double kTubeLength = 0.05, kTubeOuter = 0.006, kTubeInner = 0.003;
constexpr int kTubeSegments = 512;  // 1,024 rim points per side at every size

/// Hollow tube with `triangles` triangles; every cross-section is the same 512-gon annulus.
TriMesh tube_with(std::size_t triangles) {
    const int rings = static_cast<int>((triangles - 4 * kTubeSegments) / (4 * kTubeSegments));
    return kerf::mesh::make_hollow_tube(kTubeLength, kTubeOuter, kTubeInner, kTubeSegments, rings);
}

/// Plane i of n: across the tube in the middle of its own ring band (never an earlier cut).
Plane tube_plane(int i, int n) {
    const double z = kTubeLength * (0.1 + 0.8 * (i + 0.5) / n) + 1.234e-6;
    return *Plane::make(Vec3(0, 0, z), Vec3(0, 0, 1));
}

/// Idle time between two cuts, untimed: the context's capacity growth steps, as the display's
/// CutSession::idle() takes them, so no timed cut grows capacity (counted as growths_in_cuts).
void idle_between_cuts(CutContext& ctx, benchmark::State& state) {
    state.PauseTiming();
    while (ctx.grow_step()) {
    }
    state.ResumeTiming();
}

// ---- localised slice + caps, flat in mesh size --------------------------------------------------

void BM_LocalisedSliceCaps(benchmark::State& state) {
    TriMesh m = tube_with(static_cast<std::size_t>(state.range(0)));
    CutContext ctx(m);
    CrossSection cs;
    int i = 0;
    int refused = 0;
    double faces_split = 0;
    const int n = static_cast<int>(state.max_iterations);
    for (auto _ : state) {
        idle_between_cuts(ctx, state);
        const Plane p = tube_plane(i++, n);
        const Seed seed{Vec3(kTubeOuter, 0, p.point()[2]), kerf::mesh::FaceHandle(), -1.0};
        const auto r = kerf::cut::slice_by_plane(ctx, p, seed, cs);
        refused += r.ok() ? 0 : 1;
        faces_split += r.stats.faces_split;
        benchmark::DoNotOptimize(cs.positive.cap_faces.data());
    }
    state.counters["growths_in_cuts"] = static_cast<double>(ctx.growths_in_cuts());
    state.counters["refused"] = refused;  // cuts the library refused (timed all the same)
    state.counters["faces_split"] = faces_split / static_cast<double>(state.iterations());
    state.counters["triangles"] = static_cast<double>(state.range(0));
    state.counters["rim_points"] = 2.0 * kTubeSegments;
}
BENCHMARK(BM_LocalisedSliceCaps)
    ->Arg(100'000)
    ->Arg(1'000'000)
    ->Arg(4'000'000)
    ->Iterations(40)
    ->Unit(benchmark::kMicrosecond);

// The same localised cut of a tube with few segments: 32 around, so 128 split faces at every
// size, while the rings crowd along the axis (ring spacing 64 um at 100k, 1.6 um at 4M, against
// 1.2 mm around): long thin triangles, the case where a grid sized on face extents holds many
// faces per cell. Cost must not follow the density.
constexpr int kThinTubeSegments = 32;

TriMesh thin_tube_with(std::size_t triangles) {
    const int rings =
        static_cast<int>((triangles - 4 * kThinTubeSegments) / (4 * kThinTubeSegments));
    return kerf::mesh::make_hollow_tube(kTubeLength, kTubeOuter, kTubeInner, kThinTubeSegments,
                                        rings);
}

void BM_LocalisedSliceCaps_ThinTube(benchmark::State& state) {
    TriMesh m = thin_tube_with(static_cast<std::size_t>(state.range(0)));
    CutContext ctx(m);
    CrossSection cs;
    int i = 0;
    int refused = 0;
    double faces_split = 0;
    const int n = static_cast<int>(state.max_iterations);
    for (auto _ : state) {
        idle_between_cuts(ctx, state);
        const Plane p = tube_plane(i++, n);
        const Seed seed{Vec3(kTubeOuter, 0, p.point()[2]), kerf::mesh::FaceHandle(), -1.0};
        const auto r = kerf::cut::slice_by_plane(ctx, p, seed, cs);
        refused += r.ok() ? 0 : 1;
        faces_split += r.stats.faces_split;
    }
    state.counters["growths_in_cuts"] = static_cast<double>(ctx.growths_in_cuts());
    state.counters["refused"] = refused;
    state.counters["faces_split"] = faces_split / static_cast<double>(state.iterations());
    state.counters["triangles"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_LocalisedSliceCaps_ThinTube)
    ->Arg(100'000)
    ->Arg(1'000'000)
    ->Arg(4'000'000)
    ->Iterations(40)
    ->Unit(benchmark::kMicrosecond);

// ---- biplanar slab, localised ------------------------------------------------------------------

// A 0.5 mm slab across the regular tube in the middle of each cut's own ring band (1 mm apart
// for 40 cuts): both walls found, planned and capped, the slab removed. Its cost is the walls'
// (2 x 2,048 split faces) plus the walk over the slab's surface between them.
void BM_SlabCut(benchmark::State& state) {
    TriMesh m = tube_with(static_cast<std::size_t>(state.range(0)));
    CutContext ctx(m);
    kerf::cut::SlabCut slab;
    int i = 0;
    int refused = 0;
    double faces_split = 0;
    const int n = static_cast<int>(state.max_iterations);
    for (auto _ : state) {
        idle_between_cuts(ctx, state);
        const Plane p = tube_plane(i++, n);
        const Seed seed{Vec3(kTubeOuter, 0, p.point()[2]), kerf::mesh::FaceHandle(), -1.0};
        const auto r = kerf::cut::subtract_slab(ctx, p, 0.5e-3, seed, slab);
        refused += r.ok() ? 0 : 1;
        faces_split += r.stats.faces_split;
        benchmark::DoNotOptimize(slab.lower.negative.cap_faces.data());
    }
    state.counters["growths_in_cuts"] = static_cast<double>(ctx.growths_in_cuts());
    state.counters["refused"] = refused;
    state.counters["faces_split"] = faces_split / static_cast<double>(state.iterations());
    state.counters["triangles"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_SlabCut)->Arg(100'000)->Arg(1'000'000)->Iterations(40)->Unit(benchmark::kMicrosecond);

// ---- full-plane slice + caps of a 1M sphere, its peers and the floor ----------------------------

const TriMesh& sphere_1m() {
    static const TriMesh s = kerf::mesh::make_uv_sphere(0.01, 1'000'000);
    return s;
}

Plane sphere_plane(int i) {
    const double z = 0.01 * (-0.2 + 0.037 * i) + 1.234e-7;
    return *Plane::make(Vec3(0, 0, z), Vec3(0.05, 0.02, 1));
}

void BM_FullSliceCaps_Sphere1M(benchmark::State& state) {
    TriMesh m = sphere_1m();
    CutContext ctx(m);
    CrossSection cs;
    int i = 0;
    int refused = 0;
    for (auto _ : state) {
        idle_between_cuts(ctx, state);
        const auto r = kerf::cut::slice_by_plane(ctx, sphere_plane(i++), cs);
        refused += r.ok() ? 0 : 1;
    }
    state.counters["growths_in_cuts"] = static_cast<double>(ctx.growths_in_cuts());
    state.counters["refused"] = refused;  // cuts the library refused (timed all the same)
}
BENCHMARK(BM_FullSliceCaps_Sphere1M)->Iterations(10)->Unit(benchmark::kMillisecond);

// The physical floor: one pass over the same 1M sphere's vertex positions stored flat (x, y, z
// doubles, copied out of the mesh before timing), counting those above the plane. Not OpenMesh
// handles: iterating handles is 6-8x slower than this and would flatter every "/ floor" ratio.
void BM_FlatPass_Sphere1M(benchmark::State& state) {
    const TriMesh& m = sphere_1m();
    std::vector<double> xyz;
    xyz.reserve(3 * m.n_vertices());
    for (const auto v : m.vertices()) {
        const auto& q = m.point(v);
        xyz.insert(xyz.end(), {q[0], q[1], q[2]});
    }
    const Plane p = sphere_plane(0);
    const double nx = p.normal()[0], ny = p.normal()[1], nz = p.normal()[2];
    const double d = OpenMesh::dot(p.normal(), p.point());
    for (auto _ : state) {
        std::size_t above = 0;
        for (std::size_t i = 0; i < xyz.size(); i += 3) {
            above += nx * xyz[i] + ny * xyz[i + 1] + nz * xyz[i + 2] - d > 0 ? 1 : 0;
        }
        benchmark::DoNotOptimize(above);
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * xyz.size() * 8));
}
BENCHMARK(BM_FlatPass_Sphere1M)->Unit(benchmark::kMillisecond);

#ifdef KERF_BENCH_HAVE_VTK
void BM_VtkClipClosedSurfaceTwoHalves_Sphere1M(benchmark::State& state) {
    const TriMesh& m = sphere_1m();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    for (const auto v : m.vertices()) {
        const auto& p = m.point(v);
        points->InsertNextPoint(p[0], p[1], p[2]);
    }
    vtkNew<vtkCellArray> polys;
    for (const auto f : m.faces()) {
        vtkIdType ids[3];
        int k = 0;
        for (const auto v : m.fv_range(f)) ids[k++] = v.idx();
        polys->InsertNextCell(3, ids);
    }
    vtkNew<vtkPolyData> input;
    input->SetPoints(points);
    input->SetPolys(polys);
    const Plane p = sphere_plane(0);
    for (auto _ : state) {
        for (const double side : {1.0, -1.0}) {
            vtkNew<vtkPlane> plane;
            plane->SetOrigin(p.point()[0], p.point()[1], p.point()[2]);
            plane->SetNormal(side * p.normal()[0], side * p.normal()[1], side * p.normal()[2]);
            vtkNew<vtkPlaneCollection> planes;
            planes->AddItem(plane);
            vtkNew<vtkClipClosedSurface> clip;
            clip->SetInputData(input);
            clip->SetClippingPlanes(planes);
            clip->Update();
            benchmark::DoNotOptimize(clip->GetOutput()->GetNumberOfCells());
        }
    }
}
BENCHMARK(BM_VtkClipClosedSurfaceTwoHalves_Sphere1M)->Iterations(2)->Unit(benchmark::kMillisecond);
#endif

#ifdef KERF_BENCH_HAVE_CGAL
void BM_CgalClipVolumeTwoHalves_Sphere1M(benchmark::State& state) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    using SM = CGAL::Surface_mesh<K::Point_3>;
    const TriMesh& m = sphere_1m();
    SM input;
    std::vector<SM::Vertex_index> vi;
    for (const auto v : m.vertices()) {
        const auto& p = m.point(v);
        vi.push_back(input.add_vertex(K::Point_3(p[0], p[1], p[2])));
    }
    for (const auto f : m.faces()) {
        std::vector<SM::Vertex_index> c;
        for (const auto v : m.fv_range(f)) c.push_back(vi[static_cast<std::size_t>(v.idx())]);
        input.add_face(c[0], c[1], c[2]);
    }
    const Plane p = sphere_plane(0);
    for (auto _ : state) {
        for (const double side : {1.0, -1.0}) {
            state.PauseTiming();
            SM half = input;
            state.ResumeTiming();
            // CGAL keeps the part on the negative side of the plane.
            const K::Plane_3 plane(
                K::Point_3(p.point()[0], p.point()[1], p.point()[2]),
                K::Vector_3(side * p.normal()[0], side * p.normal()[1], side * p.normal()[2]));
            CGAL::Polygon_mesh_processing::clip(half, plane, CGAL::parameters::clip_volume(true));
            benchmark::DoNotOptimize(half.number_of_faces());
        }
    }
}
BENCHMARK(BM_CgalClipVolumeTwoHalves_Sphere1M)->Iterations(1)->Unit(benchmark::kMillisecond);
#endif

// ---- one gradual-separation step ----------------------------------------------------------------

void BM_SeparationStep_Tube1M(benchmark::State& state) {
    TriMesh m = tube_with(1'000'000);
    CutContext ctx(m);
    CrossSection cs;
    const Plane p = tube_plane(3, 7);
    const Seed seed{Vec3(kTubeOuter, 0, p.point()[2]), kerf::mesh::FaceHandle(), -1.0};
    if (!kerf::cut::slice_by_plane(ctx, p, seed, cs).ok())
        return state.SkipWithError("slice failed");
    auto sep = kerf::cut::Separator::make(ctx, cs, 1.0e-3);
    if (!sep) return state.SkipWithError("separator refused");
    double front = -kTubeOuter - 0.001;
    for (auto _ : state) {
        front += 0.0002;  // the blade advances 0.2 mm per progress event
        const std::vector<Vec2> blade{Vec2(front - 0.01, -0.0065), Vec2(front, -0.0065),
                                      Vec2(front, 0.0065), Vec2(front - 0.01, 0.0065)};
        sep->sweep(blade);
    }
    state.counters["band_vertices"] = sep->stats().band_vertices;
}
BENCHMARK(BM_SeparationStep_Tube1M)->Iterations(60)->Unit(benchmark::kMicrosecond);

// ---- caps alone ---------------------------------------------------------------------------------

void BM_TriangulateBoneAnnulus(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    std::vector<Vec2> outer, inner;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * M_PI * k / n;
        const double r = 0.01 * (1 + 0.15 * std::sin(3 * a) + 0.05 * std::sin(7 * a));
        outer.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    for (int k = 0; k < n / 2; ++k) {
        const double a = -2 * M_PI * k / (n / 2);
        const double r = 0.004 * (1 + 0.1 * std::sin(2 * a + 1));
        inner.emplace_back(0.001 + r * std::cos(a), r * std::sin(a));
    }
    const std::vector<std::span<const Vec2>> loops{outer, inner};
    kerf::cut::Triangulator t;
    std::vector<kerf::cut::Triangle> tris;
    for (auto _ : state) {
        if (!t.triangulate(loops, tris)) {
            state.SkipWithError("refused");
            break;
        }
        benchmark::DoNotOptimize(tris.data());
    }
    state.counters["points"] = 1.5 * n;
}
BENCHMARK(BM_TriangulateBoneAnnulus)->Arg(1000)->Arg(3000)->Unit(benchmark::kMicrosecond);

// ---- a real bone refined to ~1M triangles -------------------------------------------------------

const TriMesh* refined_bone() {
    static std::unique_ptr<TriMesh> bone = [] {
        const char* dir = std::getenv("KERF_SHARED_MESHES_DIR");  // e.g. on another machine
        const auto path = std::filesystem::path(dir != nullptr ? dir : KERF_SHARED_MESHES) /
                          "jma_norm01_calcaneus_right.stl";
        auto loaded = kerf::mesh::load_mesh(path, kerf::LengthUnit::kMillimetre);
        if (!loaded) return std::unique_ptr<TriMesh>();
        auto m = std::make_unique<TriMesh>(std::move(*loaded));
        OpenMesh::Subdivider::Uniform::LoopT<TriMesh, double> loop;
        loop.attach(*m);
        loop(2);  // 58,334 -> 933,344 triangles
        loop.detach();
        m->update_face_normals();
        return m;
    }();
    return bone.get();
}

void BM_LocalisedSliceCaps_RealBone1M(benchmark::State& state) {
    const TriMesh* source = refined_bone();
    if (source == nullptr) return state.SkipWithError("shared meshes absent");
    TriMesh m = *source;
    CutContext ctx(m);
    CrossSection cs;
    // Planes across the bone's long (x) extent; the seed is where an edge crosses the plane.
    OpenMesh::Vec3d lo(1e9, 1e9, 1e9), hi(-1e9, -1e9, -1e9);
    for (const auto v : m.vertices()) lo.minimize(m.point(v)), hi.maximize(m.point(v));
    int i = 0;
    int refused = 0;
    for (auto _ : state) {
        idle_between_cuts(ctx, state);
        state.PauseTiming();
        const double x = lo[0] + (hi[0] - lo[0]) * (0.3 + 0.04 * i++) + 1.234e-7;
        const Plane p = *Plane::make(Vec3(x, 0, 0), Vec3(1, 0, 0));
        Vec3 seed_point(0, 0, 0);
        for (const auto e : m.edges()) {
            const auto a = m.point(m.from_vertex_handle(m.halfedge_handle(e, 0)));
            const auto b = m.point(m.to_vertex_handle(m.halfedge_handle(e, 0)));
            const double da = p.signed_distance(a), db = p.signed_distance(b);
            if ((da < 0) != (db < 0)) {
                seed_point = a + (b - a) * (da / (da - db));
                break;
            }
        }
        state.ResumeTiming();
        const auto r =
            kerf::cut::slice_by_plane(ctx, p, Seed{seed_point, kerf::mesh::FaceHandle(), -1.0}, cs);
        refused += r.ok() ? 0 : 1;
    }
    state.counters["growths_in_cuts"] = static_cast<double>(ctx.growths_in_cuts());
    state.counters["refused"] = refused;
    state.counters["triangles"] = static_cast<double>(source->n_faces());
}
BENCHMARK(BM_LocalisedSliceCaps_RealBone1M)->Iterations(10)->Unit(benchmark::kMicrosecond);

// ---- the built-in foot at 1M triangles: a bone-sized cross-section -----------------------------

/// Localised slice + caps across the first metatarsal's shaft (cortex + canal: an annulus), at
/// successive stations along its axis; the other 18 bones cross nothing or stay untouched.
void BM_LocalisedSliceCaps_Foot1M(benchmark::State& state) {
    kerf::mesh::FootParams params;
    params.target_triangles = 1'000'000;
    auto foot = kerf::mesh::generate_foot(params);
    if (!foot) return state.SkipWithError(foot.error().c_str());
    TriMesh& m = foot->mesh;
    const kerf::mesh::BoneInfo bone = foot->first_metatarsal();
    const Vec3 axis = (bone.head_m - bone.base_m).normalized();
    CutContext ctx(m);
    CrossSection cs;
    int i = 0;
    int refused = 0;
    double faces_split = 0;
    for (auto _ : state) {
        idle_between_cuts(ctx, state);
        state.PauseTiming();
        // Station along the shaft, between the canal's ends; seed: the crossing of the bone's
        // outer shell farthest from the axis (never the canal wall).
        const double s = bone.canal_start_m + (bone.canal_end_m - bone.canal_start_m) *
                                                  (0.15 + 0.7 * (i++ + 0.5) / 40.0);
        const Vec3 at = bone.base_m + axis * s;
        const Plane p = *Plane::make(at + axis * 1.234e-7, axis);
        Vec3 seed_point = at;
        double farthest = -1.0;
        for (std::size_t f = bone.first_triangle; f < bone.first_triangle + bone.triangle_count;
             ++f) {
            for (const auto h : m.fh_range(kerf::mesh::FaceHandle(static_cast<int>(f)))) {
                const auto a = m.point(m.from_vertex_handle(h));
                const auto b = m.point(m.to_vertex_handle(h));
                const double da = p.signed_distance(a), db = p.signed_distance(b);
                if ((da < 0) == (db < 0)) continue;
                const Vec3 x = a + (b - a) * (da / (da - db));
                const double r = (x - at - axis * OpenMesh::dot(x - at, axis)).norm();
                if (r > farthest) farthest = r, seed_point = x;
            }
        }
        state.ResumeTiming();
        const auto r =
            kerf::cut::slice_by_plane(ctx, p, Seed{seed_point, kerf::mesh::FaceHandle(), -1.0}, cs);
        refused += r.ok() ? 0 : 1;
        faces_split += r.stats.faces_split;
    }
    state.counters["growths_in_cuts"] = static_cast<double>(ctx.growths_in_cuts());
    state.counters["refused"] = refused;
    state.counters["faces_split"] = faces_split / static_cast<double>(state.iterations());
    state.counters["triangles"] = static_cast<double>(m.n_faces());
}
BENCHMARK(BM_LocalisedSliceCaps_Foot1M)->Iterations(40)->Unit(benchmark::kMicrosecond);

// ---- ratio table
// ---------------------------------------------------------------------------------

/// Console output as usual (only the aggregates when `aggregates_only`), plus each benchmark's
/// times per repetition kept for the ratios.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    explicit RatioReporter(bool aggregates_only) : aggregates_only_(aggregates_only) {}

    void ReportRuns(const std::vector<Run>& runs) override {
        const bool has_aggregates = std::any_of(
            runs.begin(), runs.end(), [](const Run& r) { return r.run_type == Run::RT_Aggregate; });
        if (aggregates_only_ && has_aggregates) {
            std::vector<Run> shown;
            std::copy_if(runs.begin(), runs.end(), std::back_inserter(shown),
                         [](const Run& r) { return r.run_type == Run::RT_Aggregate; });
            ConsoleReporter::ReportRuns(shown);
        } else {
            ConsoleReporter::ReportRuns(runs);
        }
        for (const Run& r : runs) {
            if (r.error_occurred || r.run_type != Run::RT_Iteration) continue;
            const double unit = benchmark::GetTimeUnitMultiplier(r.time_unit);
            real_[r.run_name.str()].push_back(r.GetAdjustedRealTime() / unit);
            cpu_[r.run_name.str()].push_back(r.GetAdjustedCPUTime() / unit);
        }
    }
    /// The ratio table on wall time, then on the cutting thread's CPU time (which a loaded
    /// machine inflates less: time spent descheduled is not in it).
    void print_ratios() {
        seconds_ = &real_;
        std::printf("\nRatios (same run, wall time):\n");
        print_table();
        seconds_ = &cpu_;
        std::printf("\nRatios (same run, CPU time of the benchmark thread):\n");
        print_table();
    }

private:
    void print_table() const {
        ratio("localised 1M / 100k (flat = 1)", "BM_LocalisedSliceCaps/1000000/iterations:40",
              "BM_LocalisedSliceCaps/100000/iterations:40");
        ratio("localised 4M / 100k (flat = 1)", "BM_LocalisedSliceCaps/4000000/iterations:40",
              "BM_LocalisedSliceCaps/100000/iterations:40");
        ratio("VTK two halves / ours, 1M sphere",
              "BM_VtkClipClosedSurfaceTwoHalves_Sphere1M/iterations:2",
              "BM_FullSliceCaps_Sphere1M/iterations:10");
        ratio("CGAL clip_volume two halves / ours, 1M sphere",
              "BM_CgalClipVolumeTwoHalves_Sphere1M/iterations:1",
              "BM_FullSliceCaps_Sphere1M/iterations:10");
        ratio("ours full plane / flat-pass floor, 1M sphere",
              "BM_FullSliceCaps_Sphere1M/iterations:10", "BM_FlatPass_Sphere1M");
        ratio("localised 1M tube / flat-pass floor 1M sphere",
              "BM_LocalisedSliceCaps/1000000/iterations:40", "BM_FlatPass_Sphere1M");
        ratio("separation step / flat-pass floor", "BM_SeparationStep_Tube1M/iterations:60",
              "BM_FlatPass_Sphere1M");
        ratio("real bone 1M localised / flat-pass floor",
              "BM_LocalisedSliceCaps_RealBone1M/iterations:10", "BM_FlatPass_Sphere1M");
        ratio("foot 1M metatarsal localised / flat-pass floor",
              "BM_LocalisedSliceCaps_Foot1M/iterations:40", "BM_FlatPass_Sphere1M");
        ratio("thin tube localised 1M / 100k (flat = 1)",
              "BM_LocalisedSliceCaps_ThinTube/1000000/iterations:40",
              "BM_LocalisedSliceCaps_ThinTube/100000/iterations:40");
        ratio("thin tube localised 4M / 100k (flat = 1)",
              "BM_LocalisedSliceCaps_ThinTube/4000000/iterations:40",
              "BM_LocalisedSliceCaps_ThinTube/100000/iterations:40");
        absolute("localised slice + caps, 1M tube", "BM_LocalisedSliceCaps/1000000/iterations:40");
        per_split_face("per split face, 1M tube (2,048 split faces)",
                       "BM_LocalisedSliceCaps/1000000/iterations:40", 2048);
        absolute("localised slice + caps, foot 1M metatarsal",
                 "BM_LocalisedSliceCaps_Foot1M/iterations:40");
        absolute("separation step, 1M tube", "BM_SeparationStep_Tube1M/iterations:60");
    }

    struct Spread {
        double median, min, max;
        std::size_t n;
    };
    std::optional<Spread> spread(const std::string& name) const {
        const auto it = seconds_->find(name);
        if (it == seconds_->end() || it->second.empty()) return std::nullopt;
        std::vector<double> v = it->second;
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
        return Spread{median, v.front(), v.back(), n};
    }
    void ratio(const char* what, const std::string& a, const std::string& b) const {
        const auto sa = spread(a), sb = spread(b);
        if (!sa || !sb) {
            std::printf("  %-48s (not measured in this run)\n", what);
            return;
        }
        std::printf("  %-48s %10.2f  (%.2f-%.2f, n=%zu/%zu)\n", what, sa->median / sb->median,
                    sa->min / sb->max, sa->max / sb->min, sa->n, sb->n);
    }
    void absolute(const char* what, const std::string& a) const {
        if (const auto sa = spread(a)) {
            std::printf("  %-48s %10.3f ms  (%.3f-%.3f, n=%zu)\n", what, sa->median * 1e3,
                        sa->min * 1e3, sa->max * 1e3, sa->n);
        }
    }
    void per_split_face(const char* what, const std::string& a, double faces) const {
        if (const auto sa = spread(a)) {
            std::printf("  %-48s %10.3f us  (%.3f-%.3f, n=%zu)\n", what, sa->median * 1e6 / faces,
                        sa->min * 1e6 / faces, sa->max * 1e6 / faces, sa->n);
        }
    }
    bool aggregates_only_;
    std::map<std::string, std::vector<double>> real_, cpu_;
    const std::map<std::string, std::vector<double>>* seconds_ = &real_;
};

/// Whether a Google Benchmark boolean flag's value (after '=', or empty for the bare flag) is true.
bool flag_true(std::string_view value) {
    if (value.empty()) return true;
    std::string v(value);
    std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
    return !(v == "0" || v == "f" || v == "n" || v == "false" || v == "no" || v == "off");
}

/// Removes `--name` / `--name=value` from args; true when the last one given says true.
bool take_bool_flag(std::vector<char*>& args, std::string_view name, bool fallback) {
    bool value = fallback;
    std::erase_if(args, [&](const char* a) {
        const std::string_view arg(a);
        if (arg.rfind(name, 0) != 0) return false;
        const std::string_view rest = arg.substr(name.size());
        if (!rest.empty() && rest.front() != '=') return false;
        value = flag_true(rest.empty() ? rest : rest.substr(1));
        return true;
    });
    return value;
}

}  // namespace

static int program_main(int argc, char** argv) {
    // Five repetitions unless the command line says otherwise (the ctest smoke run says 1).
    std::vector<char*> args(argv, argv + argc);
    std::string reps = "--benchmark_repetitions=5";
    if (std::none_of(args.begin(), args.end(), [](const char* a) {
            return std::string_view(a).rfind("--benchmark_repetitions", 0) == 0;
        })) {
        args.push_back(reps.data());
    }
    // Google Benchmark would hand the reporter only the aggregates: the ratio table, which needs
    // every repetition, would read "not measured". The reporter filters the console instead.
    bool aggregates_only = take_bool_flag(args, "--benchmark_report_aggregates_only", false);
    aggregates_only = take_bool_flag(args, "--benchmark_display_aggregates_only", aggregates_only);
    argc = static_cast<int>(args.size());
    argv = args.data();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    RatioReporter reporter(aggregates_only);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.print_ratios();
    benchmark::Shutdown();
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_cut", [&] { return program_main(argc, argv); });
}
