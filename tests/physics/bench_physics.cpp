// Per-tick collision + force (ForceModel::step: god-object casts, friction, passivity) on the real
// calcaneus at its own resolution (58k triangles) and refined x4, x16, x64 (233k, 933k, 3.73M),
// the tool sliding over the surface 0.5 mm outside to 2 mm inside. Each repetition times every
// tick of a 20,000-tick walk; counters: p50 / p99 / max in us. The reference in the same run is one
// closest-point query per tick on the same walk (the least any collision step does).
// BM_ReseatTick times the other per-tick path: a tick with no force reaching the hand re-seats the
// proxy first (ForceModel::reset_outside: one closest-point query within the loop's 50 mm reach
// and CollisionWorld::way_out's ray walk, up to 24 casts), then steps; counters as above, and the
// same for the re-seat alone (reseat_p50_us, reseat_p99_us). Also on the 24-shell forefoot
// (shells interpenetrating at the joints: the ray crosses several), with its own reference.
// Why the tick grows with the mesh (BM_TickWarmCold): each tick is timed three ways on the same
// walk's first 6,000 ticks — as it comes (even ticks: first), repeated on a copy of the model with
// the same input (the same work with its data in cache: warm), and after evicting the per-core
// caches by writing 8 MiB (odd ticks: cold; L1 + L2 here are 96 KiB + 4 MiB in all, the shared L3
// of 260 MiB is not evicted: what the real loop sees after a millisecond of other processes on its
// core). Warm growth is the extra work of a deeper tree; the rest is memory.
//   build/bin/bench_physics --benchmark_repetitions=5 --benchmark_counters_tabular=true
#include "rt_core/physics/force_model.hpp"
#include "tests/physics/bench_support.hpp"

namespace kerf::physics::bench {
namespace {

struct Fixture {
    std::unique_ptr<const CollisionBody> body;
    CollisionWorld world;
    std::vector<Vec3> walk;
};

/// Levels 0-3: the calcaneus refined; kForefoot: the 24-shell forefoot as scanned.
constexpr int kForefoot = 100;

const test::TestMesh& forefoot() {
    static const test::TestMesh mesh = test::read_binary_stl(
        (std::filesystem::path(KERF_SHARED_MESHES) / "bp3d_right_forefoot_24shells.stl").string(),
        0.001);
    return mesh;
}

Fixture& fixture(int levels) {
    static std::map<int, std::unique_ptr<Fixture>> cache;
    auto& f = cache[levels];
    if (!f) {
        f = std::make_unique<Fixture>();
        const test::TestMesh& m = levels == kForefoot ? forefoot() : bone(levels);
        if (m.triangles() == 0) return *f;
        f->body = std::move(*CollisionBody::build(m.view()));
        f->world.set_body(0, f->body.get());
        f->walk = surface_walk(*f->body, quick_mode() ? 500 : 20000, -0.002, 0.0005);
    }
    return *f;
}

void report(benchmark::State& state, Timings& t, const Fixture& f) {
    state.counters["p50_us"] = t.percentile(0.50) / 1e3;
    state.counters["p99_us"] = t.percentile(0.99) / 1e3;
    state.counters["max_us"] = t.percentile(1.0) / 1e3;
    state.counters["triangles"] = double(f.body->triangle_count());
}

void BM_Tick(benchmark::State& state) {
    Fixture& f = fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no shared meshes");
    Timings t;
    t.ns.reserve(f.walk.size());
    int touching = 0;
    for (auto _ : state) {
        t.ns.clear();
        ForceModel model;
        Vec3 lo, hi;
        f.body->bounds(lo, hi);
        model.reset(hi + (hi - lo));  // far outside
        for (std::size_t i = 0; i < f.walk.size(); ++i) {
            ToolInput in;
            in.pose.position_m = f.walk[i];
            in.velocity_m_s = i > 0 ? (f.walk[i] - f.walk[i - 1]) * 1000.0 : Vec3{};
            const double start = now_ns();
            const PhysicsOutput out = model.step(f.world, in, 1e-3);
            t.ns.push_back(now_ns() - start);
            touching += out.contact.in_contact ? 1 : 0;
            benchmark::DoNotOptimize(out);
        }
    }
    report(state, t, f);
    state.counters["contact_share"] = double(touching) / double(f.walk.size() * state.iterations());
}

void BM_TickWarmCold(benchmark::State& state) {
    Fixture& f = fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no shared meshes");
    Timings first, warm, cold;
    for (Timings* t : {&first, &warm, &cold}) t->ns.reserve(f.walk.size());
    static std::vector<std::uint64_t> evict(8u << 17);  // 8 MiB: twice L1 + L2
    const std::size_t ticks = std::min<std::size_t>(f.walk.size(), quick_mode() ? 40 : 6000);
    std::uint64_t stamp = 0;
    for (auto _ : state) {
        for (Timings* t : {&first, &warm, &cold}) t->ns.clear();
        ForceModel model;
        Vec3 lo, hi;
        f.body->bounds(lo, hi);
        model.reset(hi + (hi - lo));
        for (std::size_t i = 0; i < ticks; ++i) {
            ToolInput in;
            in.pose.position_m = f.walk[i];
            in.velocity_m_s = i > 0 ? (f.walk[i] - f.walk[i - 1]) * 1000.0 : Vec3{};
            if (i % 2 == 1) {  // odd ticks: evicted first (even ticks keep the walk's own cache)
                ++stamp;
                for (std::size_t w = 0; w < evict.size(); w += 8) evict[w] = stamp;
                benchmark::ClobberMemory();
            }
            ForceModel again = model;
            double start = now_ns();
            PhysicsOutput out = model.step(f.world, in, 1e-3);
            (i % 2 == 1 ? cold : first).ns.push_back(now_ns() - start);
            benchmark::DoNotOptimize(out);
            start = now_ns();
            out = again.step(f.world, in, 1e-3);
            warm.ns.push_back(now_ns() - start);
            benchmark::DoNotOptimize(out);
        }
    }
    report(state, first, f);
    state.counters["warm_p50_us"] = warm.percentile(0.50) / 1e3;
    state.counters["warm_p99_us"] = warm.percentile(0.99) / 1e3;
    state.counters["cold_p50_us"] = cold.percentile(0.50) / 1e3;
    state.counters["cold_p99_us"] = cold.percentile(0.99) / 1e3;
}

// A tick with no force reaching the hand: reset_outside, then the step (the loop's order).
void BM_ReseatTick(benchmark::State& state) {
    Fixture& f = fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no shared meshes");
    constexpr double kReach = 0.05;  // HapticLoop::kReengageReach
    Timings t, reseat;
    t.ns.reserve(f.walk.size());
    reseat.ns.reserve(f.walk.size());
    int inside = 0;  // ticks the re-seat moved the proxy out of the bone
    for (auto _ : state) {
        t.ns.clear();
        reseat.ns.clear();
        ForceModel model;
        for (std::size_t i = 0; i < f.walk.size(); ++i) {
            ToolInput in;
            in.pose.position_m = f.walk[i];
            in.velocity_m_s = i > 0 ? (f.walk[i] - f.walk[i - 1]) * 1000.0 : Vec3{};
            const double start = now_ns();
            model.reset_outside(f.world, in.pose.position_m, kReach);
            const double seated = now_ns();
            const Vec3 seated_at = model.contact().proxy();
            const PhysicsOutput out = model.step(f.world, in, 1e-3);
            t.ns.push_back(now_ns() - start);
            reseat.ns.push_back(seated - start);
            inside += seated_at == in.pose.position_m ? 0 : 1;
            benchmark::DoNotOptimize(out);
        }
    }
    report(state, t, f);
    state.counters["reseat_p50_us"] = reseat.percentile(0.50) / 1e3;
    state.counters["reseat_p99_us"] = reseat.percentile(0.99) / 1e3;
    state.counters["moved_share"] = double(inside) / double(f.walk.size() * state.iterations());
}

void BM_ClosestPointReference(benchmark::State& state) {
    Fixture& f = fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no shared meshes");
    Timings t;
    t.ns.reserve(f.walk.size());
    for (auto _ : state) {
        t.ns.clear();
        for (const Vec3& p : f.walk) {
            const double start = now_ns();
            const SurfaceHit hit = f.world.closest_point(p, 0.01);
            t.ns.push_back(now_ns() - start);
            benchmark::DoNotOptimize(hit);
        }
    }
    report(state, t, f);
}

void register_all() {
    const std::vector<int> levels =
        quick_mode() ? std::vector<int>{0} : std::vector<int>{0, 1, 2, 3, kForefoot};
    for (int l : levels) {
        const std::string mesh = l == kForefoot ? "forefoot" : "calcaneus";
        using Fn = void (*)(benchmark::State&);
        const std::pair<const char*, Fn> benches[] = {
            {"BM_Tick/", BM_Tick},
            {"BM_TickWarmCold/", BM_TickWarmCold},
            {"BM_ReseatTick/", BM_ReseatTick},
            {"BM_ClosestPointReference/", BM_ClosestPointReference}};
        for (const auto& [name, fn] : benches) {
            with_min_max(benchmark::RegisterBenchmark((name + mesh).c_str(), fn))
                ->Arg(l)
                ->Iterations(1)
                ->Unit(benchmark::kMillisecond);
        }
    }
}

}  // namespace
}  // namespace kerf::physics::bench

KERF_PHYSICS_BENCH_MAIN(kerf::physics::bench::register_all)
