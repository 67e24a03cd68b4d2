#include "display/cut/separate.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace kerf::cut {
namespace {

constexpr std::uint32_t kNoCell = 0xFFFFFFFFu;

constexpr std::uint32_t kNotInBand = 0xFFFFFFFFu;

struct BandVertex {
    mesh::VertexHandle v;
    Vec3 origin;         // position at plan time, m
    Vec2 xy;             // (u, v) position, m
    double lift = 0.0;   // signed move at m = 1: side * kerf/2 * (1 - depth / D), m
    double base = 0.0;   // signed distance from the plane at plan time, m
    double m = 0.0;      // weight applied so far, 0..1: at least `swept`, more to clear the cap
    double swept = 0.0;  // m(x) of the swept region so far, 0..1
    bool rim = false;
    std::uint32_t slot = 0;   // index in the grid's item array while still live
    std::uint32_t stamp = 0;  // the sweep that last moved it
};

/// A point p of the plane where a face of a cut side (a wall) lies over that side's cap: the
/// wall must stay on its side of the cap there. Heights are along the side's direction
/// (sign * normal), from the corners' band entries (kNotInBand: a vertex that never moves, its
/// height folded into `fixed`).
struct CapClearance {
    std::uint32_t cap[3];   // the cap triangle's corners (rim band vertices)
    double a[3];            // p's barycentric coordinates in it
    std::uint32_t wall[3];  // the wall face's corners (band vertices or kNotInBand)
    double b[3];            // p's barycentric coordinates in the wall face
    double fixed = 0.0;     // height of the wall's unmoving corners at p, m
    double min_gap = 0.0;   // the wall stays at least this far above the cap at p, m
    double sign = 1.0;      // the side: +1 positive, -1 negative
};

double cross2(const Vec2& x, const Vec2& y) { return x[0] * y[1] - x[1] * y[0]; }

/// Barycentric coordinates of q in the triangle t (plane coordinates), clamped to the triangle.
void barycentric(const Vec2 (&t)[3], const Vec2& q, double (&w)[3]) {
    const double area = cross2(t[1] - t[0], t[2] - t[0]);
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        w[k] = std::max(0.0, cross2(t[(k + 1) % 3] - q, t[(k + 2) % 3] - q) / area);
        sum += w[k];
    }
    for (double& x : w) x /= sum;
}

/// Whether an edge of one counter-clockwise triangle has the whole other one outside it.
bool separated(const Vec2 (&s)[3], const Vec2 (&t)[3]) {
    for (int pass = 0; pass < 2; ++pass) {
        const Vec2(&x)[3] = pass == 0 ? s : t;
        const Vec2(&y)[3] = pass == 0 ? t : s;
        for (int e = 0; e < 3; ++e) {
            const Vec2 edge = x[(e + 1) % 3] - x[e];
            if (cross2(edge, y[0] - x[e]) <= 0 && cross2(edge, y[1] - x[e]) <= 0 &&
                cross2(edge, y[2] - x[e]) <= 0)
                return true;
        }
    }
    return false;
}

/// The part of the convex polygon `poly` inside the counter-clockwise triangle t.
void clip_to_triangle(std::vector<Vec2>& poly, const Vec2 (&t)[3], std::vector<Vec2>& scratch) {
    for (int e = 0; e < 3 && !poly.empty(); ++e) {
        const Vec2& a = t[e];
        const Vec2 ab = t[(e + 1) % 3] - a;
        scratch.clear();
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const Vec2& p = poly[i];
            const Vec2& q = poly[(i + 1) % poly.size()];
            const double sp = cross2(ab, p - a), sq = cross2(ab, q - a);
            if (sp >= 0) scratch.push_back(p);
            if ((sp >= 0) != (sq >= 0)) scratch.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        poly.swap(scratch);
    }
}

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
    // Caps are built on rim points only, so where part of the rim is swept a cap rises as
    // wedges: over a point it is where its triangle's corners' weights interpolate to, which can
    // be far above m there (a triangle from a swept rim point across the section), and a wall
    // that leans over the cap close to the plane (a vertex 9 um above it) would be left below
    // it. So the vertices of such walls rise with the cap: at every corner of the overlay of a
    // wall face's projection with the cap triangles (the wall is linear over its face, the cap
    // over each of its triangles, so these points decide) the wall keeps half its gap.
    std::vector<CapClearance> clearances;
    std::vector<std::uint32_t> clearance_start;  // per band vertex: [start[i], start[i + 1])
    std::vector<std::uint32_t> clearance_of;     // clearances whose cap has that corner
    std::vector<std::uint32_t> rims_moved;       // scratch: rim band vertices the sweep moved
    std::uint32_t sweep_stamp = 0;
    std::vector<Vec2> poly;                 // scratch: the polygon being swept, counter-clockwise
    std::vector<mesh::VertexHandle> moved;  // vertices moved by the last call
    SeparationStats stats;

    mesh::TriMesh& mesh() { return ctx->mesh(); }
    std::uint32_t cell_of(const Vec2& p) const noexcept;
    void collect_band(const CrossSection& cut);
    void add_side(const CrossSectionSide& side, const CrossSection& cut, double sign,
                  std::unordered_set<int>& seen);
    void build_grid();
    void find_clearances(const CrossSection& cut);
    void add_clearances(const CrossSectionSide& side, double sign,
                        const std::unordered_map<int, std::uint32_t>& band_of);
    double height(std::uint32_t index, double sign) const noexcept;
    void clear_cap(const CapClearance& c);
    void apply(std::uint32_t index, double m);
    void begin_sweep();
    void end_sweep();
    void retire(std::uint32_t index);
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

void Separator::State::find_clearances(const CrossSection& cut) {
    std::unordered_map<int, std::uint32_t> band_of;
    for (std::uint32_t i = 0; i < band.size(); ++i) band_of.emplace(band[i].v.idx(), i);
    add_clearances(cut.positive, +1.0, band_of);
    add_clearances(cut.negative, -1.0, band_of);
    clearance_start.assign(band.size() + 1, 0);
    for (const auto& c : clearances)
        for (const std::uint32_t k : c.cap) ++clearance_start[k + 1];
    for (std::size_t i = 1; i < clearance_start.size(); ++i)
        clearance_start[i] += clearance_start[i - 1];
    clearance_of.assign(clearance_start.back(), 0);
    std::vector<std::uint32_t> fill(clearance_start.begin(), clearance_start.end() - 1);
    for (std::uint32_t i = 0; i < clearances.size(); ++i)
        for (const std::uint32_t k : clearances[i].cap) clearance_of[fill[k]++] = i;
}

/// The clearances of one side: every face with a corner in the band that is not on the rim (the
/// walls; earlier cuts' caps included) against the cap triangles under its projection.
void Separator::State::add_clearances(const CrossSectionSide& side, double sign,
                                      const std::unordered_map<int, std::uint32_t>& band_of) {
    const mesh::TriMesh& m = mesh();
    struct CapTriangle {
        std::uint32_t corner[3];
        Vec2 p[3];  // counter-clockwise
        Vec2 lo, hi;
    };
    std::vector<CapTriangle> caps;
    std::unordered_set<int> cap_faces;
    for (const auto f : side.cap_faces) {
        cap_faces.insert(f.idx());
        CapTriangle t{};
        int k = 0;
        for (const auto v : m.fv_range(f)) {
            const auto it = band_of.find(v.idx());
            if (k == 3 || it == band_of.end()) {
                k = -1;
                break;
            }
            t.corner[k] = it->second;
            t.p[k] = band[it->second].xy;
            ++k;
        }
        if (k != 3) continue;
        const double area = cross2(t.p[1] - t.p[0], t.p[2] - t.p[0]);
        if (!(std::abs(area) > 0)) continue;
        if (area < 0) {
            std::swap(t.p[1], t.p[2]);
            std::swap(t.corner[1], t.corner[2]);
        }
        t.lo = t.hi = t.p[0];
        for (const Vec2& p : t.p) {
            t.lo.minimize(p);
            t.hi.maximize(p);
        }
        caps.push_back(t);
    }
    if (caps.empty()) return;
    // The cap triangles in a coarse grid of at most kCapGrid x kCapGrid cells (a cap triangle
    // can cross the whole section) over the caps' box: each in every cell it meets.
    constexpr std::uint32_t kCapGrid = 16;
    Vec2 origin = caps[0].lo, top = caps[0].hi;
    for (const auto& t : caps) {
        origin.minimize(t.lo);
        top.maximize(t.hi);
    }
    const double size = std::max({top[0] - origin[0], top[1] - origin[1], 1e-12});
    const double step = std::max(cell, size / kCapGrid);
    const auto cells = static_cast<std::uint32_t>(std::min<double>(kCapGrid, size / step + 1.0));
    const auto coord = [&](double x, double o) {
        return static_cast<std::uint32_t>(std::clamp((x - o) / step, 0.0, cells - 1.0));
    };
    const auto for_cells = [&](const Vec2& lo, const Vec2& hi, auto&& fn) {
        for (std::uint32_t cy = coord(lo[1], origin[1]); cy <= coord(hi[1], origin[1]); ++cy)
            for (std::uint32_t cx = coord(lo[0], origin[0]); cx <= coord(hi[0], origin[0]); ++cx)
                fn(cy * cells + cx);
    };
    const auto meets = [&](const CapTriangle& t, std::uint32_t c) {
        const Vec2 lo = origin + Vec2((c % cells) * step, (c / cells) * step);
        const Vec2 corners[4] = {lo, lo + Vec2(step, 0), lo + Vec2(step, step), lo + Vec2(0, step)};
        for (int e = 0; e < 3; ++e) {
            const Vec2 edge = t.p[(e + 1) % 3] - t.p[e];
            bool outside = true;
            for (const Vec2& q : corners) outside = outside && cross2(edge, q - t.p[e]) < 0;
            if (outside) return false;
        }
        return true;
    };
    std::vector<std::uint32_t> cap_start(std::size_t{cells} * cells + 1, 0), cap_items;
    for (const auto& t : caps)
        for_cells(t.lo, t.hi, [&](std::uint32_t c) { cap_start[c + 1] += meets(t, c) ? 1 : 0; });
    for (std::size_t c = 1; c < cap_start.size(); ++c) cap_start[c] += cap_start[c - 1];
    cap_items.assign(cap_start.back(), 0);
    {
        std::vector<std::uint32_t> fill(cap_start.begin(), cap_start.end() - 1);
        for (std::uint32_t i = 0; i < caps.size(); ++i)
            for_cells(caps[i].lo, caps[i].hi, [&](std::uint32_t c) {
                if (meets(caps[i], c)) cap_items[fill[c]++] = i;
            });
    }
    std::vector<std::uint32_t> seen_cap(caps.size(), kNotInBand);
    std::unordered_set<int> walls;
    std::vector<Vec2> clip, scratch;
    for (std::uint32_t i = 0; i < band.size(); ++i) {
        if (band[i].rim || band[i].lift * sign <= 0) continue;
        for (const auto f : m.vf_range(band[i].v)) {
            if (cap_faces.count(f.idx()) != 0 || !walls.insert(f.idx()).second) continue;
            CapClearance c{};
            c.sign = sign;
            Vec2 w[3];
            int k = 0;
            for (const auto v : m.fv_range(f)) {
                if (k == 3) break;
                const auto it = band_of.find(v.idx());
                c.wall[k] = it == band_of.end() ? kNotInBand : it->second;
                w[k] = c.wall[k] == kNotInBand ? plane.to_2d(m.point(v)) : band[c.wall[k]].xy;
                ++k;
            }
            if (k != 3) continue;
            const double area = cross2(w[1] - w[0], w[2] - w[0]);
            if (!(std::abs(area) > 0)) continue;  // seen edge-on: no cap below it
            if (area < 0) {
                std::swap(w[1], w[2]);
                std::swap(c.wall[1], c.wall[2]);
            }
            double fixed_height[3];
            const auto corners = m.fv_range(f);
            int j = 0;
            for (const auto v : corners) {
                if (j == 3) break;
                fixed_height[j++] = sign * plane.signed_distance(m.point(v));
            }
            if (area < 0) std::swap(fixed_height[1], fixed_height[2]);
            // A cap rises at most kerf/2 and the wall only rises: a face a kerf above the plane
            // keeps half its gap whatever happens.
            if (std::min({fixed_height[0], fixed_height[1], fixed_height[2]}) >= kerf) continue;
            Vec2 lo = w[0], hi = w[0];
            for (const Vec2& p : w) {
                lo.minimize(p);
                hi.maximize(p);
            }
            for_cells(lo, hi, [&](std::uint32_t cell_index) {
                for (std::uint32_t s = cap_start[cell_index]; s < cap_start[cell_index + 1]; ++s) {
                    const std::uint32_t t = cap_items[s];
                    if (seen_cap[t] == static_cast<std::uint32_t>(f.idx())) continue;
                    seen_cap[t] = static_cast<std::uint32_t>(f.idx());
                    const CapTriangle& cap = caps[t];
                    if (cap.lo[0] > hi[0] || cap.hi[0] < lo[0] || cap.lo[1] > hi[1] ||
                        cap.hi[1] < lo[1])
                        continue;
                    if (separated(w, cap.p)) continue;
                    clip.assign(w, w + 3);
                    clip_to_triangle(clip, cap.p, scratch);
                    for (const Vec2& p : clip) {
                        CapClearance at = c;
                        std::copy(cap.corner, cap.corner + 3, at.cap);
                        barycentric(cap.p, p, at.a);
                        barycentric(w, p, at.b);
                        double wall = 0.0, below = 0.0;
                        for (int q = 0; q < 3; ++q) {
                            const double h = at.wall[q] == kNotInBand ? fixed_height[q]
                                                                      : height(at.wall[q], sign);
                            wall += at.b[q] * h;
                            if (at.wall[q] == kNotInBand) at.fixed += at.b[q] * h;
                            below += at.a[q] * height(at.cap[q], sign);
                        }
                        // Touching (a rim edge), not above, or too far above to be reached.
                        if (!(wall > below) || wall - below >= kerf) continue;
                        at.min_gap = 0.5 * (wall - below);
                        clearances.push_back(at);
                    }
                }
            });
        }
    }
}

/// Height of a band vertex along the side's direction, where it is now, m.
double Separator::State::height(std::uint32_t index, double sign) const noexcept {
    const BandVertex& b = band[index];
    return sign * (b.base + b.lift * b.m);
}

/// Raises the wall face's corners (band vertices of the side that rise with it: rim points of
/// the wall too, where that raises the wall more than the cap) until the wall is min_gap above
/// the cap at the clearance's point, or they are fully lifted. A rim point raised raises its cap
/// triangles: end_sweep() checks their clearances in turn.
void Separator::State::clear_cap(const CapClearance& c) {
    double wall = c.fixed, below = 0.0;
    for (int q = 0; q < 3; ++q) {
        below += c.a[q] * height(c.cap[q], c.sign);
        if (c.wall[q] != kNotInBand) wall += c.b[q] * height(c.wall[q], c.sign);
    }
    const double deficit = c.min_gap - (wall - below);
    if (!(deficit > 1e-9 * kerf)) return;
    // How much the gap grows per unit of weight of each wall corner.
    double rate[3] = {0, 0, 0}, total = 0.0;
    for (int q = 0; q < 3; ++q) {
        if (c.wall[q] == kNotInBand) continue;
        const BandVertex& b = band[c.wall[q]];
        if (b.m >= 1.0 || b.lift * c.sign <= 0) continue;
        double r = c.b[q];
        for (int k = 0; k < 3; ++k)
            if (c.cap[k] == c.wall[q]) r -= c.a[k];
        rate[q] = std::max(0.0, r) * std::abs(b.lift);
        total += rate[q];
    }
    if (!(total > 0)) return;
    const double raise = deficit / total;
    for (int q = 0; q < 3; ++q) {
        if (rate[q] > 0) apply(c.wall[q], std::min(1.0, band[c.wall[q]].m + raise));
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
    if (b.rim && clearance_start[index] != clearance_start[index + 1]) rims_moved.push_back(index);
}

void Separator::State::begin_sweep() {
    moved.clear();
    rims_moved.clear();
    ++sweep_stamp;
}

/// Walls over the cap triangles this sweep raised keep clear of them.
void Separator::State::end_sweep() {
    // A worklist: clearing one wall can raise rim points and so other cap triangles. Weights
    // only grow and stop at 1 (everything at 1 is the fully open kerf, which clears every cap),
    // so this ends; the bound only cuts off a slow approach.
    const std::size_t limit = 8 * (clearances.size() + 1);
    std::size_t checked = 0;
    for (std::size_t i = 0; i < rims_moved.size() && checked < limit; ++i) {
        const std::uint32_t r = rims_moved[i];
        for (std::uint32_t k = clearance_start[r]; k < clearance_start[r + 1]; ++k, ++checked)
            clear_cap(clearances[clearance_of[k]]);
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
    s->find_clearances(cut);
    s->moved.reserve(s->band.size());  // sweeps never allocate
    ctx.note_vertices_moved(0.5 * kerf_width_m);
    return Separator(std::move(s));
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
