#include "display/cut/cap_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace kerf::cut::detail {
namespace {

constexpr std::uint32_t kGrid = 16;  // the walls' grid: at most kGrid x kGrid cells

double cross2(const Vec2& x, const Vec2& y) { return x[0] * y[1] - x[1] * y[0]; }

/// Barycentric coordinates of q in the counter-clockwise triangle t, clamped to it.
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

/// Orients a triangle counter-clockwise (swapping corners 1 and 2 with its other arrays);
/// false when it is degenerate seen from the plane.
template <class... Arrays>
bool counter_clockwise(Vec2 (&p)[3], Arrays&... arrays) {
    const double area = cross2(p[1] - p[0], p[2] - p[0]);
    if (!(std::abs(area) > 0)) return false;
    if (area < 0) {
        std::swap(p[1], p[2]);
        (std::swap(arrays[1], arrays[2]), ...);
    }
    return true;
}

void box_of(const Vec2 (&p)[3], Vec2& lo, Vec2& hi) {
    lo = hi = p[0];
    for (const Vec2& q : p) {
        lo.minimize(q);
        hi.maximize(q);
    }
}

}  // namespace

std::uint32_t CapClearances::cell_coord(double x, double origin) const noexcept {
    return static_cast<std::uint32_t>(std::clamp((x - origin) / step_, 0.0, cells_ - 1.0));
}

void CapClearances::build(const mesh::TriMesh& m, const CrossSection& cut,
                          std::span<const BandVertex> band, double kerf) {
    kerf_ = kerf;
    std::unordered_map<int, std::uint32_t> band_of;
    band_of.reserve(band.size());
    for (std::uint32_t i = 0; i < band.size(); ++i) band_of.emplace(band[i].v.idx(), i);
    std::unordered_set<int> cap_faces;
    for (const auto* side : {&cut.positive, &cut.negative}) {
        const double sign = side == &cut.positive ? 1.0 : -1.0;
        for (const auto f : side->cap_faces) {
            cap_faces.insert(f.idx());
            Triangle t{};
            t.sign = sign;
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
            if (k != 3 || !counter_clockwise(t.p, t.corner)) continue;
            box_of(t.p, t.lo, t.hi);
            triangles_.push_back(t);
        }
    }
    rim_start_.assign(band.size() + 1, 0);
    for (const auto& t : triangles_)
        for (const std::uint32_t c : t.corner) ++rim_start_[c + 1];
    for (std::size_t i = 1; i < rim_start_.size(); ++i) rim_start_[i] += rim_start_[i - 1];
    rim_triangles_.assign(rim_start_.back(), 0);
    {
        std::vector<std::uint32_t> fill(rim_start_.begin(), rim_start_.end() - 1);
        for (std::uint32_t i = 0; i < triangles_.size(); ++i)
            for (const std::uint32_t c : triangles_[i].corner) rim_triangles_[fill[c]++] = i;
    }
    if (triangles_.empty()) return;

    // The walls: faces round the band's vertices off the rim, on their side within a kerf of
    // the plane somewhere (a cap rises at most kerf/2 and a wall only rises, so a face a kerf
    // above the plane keeps half its gap whatever happens).
    std::unordered_set<int> seen;
    for (const BandVertex& b : band) {
        if (b.rim) continue;
        const double sign = b.lift > 0 ? 1.0 : -1.0;
        for (const auto f : m.vf_range(b.v)) {
            if (cap_faces.count(f.idx()) != 0 || !seen.insert(f.idx()).second) continue;
            Wall w{};
            w.sign = sign;
            int k = 0;
            for (const auto v : m.fv_range(f)) {
                if (k == 3) break;
                const auto it = band_of.find(v.idx());
                w.corner[k] = it == band_of.end() ? kNotInBand : it->second;
                const Vec3 at = w.corner[k] == kNotInBand ? m.point(v) : band[w.corner[k]].origin;
                w.p[k] = w.corner[k] == kNotInBand ? cut.plane.to_2d(at) : band[w.corner[k]].xy;
                w.height[k] = sign * cut.plane.signed_distance(at);
                ++k;
            }
            if (k != 3 || std::min({w.height[0], w.height[1], w.height[2]}) >= kerf) continue;
            if (!counter_clockwise(w.p, w.corner, w.height)) continue;  // edge-on: over no cap
            box_of(w.p, w.lo, w.hi);
            walls_.push_back(w);
        }
    }
    if (walls_.empty()) return;
    Vec2 top = walls_[0].hi;
    origin_ = walls_[0].lo;
    for (const Wall& w : walls_) {
        origin_.minimize(w.lo);
        top.maximize(w.hi);
    }
    const double size = std::max({top[0] - origin_[0], top[1] - origin_[1], 1e-12});
    step_ = std::max(kerf, size / kGrid);
    cells_ = static_cast<std::uint32_t>(std::min<double>(kGrid, size / step_ + 1.0));
    cell_start_.assign(std::size_t{cells_} * cells_ + 1, 0);
    const auto for_cells = [this](const Vec2& lo, const Vec2& hi, auto&& fn) {
        for (std::uint32_t cy = cell_coord(lo[1], origin_[1]); cy <= cell_coord(hi[1], origin_[1]);
             ++cy)
            for (std::uint32_t cx = cell_coord(lo[0], origin_[0]);
                 cx <= cell_coord(hi[0], origin_[0]); ++cx)
                fn(cy * cells_ + cx);
    };
    for (const Wall& w : walls_)
        for_cells(w.lo, w.hi, [&](std::uint32_t c) { ++cell_start_[c + 1]; });
    for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
    cell_walls_.assign(cell_start_.back(), 0);
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::uint32_t i = 0; i < walls_.size(); ++i)
        for_cells(walls_[i].lo, walls_[i].hi, [&](std::uint32_t c) { cell_walls_[fill[c]++] = i; });
    wall_seen_.assign(walls_.size(), 0);
}

/// The clearances of cap triangle t: the corners of the overlay of each wall face of its side
/// with it where the wall is above the cap by less than a kerf.
void CapClearances::find(Triangle& t, std::span<const BandVertex> band) {
    t.found = true;
    t.first = static_cast<std::uint32_t>(clearances_.size());
    if (walls_.empty()) return;
    const auto id = static_cast<std::uint32_t>(&t - triangles_.data()) + 1;
    for (std::uint32_t cy = cell_coord(t.lo[1], origin_[1]); cy <= cell_coord(t.hi[1], origin_[1]);
         ++cy) {
        for (std::uint32_t cx = cell_coord(t.lo[0], origin_[0]);
             cx <= cell_coord(t.hi[0], origin_[0]); ++cx) {
            const std::uint32_t c = cy * cells_ + cx;
            for (std::uint32_t s = cell_start_[c]; s < cell_start_[c + 1]; ++s) {
                const std::uint32_t wi = cell_walls_[s];
                if (wall_seen_[wi] == id) continue;
                wall_seen_[wi] = id;
                const Wall& w = walls_[wi];
                if (w.sign != t.sign || w.lo[0] > t.hi[0] || w.hi[0] < t.lo[0] ||
                    w.lo[1] > t.hi[1] || w.hi[1] < t.lo[1] || separated(w.p, t.p))
                    continue;
                clip_.assign(w.p, w.p + 3);
                clip_to_triangle(clip_, t.p, scratch_);
                for (const Vec2& p : clip_) {
                    Clearance at{};
                    at.sign = t.sign;
                    std::copy(t.corner, t.corner + 3, at.cap);
                    std::copy(w.corner, w.corner + 3, at.wall);
                    barycentric(t.p, p, at.a);
                    barycentric(w.p, p, at.b);
                    double wall = 0.0, below = 0.0;
                    for (int q = 0; q < 3; ++q) {
                        wall += at.b[q] * w.height[q];
                        if (at.wall[q] == kNotInBand) at.fixed += at.b[q] * w.height[q];
                        below += at.a[q] * t.sign * band[at.cap[q]].base;
                    }
                    // At plan time: touching (a rim edge), not above, or too far above to be
                    // reached.
                    if (!(wall > below) || wall - below >= kerf_) continue;
                    at.min_gap = 0.5 * (wall - below);
                    clearances_.push_back(at);
                }
            }
        }
    }
    t.count = static_cast<std::uint32_t>(clearances_.size()) - t.first;
}

}  // namespace kerf::cut::detail
