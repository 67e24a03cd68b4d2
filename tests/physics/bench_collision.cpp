// The collision structure against its peer, Intel Embree 3 (Debian's libembree-dev), in one run:
//  - closest point on a slow walk 0-2 mm outside the surface (kerf tree vs rtcPointQuery with the
//    same double-precision triangle routine in its callback; one thread each), p50/p99/max per
//    query; the two must agree on every distance (counter `mismatches`);
//  - build from scratch (kerf: 1 thread; Embree: a 1-thread device, low and medium quality);
//  - structure update after a cut (a plane through the middle: the triangles it crosses split in
//    place and appended, a fan cap appended), on both meshes: kerf local update (touched chunks
//    refitted, new chunks for new triangles), kerf whole refit (same topology, vertices moved by
//    half a kerf), kerf rebuild, and their physical floor: a copy of the cut mesh's bytes into
//    fresh arrays, which any update that keeps its own copy of the mesh does; on the calcaneus
//    also Embree rebuild (low quality), Embree refit, and Embree as 64 instanced chunks with only
//    the touched chunks recommitted.
// Meshes: the calcaneus refined x16 (933k triangles) and an icosphere (1.31M). The process runs
// with kerf-rt's heap set-up (keep_freed_memory), as the world builder does.
//   build/bin/bench_collision --benchmark_repetitions=5 --benchmark_counters_tabular=true
#include <embree3/rtcore.h>
#include <malloc.h>

#include "rt_core/loop/realtime_setup.hpp"
#include "tests/physics/bench_support.hpp"

namespace kerf::physics::bench {
namespace {

// ---- the cut used by the update benchmarks ------------------------------------------------

/// Splits every triangle crossing the plane x = x0 into three (the crossing vertex's side in
/// place, two appended) and appends a cap fan: what a slice does to the collision mesh.
test::TestMesh cut_at(const test::TestMesh& in, double x0) {
    test::TestMesh m = in;
    m.positions.reserve(in.positions.size() * 2);
    Vec3 cap_centre;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> rim;
    const std::size_t n = in.triangles();
    for (std::size_t t = 0; t < n; ++t) {
        std::uint32_t v[3] = {in.indices[3 * t], in.indices[3 * t + 1], in.indices[3 * t + 2]};
        double s[3];
        for (int k = 0; k < 3; ++k) s[k] = in.vertex(v[k]).x - x0;
        int lone = -1;
        for (int k = 0; k < 3; ++k) {
            if ((s[k] > 0) != (s[(k + 1) % 3] > 0) && (s[k] > 0) != (s[(k + 2) % 3] > 0)) lone = k;
        }
        if (lone < 0) continue;
        const std::uint32_t a = v[lone], b = v[(lone + 1) % 3], c = v[(lone + 2) % 3];
        const double sa = s[lone], sb = s[(lone + 1) % 3], sc = s[(lone + 2) % 3];
        const Vec3 pa = in.vertex(a);
        const std::uint32_t p = m.add_vertex(pa + (in.vertex(b) - pa) * (sa / (sa - sb)));
        const std::uint32_t q = m.add_vertex(pa + (in.vertex(c) - pa) * (sa / (sa - sc)));
        m.indices[3 * t + 1] = p, m.indices[3 * t + 2] = q;
        m.add_triangle(p, b, c, in.materials[t]);
        m.add_triangle(p, c, q, in.materials[t]);
        cap_centre += m.vertex(p);
        rim.emplace_back(p, q);
    }
    if (!rim.empty()) {
        const std::uint32_t centre = m.add_vertex(cap_centre * (1.0 / double(rim.size())));
        for (auto [p, q] : rim) m.add_triangle(centre, q, p, Material::kCutSurface);
    }
    return m;
}

/// Same topology, vertices within 1 mm of x = x0 pushed 0.4 mm away from it (a CutProgress).
test::TestMesh spread_at(const test::TestMesh& in, double x0) {
    test::TestMesh m = in;
    for (std::size_t i = 0; i < m.positions.size(); i += 3) {
        const double d = m.positions[i] - x0;
        if (std::abs(d) < 0.001) m.positions[i] += float(d < 0 ? -0.0004 : 0.0004);
    }
    return m;
}

double mesh_centre_x(const test::TestMesh& m) {
    double lo = 1e9, hi = -1e9;
    for (std::size_t i = 0; i < m.positions.size(); i += 3)
        lo = std::min<double>(lo, m.positions[i]), hi = std::max<double>(hi, m.positions[i]);
    return 0.5 * (lo + hi) + 0.0001234;  // off any vertex plane
}

// ---- Embree -------------------------------------------------------------------------------

RTCDevice embree_device() {
    static RTCDevice device = rtcNewDevice("threads=1");
    return device;
}

/// One Embree scene over flat arrays: a single triangle geometry, or `chunk_count` instanced
/// chunk scenes (triangles grouped in Morton order of their centroids).
struct EmbreeMesh {
    std::vector<float> vertices;                      // x y z per vertex, + 1 float of padding
    std::vector<std::vector<std::uint32_t>> indices;  // per chunk, into `vertices`
    std::vector<std::vector<std::uint32_t>> ids;      // per chunk: mesh triangle index
    std::vector<RTCScene> chunk_scenes;
    std::vector<RTCGeometry> chunk_geometries;
    RTCScene top = nullptr;

    ~EmbreeMesh() {
        if (top) rtcReleaseScene(top);
        for (RTCScene s : chunk_scenes) rtcReleaseScene(s);
    }
};

RTCScene commit_chunk(EmbreeMesh& e, std::size_t c, RTCBuildQuality quality) {
    RTCScene scene = rtcNewScene(embree_device());
    rtcSetSceneBuildQuality(scene, quality);
    RTCGeometry g = rtcNewGeometry(embree_device(), RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(
        g, quality == RTC_BUILD_QUALITY_REFIT ? RTC_BUILD_QUALITY_REFIT : quality);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, e.vertices.data(),
                               0, 12, (e.vertices.size() - 1) / 3);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, e.indices[c].data(),
                               0, 12, e.indices[c].size() / 3);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, 0);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    if (c >= e.chunk_scenes.size())
        e.chunk_scenes.resize(c + 1, nullptr), e.chunk_geometries.resize(c + 1, nullptr);
    if (e.chunk_scenes[c]) rtcReleaseScene(e.chunk_scenes[c]);
    e.chunk_scenes[c] = scene;
    e.chunk_geometries[c] = g;
    return scene;
}

std::uint32_t morton(const Vec3& p, const Vec3& lo, const Vec3& size) {
    const auto spread = [](std::uint32_t x) {
        x &= 0x3ff;
        x = (x | (x << 16)) & 0x30000ff;
        x = (x | (x << 8)) & 0x300f00f;
        x = (x | (x << 4)) & 0x30c30c3;
        return (x | (x << 2)) & 0x9249249;
    };
    const auto q = [&](double v, double l, double s) {
        return std::uint32_t(std::clamp((v - l) / s, 0.0, 0.999) * 1024);
    };
    return spread(q(p.x, lo.x, size.x)) | (spread(q(p.y, lo.y, size.y)) << 1) |
           (spread(q(p.z, lo.z, size.z)) << 2);
}

/// Builds `m` into Embree: `chunk_count` == 1 is a plain scene (no instancing).
std::unique_ptr<EmbreeMesh> embree_build(const test::TestMesh& m, std::size_t chunk_count,
                                         RTCBuildQuality quality, std::size_t vertex_reserve = 0) {
    auto e = std::make_unique<EmbreeMesh>();
    e->vertices.reserve(std::max(vertex_reserve, m.positions.size()) + 1);
    e->vertices.assign(m.positions.begin(), m.positions.end());
    e->vertices.push_back(0);
    const std::size_t n = m.triangles();
    std::vector<std::uint32_t> order(n);
    for (std::uint32_t t = 0; t < n; ++t) order[t] = t;
    if (chunk_count > 1) {
        Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
        for (std::size_t i = 0; i < m.positions.size(); i += 3) {
            lo = {std::min<double>(lo.x, m.positions[i]),
                  std::min<double>(lo.y, m.positions[i + 1]),
                  std::min<double>(lo.z, m.positions[i + 2])};
            hi = {std::max<double>(hi.x, m.positions[i]),
                  std::max<double>(hi.y, m.positions[i + 1]),
                  std::max<double>(hi.z, m.positions[i + 2])};
        }
        std::vector<std::uint32_t> code(n);
        for (std::size_t t = 0; t < n; ++t) {
            code[t] = morton((m.vertex(m.indices[3 * t]) + m.vertex(m.indices[3 * t + 1]) +
                              m.vertex(m.indices[3 * t + 2])) *
                                 (1.0 / 3),
                             lo, hi - lo);
        }
        std::sort(order.begin(), order.end(),
                  [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
    }
    e->indices.resize(chunk_count);
    e->ids.resize(chunk_count);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t c = i * chunk_count / n;
        const std::uint32_t t = order[i];
        e->ids[c].push_back(t);
        e->indices[c].insert(e->indices[c].end(),
                             {m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]});
    }
    if (chunk_count == 1) {
        commit_chunk(*e, 0, quality);
        return e;
    }
    e->top = rtcNewScene(embree_device());
    for (std::size_t c = 0; c < chunk_count; ++c) {
        RTCGeometry inst = rtcNewGeometry(embree_device(), RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, commit_chunk(*e, c, quality));
        const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
        rtcCommitGeometry(inst);
        rtcAttachGeometryByID(e->top, inst, unsigned(c));
        rtcReleaseGeometry(inst);
    }
    rtcCommitScene(e->top);
    return e;
}

RTCScene embree_root(const EmbreeMesh& e) { return e.top ? e.top : e.chunk_scenes[0]; }

struct EmbreeQuery {
    const EmbreeMesh* mesh;
    Vec3 p;
    double best = 1e300;
    std::uint32_t triangle = kNoTriangle;
};

bool embree_closest(RTCPointQueryFunctionArguments* args) {
    auto* q = static_cast<EmbreeQuery*>(args->userPtr);
    const std::size_t chunk = args->context->instStackSize > 0 ? args->context->instID[0] : 0;
    const std::uint32_t* tri = &q->mesh->indices[chunk][3 * std::size_t{args->primID}];
    const float* v = q->mesh->vertices.data();
    const auto at = [&](std::uint32_t i) { return Vec3{v[3 * i], v[3 * i + 1], v[3 * i + 2]}; };
    const Vec3 c = closest_point_on_triangle(q->p, at(tri[0]), at(tri[1]), at(tri[2]));
    const double d = norm(c - q->p);
    if (d >= q->best) return false;
    q->best = d;
    q->triangle = q->mesh->ids[chunk][args->primID];
    args->query->radius = float(d);
    return true;
}

double embree_distance(const EmbreeMesh& e, const Vec3& p, double radius) {
    RTCPointQuery query;
    query.x = float(p.x), query.y = float(p.y), query.z = float(p.z), query.time = 0;
    query.radius = float(radius);
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    EmbreeQuery q{&e, p};
    q.best = radius;
    rtcPointQuery(embree_root(e), &query, &context, embree_closest, &q);
    return q.best;
}

// ---- fixtures -----------------------------------------------------------------------------

const test::TestMesh& mesh_for(int which) {
    // 0: calcaneus x16 (933k), 1: icosphere 1.31M. Quick mode: the raw bone and a 5k sphere.
    if (which == 0) return bone(quick_mode() ? 0 : 2);
    return sphere(quick_mode() ? 4 : 8);
}
const char* name_of(int which) { return which == 0 ? "calcaneus" : "sphere"; }

struct QueryFixture {
    std::unique_ptr<const CollisionBody> body;
    std::unique_ptr<EmbreeMesh> embree;
    std::vector<Vec3> walk;
};

QueryFixture& query_fixture(int which) {
    static std::map<int, std::unique_ptr<QueryFixture>> cache;
    auto& f = cache[which];
    if (!f) {
        f = std::make_unique<QueryFixture>();
        const test::TestMesh& m = mesh_for(which);
        if (m.triangles() == 0) return *f;
        f->body = std::move(*CollisionBody::build(m.view()));
        f->embree = embree_build(m, 1, RTC_BUILD_QUALITY_MEDIUM);
        f->walk = surface_walk(*f->body, quick_mode() ? 500 : 20000, 0.0, 0.002);
    }
    return *f;
}

template <class Query>
void time_walk(benchmark::State& state, const std::vector<Vec3>& walk, const Query& query) {
    Timings t;
    t.ns.reserve(walk.size());
    for (auto _ : state) {
        t.ns.clear();
        for (const Vec3& p : walk) {
            const double start = now_ns();
            const double d = query(p);
            t.ns.push_back(now_ns() - start);
            benchmark::DoNotOptimize(d);
        }
    }
    state.counters["p50_us"] = t.percentile(0.5) / 1e3;
    state.counters["p99_us"] = t.percentile(0.99) / 1e3;
    state.counters["max_us"] = t.percentile(1.0) / 1e3;
}

void BM_ClosestPointKerf(benchmark::State& state) {
    QueryFixture& f = query_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    time_walk(state, f.walk,
              [&](const Vec3& p) { return f.body->closest_point(p, 0.01).distance; });
    state.counters["triangles"] = double(f.body->triangle_count());
}

void BM_ClosestPointEmbree(benchmark::State& state) {
    QueryFixture& f = query_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    time_walk(state, f.walk, [&](const Vec3& p) { return embree_distance(*f.embree, p, 0.01); });
    int mismatches = 0;
    for (const Vec3& p : f.walk) {
        const double a = f.body->closest_point(p, 0.01).distance,
                     b = embree_distance(*f.embree, p, 0.01);
        mismatches += std::abs(a - b) > 1e-7 ? 1 : 0;
    }
    state.counters["mismatches"] = mismatches;
    state.counters["triangles"] = double(f.body->triangle_count());
}

std::size_t heap_in_use() {
    const struct mallinfo2 mi = mallinfo2();
    return mi.uordblks + mi.hblkhd;
}

void BM_BuildKerf(benchmark::State& state) {
    const test::TestMesh& m = mesh_for(int(state.range(0)));
    std::size_t bytes = 0;
    for (auto _ : state) {
        auto body = CollisionBody::build(m.view());
        bytes = (*body)->memory_bytes();
        benchmark::DoNotOptimize(body);
    }
    state.counters["MiB"] = double(bytes) / (1 << 20);
}

void BM_BuildEmbree(benchmark::State& state) {
    const test::TestMesh& m = mesh_for(int(state.range(0)));
    const auto quality = RTCBuildQuality(state.range(1));
    std::size_t bytes = 0;
    for (auto _ : state) {
        const std::size_t before = heap_in_use();
        auto e = embree_build(m, 1, quality);
        bytes = heap_in_use() - before;
        benchmark::DoNotOptimize(e);
    }
    state.counters["MiB"] = double(bytes) / (1 << 20);  // glibc heap (Embree allocates there)
}

// ---- update after a cut (calcaneus 933k, sphere 1.31M) ------------------------------------

struct CutFixture {
    test::TestMesh before, cut, spread;
    std::unique_ptr<const CollisionBody> body;
};

CutFixture& cut_fixture(int which) {
    static std::map<int, std::unique_ptr<CutFixture>> cache;
    auto& f = cache[which];
    if (!f) {
        f = std::make_unique<CutFixture>();
        f->before = mesh_for(which);
        if (f->before.triangles() == 0) return *f;
        const double x0 = mesh_centre_x(f->before);
        f->cut = cut_at(f->before, x0);
        f->spread = spread_at(f->before, x0);
        f->body = std::move(*CollisionBody::build(f->before.view()));
    }
    return *f;
}

void BM_UpdateKerfLocal(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    UpdateStats stats;
    for (auto _ : state) {
        auto next = CollisionBody::update(*f.body, f.cut.view(), &stats);
        benchmark::DoNotOptimize(next);
    }
    state.counters["chunks"] = stats.chunks_total;
    state.counters["refitted"] = stats.chunks_refitted;
    state.counters["rebuilt"] = stats.chunks_rebuilt;
    state.counters["regrouped"] = stats.chunks_regrouped;
    state.counters["triangles"] = double(f.cut.triangles());
    state.counters["added_tris"] = double(f.cut.triangles() - f.before.triangles());
}

/// The floor of an update that keeps its own copy of the mesh: the cut mesh's positions,
/// indices and materials copied into fresh arrays (as CollisionBody does, on the same heap).
void BM_UpdateFloorMemcpy(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    for (auto _ : state) {
        std::vector<float> positions(f.cut.positions.begin(), f.cut.positions.end());
        std::vector<std::uint32_t> indices(f.cut.indices.begin(), f.cut.indices.end());
        std::vector<Material> materials(f.cut.materials.begin(), f.cut.materials.end());
        benchmark::DoNotOptimize(positions.data());
        benchmark::DoNotOptimize(indices.data());
        benchmark::DoNotOptimize(materials.data());
    }
    state.counters["MiB"] =
        double(f.cut.positions.size() * 4 + f.cut.indices.size() * 4 + f.cut.materials.size()) /
        (1 << 20);
}

void BM_UpdateKerfWholeRefit(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    for (auto _ : state) {
        auto next = CollisionBody::refit(*f.body, f.spread.view());
        benchmark::DoNotOptimize(next);
    }
}

void BM_UpdateKerfRebuild(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    for (auto _ : state) {
        auto next = CollisionBody::build(f.cut.view());
        benchmark::DoNotOptimize(next);
    }
}

void BM_UpdateEmbreeRebuild(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    for (auto _ : state) {
        auto e = embree_build(f.cut, 1, RTC_BUILD_QUALITY_LOW);
        benchmark::DoNotOptimize(e);
    }
}

void BM_UpdateEmbreeRefit(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    auto e = embree_build(f.before, 1, RTC_BUILD_QUALITY_REFIT);
    for (auto _ : state) {
        state.PauseTiming();
        const bool forward = e->vertices[0] == f.before.positions[0];
        const auto& src = forward ? f.spread.positions : f.before.positions;
        std::copy(src.begin(), src.end(), e->vertices.begin());
        state.ResumeTiming();
        rtcUpdateGeometryBuffer(e->chunk_geometries[0], RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(e->chunk_geometries[0]);
        rtcCommitScene(e->chunk_scenes[0]);
    }
}

void BM_UpdateEmbreeChunks(benchmark::State& state) {
    CutFixture& f = cut_fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no mesh");
    std::size_t touched = 0;
    for (auto _ : state) {
        state.PauseTiming();
        auto e = embree_build(f.before, 64, RTC_BUILD_QUALITY_LOW, f.cut.positions.size());
        state.ResumeTiming();
        // The cut: new vertices, changed triangles patched in their chunks, new triangles in a new
        // chunk; recommit the touched chunk scenes and the top scene.
        e->vertices.pop_back();
        e->vertices.insert(e->vertices.end(), f.cut.positions.begin() + f.before.positions.size(),
                           f.cut.positions.end());
        e->vertices.push_back(0);
        std::vector<char> dirty(64, 0);
        for (std::size_t c = 0; c < 64; ++c) {
            for (std::size_t i = 0; i < e->ids[c].size(); ++i) {
                const std::uint32_t t = e->ids[c][i];
                for (int k = 0; k < 3; ++k) {
                    if (e->indices[c][3 * i + k] != f.cut.indices[3 * t + k])
                        e->indices[c][3 * i + k] = f.cut.indices[3 * t + k], dirty[c] = 1;
                }
            }
        }
        touched = 0;
        for (std::size_t c = 0; c < 64; ++c) {
            if (!dirty[c]) continue;
            ++touched;
            commit_chunk(*e, c, RTC_BUILD_QUALITY_LOW);
            rtcSetGeometryInstancedScene(rtcGetGeometry(e->top, unsigned(c)), e->chunk_scenes[c]);
            rtcCommitGeometry(rtcGetGeometry(e->top, unsigned(c)));
        }
        e->indices.emplace_back(f.cut.indices.begin() + 3 * f.before.triangles(),
                                f.cut.indices.end());
        e->ids.emplace_back();
        for (std::size_t t = f.before.triangles(); t < f.cut.triangles(); ++t)
            e->ids.back().push_back(std::uint32_t(t));
        RTCGeometry inst = rtcNewGeometry(embree_device(), RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, commit_chunk(*e, 64, RTC_BUILD_QUALITY_LOW));
        const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
        rtcCommitGeometry(inst);
        rtcAttachGeometryByID(e->top, inst, 64);
        rtcReleaseGeometry(inst);
        rtcCommitScene(e->top);
        state.PauseTiming();
        // Check the updated scene answers like a fresh kerf build of the cut mesh.
        if (state.iterations() == 0) {
            auto fresh = CollisionBody::build(f.cut.view());
            int mismatches = 0;
            for (int i = 0; i < 200; ++i) {
                const Vec3 p =
                    f.cut.vertex(std::uint32_t(i * 7919 % (f.cut.positions.size() / 3))) +
                    Vec3{0.0005, 0.0003, -0.0002};
                mismatches += std::abs((*fresh)->closest_point(p, 0.01).distance -
                                       embree_distance(*e, p, 0.01)) > 1e-7;
            }
            state.counters["mismatches"] = mismatches;
        }
        e.reset();
        state.ResumeTiming();
    }
    state.counters["touched_chunks"] = double(touched);
}

void register_all() {
    // The heap kerf-rt runs with (freed memory kept, rt_core/loop/realtime_setup.hpp): a
    // structure update reuses pages faulted in by earlier ones, as it does in kerf-rt.
    if (!kerf::rt::keep_freed_memory().ok) std::fprintf(stderr, "keep_freed_memory refused\n");
    for (int which : {0, 1}) {
        const std::string n = name_of(which);
        with_min_max(
            benchmark::RegisterBenchmark(("BM_ClosestPointKerf/" + n).c_str(), BM_ClosestPointKerf))
            ->Arg(which)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
        with_min_max(benchmark::RegisterBenchmark(("BM_ClosestPointEmbree/" + n).c_str(),
                                                  BM_ClosestPointEmbree))
            ->Arg(which)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
    }
    with_min_max(benchmark::RegisterBenchmark("BM_BuildKerf/calcaneus", BM_BuildKerf))
        ->Arg(0)
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
    with_min_max(benchmark::RegisterBenchmark("BM_BuildEmbree/calcaneus/low", BM_BuildEmbree))
        ->Args({0, RTC_BUILD_QUALITY_LOW})
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
    with_min_max(benchmark::RegisterBenchmark("BM_BuildEmbree/calcaneus/medium", BM_BuildEmbree))
        ->Args({0, RTC_BUILD_QUALITY_MEDIUM})
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
    // The three updates and their floor on each mesh, one after the other (one run, same load).
    for (int which : {0, 1}) {
        const std::string n = name_of(which);
        const std::pair<const char*, void (*)(benchmark::State&)> updates[] = {
            {"BM_UpdateKerfLocal/", BM_UpdateKerfLocal},
            {"BM_UpdateKerfWholeRefit/", BM_UpdateKerfWholeRefit},
            {"BM_UpdateKerfRebuild/", BM_UpdateKerfRebuild},
            {"BM_UpdateFloorMemcpy/", BM_UpdateFloorMemcpy}};
        for (const auto& [name, fn] : updates) {
            with_min_max(benchmark::RegisterBenchmark((name + n).c_str(), fn))
                ->Arg(which)
                ->Iterations(1)
                ->Unit(benchmark::kMillisecond);
        }
    }
    with_min_max(benchmark::RegisterBenchmark("BM_UpdateEmbreeRebuildLow", BM_UpdateEmbreeRebuild))
        ->Arg(0)
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
    with_min_max(benchmark::RegisterBenchmark("BM_UpdateEmbreeRefit", BM_UpdateEmbreeRefit))
        ->Arg(0)
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
    with_min_max(benchmark::RegisterBenchmark("BM_UpdateEmbree64Chunks", BM_UpdateEmbreeChunks))
        ->Arg(0)
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
}

}  // namespace
}  // namespace kerf::physics::bench

KERF_PHYSICS_BENCH_MAIN(kerf::physics::bench::register_all)
