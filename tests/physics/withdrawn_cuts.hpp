// The calcaneus cut the way a session cuts it, for the benchmark of the tick after cuts
// (bench_physics BM_TickAfterCuts) and the test that the proxy stays out of bone the blade never
// separated (tests/rt/withdrawn_cut_contact_test.cpp): localised withdrawn saw cuts applied by the
// display's own code (CutSession through apply_record), exported as kerf-display publishes them
// after every CutEnd (export_collision) and turned into the collision structure as kerf-rt's
// WorldBuilder does (body_view, CollisionBody::update from the previous body). Units: m.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "display/app/collision_export.hpp"
#include "display/app/session_events_ipc.hpp"
#include "rt_core/loop/world_builder.hpp"
#include "rt_core/physics/collision_body.hpp"
#include "rt_core/physics/collision_world.hpp"
#include "rt_core/physics/force_model.hpp"
#include "tests/physics/physics_test_shapes.hpp"

namespace kerf::physics::test {

/// Publishes the session as kerf-display does and updates `bodies` as kerf-rt's WorldBuilder does
/// (aborts on a refusal: the fixtures are known good).
inline void publish(const cut::CutSession& session, ipc::CollisionMesh& mesh,
                    std::vector<std::shared_ptr<const CollisionBody>>& bodies) {
    if (auto ok = display::export_collision(session, mesh); !ok) std::abort();
    std::vector<Material> materials;
    std::vector<std::shared_ptr<const CollisionBody>> next;
    for (std::uint32_t b = 0; b < mesh.body_count; ++b) {
        const CollisionMeshView view = rt::body_view(mesh, b, materials);
        auto body = b < bodies.size() ? CollisionBody::update(*bodies[b], view)
                                      : CollisionBody::build(view);
        if (!body) std::abort();
        next.push_back(std::move(*body));
    }
    bodies = std::move(next);
}

/// One withdrawn saw cut as a session makes it: a 0.8 mm kerf 10 mm long and 4 mm deep from the
/// surface inwards. Blade frame: plane normal `normal`, v = `outwards` (the surface normal: the
/// blade goes -v), u = v x normal (the blade's length, along the surface).
struct WithdrawnCutSpec {
    Vec3 point;     ///< where the blade first touched (on the surface), m
    Vec3 normal;    ///< the cut plane's normal, unit
    Vec3 outwards;  ///< the surface normal there, unit, in the plane
    double kerf_m = 0.0008;
    double half_length_m = 0.005;
    double depth_m = 0.004;

    Vec3 u() const { return cross(outwards, normal); }
    /// Whether `p` is in the kerf the blade sawed (grown by `margin_m` all round).
    bool in_kerf(const Vec3& p, double margin_m) const {
        const Vec3 d = p - point;
        return std::abs(dot(d, normal)) <= 0.5 * kerf_m + margin_m &&
               std::abs(dot(d, u())) <= half_length_m + margin_m &&
               dot(d, outwards) >= -depth_m - margin_m;
    }
};

/// Cut k of `cuts` across `walk` at its point (2k + 1) / (2 cuts) of the way: the blade's plane
/// holds the surface normal of `body` there and is across the walk's direction (its normal).
inline WithdrawnCutSpec cut_across_walk(const CollisionBody& body, const std::vector<Vec3>& walk,
                                        int k, int cuts) {
    const std::size_t i = (2 * std::size_t(k) + 1) * (walk.size() - 1) / (2 * std::size_t(cuts));
    const SurfaceHit at = body.closest_point(walk[i], 0.05);
    Vec3 along = walk[std::min(i + 1, walk.size() - 1)] - walk[i > 0 ? i - 1 : 0];
    along = normalized(along - at.normal * dot(along, at.normal));
    WithdrawnCutSpec spec;
    spec.point = at.point;
    spec.normal = along;
    spec.outwards = at.normal;
    return spec;
}

/// Cut k of `cuts` across `walk` as cut_across_walk, turned about the surface normal by up to
/// +-0.6 rad, with a kerf of 0.5-1.2 mm, 6-16 mm long and 2-7 mm deep, drawn from `rng` (the
/// random withdrawn-cut sequences of the rt tests).
inline WithdrawnCutSpec turned_cut_across_walk(const CollisionBody& body,
                                               const std::vector<Vec3>& walk, int k, int cuts,
                                               std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uni(0, 1);
    WithdrawnCutSpec spec = cut_across_walk(body, walk, k, cuts);
    const double turn = (uni(rng) - 0.5) * 1.2;
    spec.normal = normalized(spec.normal * std::cos(turn) + spec.u() * std::sin(turn));
    spec.kerf_m = (0.5 + 0.7 * uni(rng)) * 1e-3;
    spec.half_length_m = (3 + 5 * uni(rng)) * 1e-3;
    spec.depth_m = (2 + 5 * uni(rng)) * 1e-3;
    return spec;
}

/// Applies the cut to `session` as kerf-rt's events would: CutBegin, a CutProgress every 0.2 mm
/// of depth, CutEnd{withdrawn}, then an idle step. Returns what the CutBegin did.
inline cut::ApplyReport apply_withdrawn_cut(cut::CutSession& session, const WithdrawnCutSpec& spec,
                                            std::uint32_t cut_id) {
    const auto to_cut = [](const Vec3& p) { return cut::Vec3(p.x, p.y, p.z); };
    cut::CutBegin begin;
    begin.cut_id = cut_id;
    begin.blade = {to_cut(spec.point), to_cut(spec.normal), to_cut(spec.u())};
    begin.seed_m = to_cut(spec.point);
    begin.kerf_width_m = spec.kerf_m;
    const cut::ApplyReport report =
        display::apply_record(session, display::make_record(begin)).report;
    cut::CutProgress progress{
        begin.cut_id, begin.blade, {-spec.half_length_m, spec.half_length_m, 0, 0.002}};
    const int steps = int(std::lround(spec.depth_m / 0.0002));
    for (int step = 1; step <= steps; ++step) {  // every 0.2 mm, as kerf-rt sends them
        progress.swept.v_min_m = -spec.depth_m * step / steps;
        display::apply_record(session, display::make_record(progress, begin));
    }
    const cut::CutEnd end{begin.cut_id, cut::CutEndKind::kWithdrawn};
    display::apply_record(session, display::make_record(end, begin));
    session.idle();
    return report;
}

/// Where the proxy went on a walk (ForceModel::step each tick, as BM_TickAfterCuts does).
struct ProxyStray {
    double depth_max_m = 0;      ///< deepest inside the uncut bone, outside every sawn kerf
    std::size_t deep_ticks = 0;  ///< ticks deeper than `deep_m` there
    double trail_max_m = 0;      ///< largest proxy-device distance
};

/// Steps a fresh ForceModel along `walk` on `world` and measures each tick's proxy against the
/// uncut bone (`uncut`: depth by CollisionWorld::way_out, so exact on a closed mesh), leaving out
/// proxies within `kerf_margin_m` of the kerfs of `sawn`. Not real-time (queries per tick).
inline ProxyStray walk_proxy(const CollisionWorld& world, const CollisionWorld& uncut,
                             const std::vector<Vec3>& walk,
                             const std::vector<WithdrawnCutSpec>& sawn, double deep_m,
                             double kerf_margin_m) {
    ProxyStray stray;
    ForceModel model;
    Vec3 lo, hi;
    uncut.body(0)->bounds(lo, hi);
    model.reset(hi + (hi - lo));  // far outside
    for (std::size_t i = 0; i < walk.size(); ++i) {
        ToolInput in;
        in.pose.position_m = walk[i];
        in.velocity_m_s = i > 0 ? (walk[i] - walk[i - 1]) * 1000.0 : Vec3{};
        const Vec3 p = model.step(world, in, 1e-3).contact.proxy_m;
        stray.trail_max_m = std::max(stray.trail_max_m, norm(p - walk[i]));
        if (std::any_of(sawn.begin(), sawn.end(),
                        [&](const WithdrawnCutSpec& c) { return c.in_kerf(p, kerf_margin_m); })) {
            continue;
        }
        const SurfaceHit near = uncut.closest_point(p, 0.1);
        if (!near.found) continue;
        const CollisionWorld::WayOut out = uncut.way_out(p, near.point, 0.2);
        if (out.known && out.depth <= 0) continue;  // outside (unknown counts as inside)
        stray.depth_max_m = std::max(stray.depth_max_m, near.distance);
        stray.deep_ticks += near.distance > deep_m ? 1 : 0;
    }
    return stray;
}

/// One random sequence of withdrawn cuts turned about the surface normal, drawn from `seed` (the
/// sequences of WithdrawnCutContact and WithdrawnCutProbe): a surface walk of 6,000-20,000 ticks
/// and 6-17 cuts across it, each applied with apply_withdrawn_cut and the collision bodies then
/// republished; `after_cut(k, cuts, report)` after each. Returns the number of cuts.
template <class AfterCut>
int apply_turned_withdrawn_sequence(cut::CutSession& session, std::uint64_t seed,
                                    AfterCut&& after_cut) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0, 1);
    auto mesh = std::make_unique<ipc::CollisionMesh>();
    std::vector<std::shared_ptr<const CollisionBody>> bodies;
    publish(session, *mesh, bodies);
    const int ticks = 6000 + int(uni(rng) * 14000);
    const int cuts = 6 + int(uni(rng) * 12);
    const std::vector<Vec3> walk = surface_walk(*bodies[0], ticks, -0.002, 0.0005);
    for (int k = 0; k < cuts; ++k) {
        const auto spec = turned_cut_across_walk(*bodies[0], walk, k, cuts, rng);
        const cut::ApplyReport r = apply_withdrawn_cut(session, spec, std::uint32_t(k + 1));
        publish(session, *mesh, bodies);
        after_cut(k, cuts, r);
    }
    return cuts;
}

}  // namespace kerf::physics::test
