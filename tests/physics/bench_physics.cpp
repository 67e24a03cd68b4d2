// Per-tick collision + force (ForceModel::step: god-object casts, friction, passivity) on the real
// calcaneus at its own resolution (58k triangles) and refined x4, x16, x64 (233k, 933k, 3.73M),
// the tool sliding over the surface 0.5 mm outside to 2 mm inside. Each repetition times every
// tick of a 20,000-tick walk; counters: p50 / p99 / max in us. The reference in the same run is one
// closest-point query per tick on the same walk (the least any collision step does).
// BM_ReseatTick times the other per-tick path: a tick with no force reaching the hand re-seats the
// proxy first (ForceModel::reset_outside: one closest-point query within the loop's 50 mm reach
// and CollisionWorld::way_out: one traversal per body collecting every crossing along the ray),
// then steps; counters as above, the same for the re-seat alone (reseat_p50_us, reseat_p99_us),
// and for the re-seat as it was before (casts_p50_us, casts_p99_us: the same closest point, then
// one segment cast per crossing, up to 24, each a whole traversal: ReseatByCasts below). Also on
// the 24-shell forefoot (shells interpenetrating at the joints: the ray crosses several), with its
// own reference.
// Why the tick grows with the mesh (BM_TickWarmCold): each tick is timed three ways on the same
// walk's first 6,000 ticks — as it comes (even ticks: first), repeated on a copy of the model with
// the same input (the same work with its data in cache: warm), and after evicting the per-core
// caches by writing 8 MiB (odd ticks: cold; L1 + L2 here are 96 KiB + 4 MiB in all, the shared L3
// of 260 MiB is not evicted: what the real loop sees after a millisecond of other processes on its
// core). Warm growth is the extra work of a deeper tree; the rest is memory.
// The tick after many cuts (BM_TickAfterCuts/N): the calcaneus as scanned, cut N times (10, 30)
// the way a session cuts it — each a localised withdrawn saw cut (a 0.8 mm kerf 10 mm long and
// 4 mm deep across the walk, from the surface inwards) applied by the display's own code
// (CutSession through apply_record; tests/physics/withdrawn_cuts.hpp), exported as kerf-display
// publishes it after every CutEnd (export_collision), and each published mesh turned into the
// collision structure as kerf-rt's WorldBuilder does (body_view, CollisionBody::update from the
// previous body: the cut's new triangles in new chunks overlapping the old ones, touched chunks
// refitted). The walk is BM_Tick's and crosses every kerf; the reference in the same run is the
// same walk on the uncut bone (BM_TickAfterCuts/0), and the last cut mesh built from scratch
// (.._last_built_fresh/-1: what no update history can beat). Counters as BM_Tick, plus chunks
// (count), triangles, and one closest-point query per walk point on the same world (cp_p50_us,
// cp_p99_us: the structure's cost alone, whatever the contact state). Untimed, the same walk once
// more says where the proxy went: proxy_depth_max_mm (deepest inside the uncut bone, outside the
// kerfs sawn), proxy_deep_ticks (ticks deeper than 4.5 mm there) and proxy_trail_max_mm (largest
// proxy-tool distance).
//   build/bin/bench_physics --benchmark_repetitions=5 --benchmark_counters_tabular=true
#include "display/mesh/mesh_io.hpp"
#include "rt_core/physics/force_model.hpp"
#include "tests/physics/bench_support.hpp"
#include "tests/physics/withdrawn_cuts.hpp"

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

/// The re-seat's ray walk before one-traversal way_out (kept to measure against in the same run):
/// one first_hit cast per crossing, from just past the previous one. Returns the depth.
int way_out_by_casts(const CollisionWorld& world, const Vec3& from, const Vec3& towards) {
    Vec3 d = normalized(towards - from);
    if (norm2(d) == 0) d = Vec3{0, 1, 0};
    constexpr double kLength = 1.0, kStep = 1e-9;
    const Vec3 end = from + d * kLength;
    int depth = 0, count = 0;
    for (double s = 0; s < kLength;) {
        const SegmentHit hit = world.first_hit(from + d * s, end, HitSides::kBoth);
        if (!hit.found) break;
        if (++count > 24) return -1;
        depth += dot(d, hit.normal) > 0 ? 1 : -1;
        s = s + hit.t * (kLength - s) + kStep;
    }
    return depth;
}

// A tick with no force reaching the hand: reset_outside, then the step (the loop's order).
void BM_ReseatTick(benchmark::State& state) {
    Fixture& f = fixture(int(state.range(0)));
    if (!f.body) return state.SkipWithError("no shared meshes");
    constexpr double kReach = 0.05;  // HapticLoop::kReengageReach
    Timings t, reseat, casts;
    for (Timings* x : {&t, &reseat, &casts}) x->ns.reserve(f.walk.size());
    int inside = 0;  // ticks the re-seat moved the proxy out of the bone
    for (auto _ : state) {
        for (Timings* x : {&t, &reseat, &casts}) x->ns.clear();
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
            // The same re-seat by casts (the closest point, then the walk), timed after the step.
            const double cast_start = now_ns();
            const SurfaceHit near =
                f.world.closest_point(in.pose.position_m, kReach, kBoneSurfaces);
            const Vec3 towards = near.found ? near.point : in.pose.position_m + Vec3{0, 1, 0};
            const int depth = way_out_by_casts(f.world, in.pose.position_m, towards);
            casts.ns.push_back(now_ns() - cast_start);
            benchmark::DoNotOptimize(depth);
        }
    }
    report(state, t, f);
    state.counters["reseat_p50_us"] = reseat.percentile(0.50) / 1e3;
    state.counters["reseat_p99_us"] = reseat.percentile(0.99) / 1e3;
    state.counters["casts_p50_us"] = casts.percentile(0.50) / 1e3;
    state.counters["casts_p99_us"] = casts.percentile(0.99) / 1e3;
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

// ---- the tick after many cuts ------------------------------------------------------------------

/// The key of the last cut mesh's world built from scratch instead of updated cut by cut.
constexpr int kBuiltFresh = -1;

/// The calcaneus after 0, 10 and 30 localised cuts, one world each, and the walk.
struct CutFixture {
    std::map<int, std::vector<std::shared_ptr<const CollisionBody>>> bodies;  // by cut count
    std::map<int, CollisionWorld> worlds;
    std::vector<Vec3> walk;
    std::vector<test::WithdrawnCutSpec> sawn;  // every cut, in order
};

using test::publish;

CutFixture* cut_fixture() {
    static std::unique_ptr<CutFixture> f;
    static bool tried = false;
    if (tried) return f.get();
    tried = true;
    const auto file = std::filesystem::path(KERF_SHARED_MESHES) / "jma_norm01_calcaneus_right.stl";
    auto scene = mesh::load_mesh_owned(file, LengthUnit::kMillimetre);
    if (!scene) return nullptr;
    f = std::make_unique<CutFixture>();
    cut::CutSession session(std::move(*scene));
    auto mesh = std::make_unique<ipc::CollisionMesh>();
    std::vector<std::shared_ptr<const CollisionBody>> bodies;
    publish(session, *mesh, bodies);
    f->walk = surface_walk(*bodies[0], quick_mode() ? 500 : 20000, -0.002, 0.0005);
    const std::vector<int> counts =
        quick_mode() ? std::vector<int>{0, 1} : std::vector<int>{0, 10, 30};
    const int cuts = counts.back();
    for (int k = 0; k <= cuts; ++k) {
        if (std::find(counts.begin(), counts.end(), k) != counts.end()) {
            f->bodies[k] = bodies;
            CollisionWorld& world = f->worlds[k];
            for (std::uint32_t b = 0; b < bodies.size(); ++b) world.set_body(b, bodies[b].get());
        }
        if (k == cuts) {  // the last mesh built from scratch: what no update history can beat
            std::vector<Material> materials;
            auto& fresh = f->bodies[kBuiltFresh];
            for (std::uint32_t b = 0; b < mesh->body_count; ++b) {
                fresh.push_back(
                    std::move(*CollisionBody::build(rt::body_view(*mesh, b, materials))));
                f->worlds[kBuiltFresh].set_body(b, fresh.back().get());
            }
            break;
        }
        // Cut k across the walk: the blade's plane holds the surface normal and is across the
        // walk's direction; the blade lies along the surface.
        f->sawn.push_back(test::cut_across_walk(*bodies[0], f->walk, k, cuts));
        test::apply_withdrawn_cut(session, f->sawn.back(), std::uint32_t(k + 1));
        publish(session, *mesh, bodies);
    }
    return f.get();
}

void BM_TickAfterCuts(benchmark::State& state) {
    CutFixture* f = cut_fixture();
    if (!f) return state.SkipWithError("no shared meshes");
    const int cuts = int(state.range(0));
    const CollisionWorld& world = f->worlds.at(cuts);
    Timings t;
    t.ns.reserve(f->walk.size());
    int touching = 0;
    for (auto _ : state) {
        t.ns.clear();
        ForceModel model;
        Vec3 lo, hi;
        f->bodies.at(cuts)[0]->bounds(lo, hi);
        model.reset(hi + (hi - lo));  // far outside
        for (std::size_t i = 0; i < f->walk.size(); ++i) {
            ToolInput in;
            in.pose.position_m = f->walk[i];
            in.velocity_m_s = i > 0 ? (f->walk[i] - f->walk[i - 1]) * 1000.0 : Vec3{};
            const double start = now_ns();
            const PhysicsOutput out = model.step(world, in, 1e-3);
            t.ns.push_back(now_ns() - start);
            touching += out.contact.in_contact ? 1 : 0;
            benchmark::DoNotOptimize(out);
        }
    }
    state.counters["p50_us"] = t.percentile(0.50) / 1e3;
    state.counters["p99_us"] = t.percentile(0.99) / 1e3;
    state.counters["max_us"] = t.percentile(1.0) / 1e3;
    double triangles = 0, chunks = 0;
    for (const auto& b : f->bodies.at(cuts)) {
        triangles += double(b->triangle_count());
        chunks += double(b->chunk_count());
    }
    state.counters["triangles"] = triangles;
    state.counters["chunks"] = chunks;
    Timings cp;
    for (const Vec3& p : f->walk) {
        const double start = now_ns();
        const SurfaceHit hit = world.closest_point(p, 0.01);
        cp.ns.push_back(now_ns() - start);
        benchmark::DoNotOptimize(hit);
    }
    state.counters["cp_p50_us"] = cp.percentile(0.50) / 1e3;
    state.counters["cp_p99_us"] = cp.percentile(0.99) / 1e3;
    state.counters["contact_share"] =
        double(touching) / double(f->walk.size() * state.iterations());
    // Where the proxy went (untimed): into bone the blade never separated, and behind the tool.
    const std::vector<test::WithdrawnCutSpec> sawn(
        f->sawn.begin(),
        f->sawn.begin() + std::min<std::ptrdiff_t>(cuts < 0 ? std::ptrdiff_t(f->sawn.size()) : cuts,
                                                   std::ptrdiff_t(f->sawn.size())));
    const test::ProxyStray stray =
        test::walk_proxy(world, f->worlds.at(0), f->walk, sawn, 0.0045, 0.0002);
    state.counters["proxy_depth_max_mm"] = stray.depth_max_m * 1e3;
    state.counters["proxy_deep_ticks"] = double(stray.deep_ticks);
    state.counters["proxy_trail_max_mm"] = stray.trail_max_m * 1e3;
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
    for (int cuts :
         quick_mode() ? std::vector<int>{0, 1} : std::vector<int>{0, 10, 30, kBuiltFresh}) {
        const char* name = cuts == kBuiltFresh ? "BM_TickAfterCuts/calcaneus_last_built_fresh"
                                               : "BM_TickAfterCuts/calcaneus";
        with_min_max(benchmark::RegisterBenchmark(name, BM_TickAfterCuts))
            ->Arg(cuts)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
    }
}

}  // namespace
}  // namespace kerf::physics::bench

KERF_PHYSICS_BENCH_MAIN(kerf::physics::bench::register_all)
