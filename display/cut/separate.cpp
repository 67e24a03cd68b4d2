#include "display/cut/separate.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "display/cut/cap_clearance.hpp"

namespace kerf::cut {
namespace {

constexpr std::uint32_t kNoCell = 0xFFFFFFFFu;

using detail::BandVertex;

/// Distance from q to a counter-clockwise convex polygon (0 inside).
double distance_to_convex(const Vec2& q, std::span<const Vec2> poly) {
    bool inside = true;
    double best2 = 1e300;  // squared: one square root per query, not one per edge
    const Vec2* a = &poly.back();
    for (const Vec2& b : poly) {
        const Vec2 ab = b - *a;
        const Vec2 aq = q - *a;
        if (ab[0] * aq[1] - ab[1] * aq[0] < 0) inside = false;
        const double len2 = ab | ab;
        const double t = len2 > 0 ? std::clamp((aq | ab) / len2, 0.0, 1.0) : 0.0;
        best2 = std::min(best2, (aq - ab * t).sqrnorm());
        a = &b;
    }
    return inside ? 0.0 : std::sqrt(best2);
}

}  // namespace

struct Separator::State {
    CutContext* ctx = nullptr;
    Plane plane;
    double kerf = 0.0;
    double depth = 0.0;  // D
    double ramp = 0.0;   // width of the 1 -> 0 fall-off outside the swept region
    std::vector<BandVertex> band;
    // Grid of live (m < 1) band vertices by (u, v) cell: cell c holds items
    // [start[c], start[c] + live[c]).
    Vec2 grid_origin{0.0, 0.0};
    double cell = 1.0;
    std::uint32_t nx = 1, ny = 1;
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> live;
    std::vector<std::uint32_t> items;
    // Walls over a partly opened cap rise with it (cap_clearance.hpp).
    detail::CapClearances clearances;
    std::vector<std::uint32_t> rims_moved;  // scratch: rim band vertices the sweep moved
    std::uint32_t sweep_stamp = 0;
    std::vector<Vec2> poly;                 // scratch: the polygon being swept, counter-clockwise
    std::vector<mesh::VertexHandle> moved;  // vertices moved by the last call
    std::vector<double> full_lift;          // lifts before keep_off (once it is called)
    std::unordered_map<int, std::uint32_t> band_of;  // vertex index -> band index (keep_off)
    SeparationStats stats;

    mesh::TriMesh& mesh() { return ctx->mesh(); }
    std::uint32_t cell_of(const Vec2& p) const noexcept;
    void collect_band(const CrossSection& cut);
    void add_side(const CrossSectionSide& side, const CrossSection& cut, double sign,
                  std::unordered_set<int>& seen);
    void build_grid();
    void apply(std::uint32_t index, double m);
    void begin_sweep();
    void end_sweep();
    void retire(std::uint32_t index);
    void index_band();
    void keep_full_lifts();
    void spread(std::vector<std::pair<double, std::uint32_t>>& heap);
    void hold_earlier_caps(const CrossSection& cut);
};

std::uint32_t Separator::State::cell_of(const Vec2& p) const noexcept {
    const auto cx = static_cast<std::uint32_t>(
        std::clamp((p[0] - grid_origin[0]) / cell, 0.0, static_cast<double>(nx - 1)));
    const auto cy = static_cast<std::uint32_t>(
        std::clamp((p[1] - grid_origin[1]) / cell, 0.0, static_cast<double>(ny - 1)));
    return cy * nx + cx;
}

/// Breadth-first from one side's rim over vertices on that side nearer the plane than D.
void Separator::State::add_side(const CrossSectionSide& side, const CrossSection& cut, double sign,
                                std::unordered_set<int>& seen) {
    const mesh::TriMesh& m = mesh();
    const double tol = ctx->tolerance_m();
    const std::size_t first = band.size();
    auto push = [&](mesh::VertexHandle v, const Vec2& xy, bool rim) {
        const double d = std::max(0.0, sign * plane.signed_distance(m.point(v)));
        BandVertex b;
        b.v = v;
        b.origin = m.point(v);
        b.xy = xy;
        b.lift = sign * 0.5 * kerf * (1.0 - std::min(d, depth) / depth);
        b.base = plane.signed_distance(b.origin);
        b.rim = rim;
        band.push_back(b);
    };
    for (std::size_t i = 0; i < side.loops.size(); ++i) {
        for (std::size_t j = 0; j < side.loops[i].size(); ++j) {
            const auto v = side.loops[i][j];
            if (!v.is_valid() || !seen.insert(v.idx()).second) continue;
            const bool have_2d = i < cut.loops_2d.size() && j < cut.loops_2d[i].size();
            push(v, have_2d ? cut.loops_2d[i][j] : plane.to_2d(m.point(v)), true);
        }
    }
    for (std::size_t head = first; head < band.size(); ++head) {
        const auto v = band[head].v;
        for (const auto w : m.vv_range(v)) {
            const double d = sign * plane.signed_distance(m.point(w));
            if (d < -tol || d >= depth || seen.count(w.idx()) != 0) continue;
            seen.insert(w.idx());
            push(w, plane.to_2d(m.point(w)), false);
        }
    }
}

void Separator::State::collect_band(const CrossSection& cut) {
    std::unordered_set<int> seen;
    add_side(cut.positive, cut, +1.0, seen);
    add_side(cut.negative, cut, -1.0, seen);
    stats.band_vertices = static_cast<std::uint32_t>(band.size());
    for (const auto& loop : cut.positive.loops) {
        stats.rim_pairs += static_cast<std::uint32_t>(loop.size());
    }
}

/// Cells about a kerf wide (the fall-off width), at most ~4 per band vertex.
void Separator::State::build_grid() {
    Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
    for (const auto& b : band) {
        lo.minimize(b.xy);
        hi.maximize(b.xy);
    }
    const Vec2 size = hi - lo;
    const double n = static_cast<double>(std::max<std::size_t>(band.size(), 1));
    cell = std::max({ramp, std::sqrt(size[0] * size[1] / (4.0 * n)), 1e-12});
    grid_origin = lo;
    nx = static_cast<std::uint32_t>(std::clamp(size[0] / cell + 1.0, 1.0, 4096.0));
    ny = static_cast<std::uint32_t>(std::clamp(size[1] / cell + 1.0, 1.0, 4096.0));
    start.assign(std::size_t{nx} * ny + 1, 0);
    live.assign(std::size_t{nx} * ny, 0);
    for (const auto& b : band) ++start[cell_of(b.xy) + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    items.assign(band.size(), 0);
    for (std::uint32_t i = 0; i < band.size(); ++i) {
        const std::uint32_t c = cell_of(band[i].xy);
        band[i].slot = start[c] + live[c]++;
        items[band[i].slot] = i;
    }
}

void Separator::State::apply(std::uint32_t index, double m) {
    BandVertex& b = band[index];
    b.m = m;
    mesh::TriMesh& mm = mesh();
    mm.set_point(b.v, b.origin + plane.normal() * (b.lift * m));
    if (b.stamp != sweep_stamp) {
        b.stamp = sweep_stamp;
        moved.push_back(b.v);
    }
    if (b.rim && clearances.raises_cap(index)) rims_moved.push_back(index);
}

void Separator::State::begin_sweep() {
    moved.clear();
    rims_moved.clear();
    ++sweep_stamp;
}

/// Walls over the cap triangles this sweep raised keep clear of them. A worklist: clearing a
/// wall can raise its rim points and so other cap triangles. Weights only grow and stop at 1
/// (everything at 1 is the fully open kerf, which clears every cap), so this ends; the bound only
/// cuts off a slow approach.
void Separator::State::end_sweep() {
    const std::size_t limit = rims_moved.size() + 8 * band.size();
    for (std::size_t i = 0; i < rims_moved.size() && i < limit; ++i) {
        clearances.clear(rims_moved[i], band,
                         [this](std::uint32_t index, double m) { apply(index, m); });
    }
    rims_moved.clear();
    stats.moved_last_sweep = static_cast<std::uint32_t>(moved.size());
}

/// Removes a fully swept vertex from its cell (swap with the cell's last live item).
void Separator::State::retire(std::uint32_t index) {
    BandVertex& b = band[index];
    const std::uint32_t c = cell_of(b.xy);
    const std::uint32_t last_slot = start[c] + --live[c];
    const std::uint32_t other = items[last_slot];
    items[b.slot] = other;
    band[other].slot = b.slot;
    items[last_slot] = index;
    b.slot = kNoCell;
    if (b.rim && b.lift > 0) ++stats.rim_pairs_swept;
}

Result<Separator, CutStatus> Separator::make(CutContext& ctx, const CrossSection& cut,
                                             double kerf_width_m) {
    if (!std::isfinite(kerf_width_m) || kerf_width_m <= 0.0 || cut.positive.loops.empty() ||
        cut.positive.loops.size() != cut.negative.loops.size()) {
        return Err{CutStatus::kInvalidArgument};
    }
    auto s = std::make_unique<State>();
    s->ctx = &ctx;
    s->plane = cut.plane;
    s->kerf = kerf_width_m;
    s->depth = kBandDepthKerfs * kerf_width_m;
    s->ramp = kerf_width_m;
    s->collect_band(cut);
    s->build_grid();
    s->hold_earlier_caps(cut);
    s->clearances.build(ctx.mesh(), cut, s->band, kerf_width_m);
    s->moved.reserve(s->band.size());  // sweeps never allocate
    ctx.note_vertices_moved(0.5 * kerf_width_m);
    return Separator(std::move(s));
}

void Separator::keep_off(const Plane& other, const Vec3& lo, const Vec3& hi) {
    State& s = *s_;
    const double tol = s.ctx->tolerance_m();
    const double slope = s.plane.normal() | other.normal();  // d(distance to other) / d(lift)
    s.keep_full_lifts();
    std::vector<std::pair<double, std::uint32_t>> heap;  // (scale, band index), smallest first
    for (std::uint32_t i = 0; i < s.band.size(); ++i) {
        BandVertex& b = s.band[i];
        const Vec3& p = b.origin;
        if (p[0] < lo[0] || p[1] < lo[1] || p[2] < lo[2] || p[0] > hi[0] || p[1] > hi[1] ||
            p[2] > hi[2])
            continue;
        const double w = other.signed_distance(p);
        const double change = b.lift * slope;                // at full lift
        if (std::abs(w) > tol && change * w >= 0) continue;  // moves away from it, or along it
        const double allowed = std::max(0.0, std::abs(w) - 2.0 * tol);
        if (std::abs(change) > allowed) {
            b.lift *= allowed / std::abs(change);
            heap.emplace_back(s.full_lift[i] != 0 ? b.lift / s.full_lift[i] : 0.0, i);
        }
    }
    s.spread(heap);
}

/// band_of, once.
void Separator::State::index_band() {
    if (!band_of.empty()) return;
    band_of.reserve(band.size());
    for (std::uint32_t i = 0; i < band.size(); ++i) band_of.emplace(band[i].v.idx(), i);
}

/// full_lift, once: the lifts before anything held a vertex back.
void Separator::State::keep_full_lifts() {
    if (!full_lift.empty()) return;
    full_lift.reserve(band.size());
    for (const BandVertex& b : band) full_lift.push_back(b.lift);
}

/// A vertex held back holds its neighbours back too, less with distance: the lift's share then
/// changes across a face by its length over the ramp, not from 0 to 1, so faces near the held
/// vertices do not fold where one corner stays and the next moves. `heap`: (share, band index)
/// of the vertices held back.
void Separator::State::spread(std::vector<std::pair<double, std::uint32_t>>& heap) {
    if (heap.empty()) return;
    index_band();
    const double reach = kKeepOffRampKerfs * kerf;
    const mesh::TriMesh& m = mesh();
    const auto later = [](const auto& x, const auto& y) { return x.first > y.first; };
    std::make_heap(heap.begin(), heap.end(), later);
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        const auto [scale, i] = heap.back();
        heap.pop_back();
        const BandVertex& b = band[i];
        if (full_lift[i] != 0 && b.lift / full_lift[i] < scale - 1e-12) continue;  // stale
        for (const auto v : m.vv_range(b.v)) {
            const auto it = band_of.find(v.idx());
            if (it == band_of.end()) continue;
            BandVertex& n = band[it->second];
            const double full = full_lift[it->second];
            if (full == 0) continue;
            const double to = scale + (n.origin - b.origin).norm() / reach;
            if (to >= 1.0 || to >= n.lift / full) continue;
            n.lift = full * to;
            heap.emplace_back(to, it->second);
            std::push_heap(heap.begin(), heap.end(), later);
        }
    }
}

/// Earlier caps are rim-only, so their triangles are long: one that reaches past the band's edge
/// (distance D, where the lift's slope changes) is interpolated across that crease while a wall a
/// few um above it follows the lift, and they cross. Its corners in the band (off this cut's rim)
/// are held still, and their neighbours ramp up from them (spread).
void Separator::State::hold_earlier_caps(const CrossSection& cut) {
    OpenMesh::FPropHandleT<std::uint8_t> cap;
    mesh::TriMesh& m = mesh();
    if (!m.get_property_handle(cap, kCapFaceProperty)) return;
    std::unordered_set<int> own;
    for (const auto* side : {&cut.positive, &cut.negative})
        for (const auto f : side->cap_faces) own.insert(f.idx());
    index_band();
    std::vector<std::pair<double, std::uint32_t>> heap;
    for (std::uint32_t i = 0; i < band.size(); ++i) {
        if (band[i].rim) continue;
        for (const auto f : m.vf_range(band[i].v)) {
            if (m.property(cap, f) == kCapNone || own.count(f.idx()) != 0) continue;
            bool outside = false;
            for (const auto w : m.fv_range(f)) outside |= band_of.count(w.idx()) == 0;
            if (!outside) continue;
            keep_full_lifts();
            band[i].lift = 0.0;
            heap.emplace_back(0.0, i);
            break;
        }
    }
    spread(heap);
}

Separator::Separator(std::unique_ptr<State> s) noexcept : s_(std::move(s)) {}
Separator::Separator(Separator&&) noexcept = default;
Separator& Separator::operator=(Separator&&) noexcept = default;
Separator::~Separator() = default;

const SeparationStats& Separator::stats() const noexcept { return s_->stats; }

std::span<const mesh::VertexHandle> Separator::moved_vertices() const noexcept { return s_->moved; }

bool Separator::sweep(std::span<const Vec2> polygon) {
    State& s = *s_;
    s.begin_sweep();
    s.stats.moved_last_sweep = 0;
    if (polygon.size() < 3) return false;
    s.poly.assign(polygon.begin(), polygon.end());
    double twice_area = 0.0;
    Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
    for (std::size_t i = 0; i < s.poly.size(); ++i) {
        const Vec2& a = s.poly[i];
        const Vec2& b = s.poly[(i + 1) % s.poly.size()];
        if (!std::isfinite(a[0]) || !std::isfinite(a[1])) return false;
        twice_area += a[0] * b[1] - a[1] * b[0];
        lo.minimize(a);
        hi.maximize(a);
    }
    if (!(std::abs(twice_area) > 0.0)) return false;
    if (twice_area < 0) std::reverse(s.poly.begin(), s.poly.end());
    const Vec2 pad(s.ramp, s.ramp);
    const std::uint32_t c0 = s.cell_of(lo - pad);
    const std::uint32_t c1 = s.cell_of(hi + pad);
    for (std::uint32_t cy = c0 / s.nx; cy <= c1 / s.nx; ++cy) {
        for (std::uint32_t cx = c0 % s.nx; cx <= c1 % s.nx; ++cx) {
            const std::uint32_t c = cy * s.nx + cx;
            for (std::uint32_t k = s.start[c]; k < s.start[c] + s.live[c];) {
                const std::uint32_t i = s.items[k];
                BandVertex& b = s.band[i];
                const double d = distance_to_convex(b.xy, s.poly);
                b.swept = std::max(b.swept, std::clamp(1.0 - d / s.ramp, 0.0, 1.0));
                if (b.swept > b.m) s.apply(i, b.swept);
                if (b.m >= 1.0) {
                    s.retire(i);  // swaps another live item into slot k: test k again
                    continue;
                }
                ++k;
            }
        }
    }
    s.end_sweep();
    return true;
}

void Separator::sweep_all() {
    State& s = *s_;
    s.begin_sweep();
    for (std::uint32_t i = 0; i < s.band.size(); ++i) {
        BandVertex& b = s.band[i];
        if (b.slot == kNoCell) continue;
        b.swept = 1.0;
        if (b.m < 1.0) s.apply(i, 1.0);
        s.retire(i);
    }
    s.rims_moved.clear();  // everything at full lift: the caps are flat again
    s.stats.moved_last_sweep = static_cast<std::uint32_t>(s.moved.size());
}

}  // namespace kerf::cut
