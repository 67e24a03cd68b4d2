// Per-tick collision + force (ForceModel::step: god-object casts, friction, passivity) on the real
// calcaneus at its own resolution (58k triangles) and refined x4, x16, x64 (233k, 933k, 3.73M),
// the tool sliding over the surface 0.5 mm outside to 2 mm inside. Each repetition times every
// tick of a 20,000-tick walk; counters: p50 / p99 / max in us. The reference in the same run is one
// closest-point query per tick on the same walk (the least any collision step does).
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

Fixture& fixture(int levels) {
    static std::map<int, std::unique_ptr<Fixture>> cache;
    auto& f = cache[levels];
    if (!f) {
        f = std::make_unique<Fixture>();
        const test::TestMesh& m = bone(levels);
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
        quick_mode() ? std::vector<int>{0} : std::vector<int>{0, 1, 2, 3};
    for (int l : levels) {
        with_min_max(benchmark::RegisterBenchmark("BM_Tick/calcaneus", BM_Tick))
            ->Arg(l)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
        with_min_max(benchmark::RegisterBenchmark("BM_ClosestPointReference/calcaneus",
                                                  BM_ClosestPointReference))
            ->Arg(l)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
    }
}

}  // namespace
}  // namespace kerf::physics::bench

KERF_PHYSICS_BENCH_MAIN(kerf::physics::bench::register_all)
