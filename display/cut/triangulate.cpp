// Ear clipping with holes. The ring bookkeeping follows the well-tried layout of mapbox/earcut
// (circular doubly linked nodes, holes bridged left to right, a grid of reflex vertices for the ear
// test), in double precision and with two Kerf rules: no input point is ever dropped (a cap must
// use every loop edge exactly once) and input is validated first, so the clipper only meets simple
// regions.
#include "display/cut/triangulate.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "display/cut/vec_ops.hpp"

namespace kerf::cut {

std::string_view to_string(TriangulateErrc f) noexcept {
    switch (f) {
        case TriangulateErrc::kNoLoops:
            return "no_loops";
        case TriangulateErrc::kTooFewPoints:
            return "too_few_points";
        case TriangulateErrc::kNonFinite:
            return "non_finite";
        case TriangulateErrc::kZeroArea:
            return "zero_area";
        case TriangulateErrc::kSelfIntersecting:
            return "self_intersecting";
        case TriangulateErrc::kTooManyPoints:
            return "too_many_points";
    }
    return "unknown";
}

TriangulateError triangulate_error(TriangulateErrc code, std::int32_t loop,
                                   std::int32_t other_loop) {
    TriangulateError e;
    e.code = code;
    e.loop = loop;
    e.other_loop = other_loop;
    if (loop >= 0 && other_loop >= 0 && other_loop != loop) {
        e.where = "loops " + std::to_string(loop) + " and " + std::to_string(other_loop);
    } else if (loop >= 0) {
        e.where = "loop " + std::to_string(loop);
    } else {
        e.where = "loops";
    }
    switch (code) {
        case TriangulateErrc::kNoLoops:
            e.what = "no loop given";
            break;
        case TriangulateErrc::kTooFewPoints:
            e.what = "fewer than 3 points";
            break;
        case TriangulateErrc::kNonFinite:
            e.what = "a coordinate is NaN or infinite";
            break;
        case TriangulateErrc::kZeroArea:
            e.what = "encloses (relatively) zero area";
            break;
        case TriangulateErrc::kSelfIntersecting:
            e.what = other_loop == loop ? "two of its edges cross or touch"
                                        : "an edge of one crosses or touches an edge of the other";
            break;
        case TriangulateErrc::kTooManyPoints:
            e.what = "more points than a 32-bit index can name";
            break;
    }
    return e;
}

double signed_area(std::span<const Point2> loop) noexcept {
    if (loop.size() < 3) return 0.0;
    double twice = 0.0;
    const Point2& o = loop[0];
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
        const Point2 a = loop[i] - o;
        const Point2 b = loop[i + 1] - o;
        twice += a[0] * b[1] - a[1] * b[0];
    }
    return 0.5 * twice;
}

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kGridThreshold = 64;  // rings at least this long get the reflex grid

/// Twice the signed area of (a, b, c): positive for a left turn (counter-clockwise).
inline double cross(double ax, double ay, double bx, double by, double cx, double cy) noexcept {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

struct Box {
    double x0 = std::numeric_limits<double>::infinity();
    double y0 = std::numeric_limits<double>::infinity();
    double x1 = -std::numeric_limits<double>::infinity();
    double y1 = -std::numeric_limits<double>::infinity();
    void add(const Point2& p) noexcept {
        x0 = std::min(x0, p[0]);
        y0 = std::min(y0, p[1]);
        x1 = std::max(x1, p[0]);
        y1 = std::max(y1, p[1]);
    }
    bool contains(const Box& o) const noexcept {
        return x0 <= o.x0 && y0 <= o.y0 && o.x1 <= x1 && o.y1 <= y1;
    }
};

struct Node {
    double x;
    double y;
    std::uint32_t i;  // index of the input point
    std::uint32_t prev;
    std::uint32_t next;
    bool alive;
};

/// An ear candidate; stale when its node's version moved on.
struct Candidate {
    std::uint32_t node;
    std::uint32_t version;
};
constexpr std::uint32_t kBuckets = 128;

}  // namespace

struct Triangulator::Impl {
    std::vector<Point2> pts;
    std::vector<std::uint32_t> begin;  // first point of each loop, then the end
    std::vector<Box> box;
    std::vector<double> area;  // signed area per loop
    std::vector<std::int32_t> depth;
    std::vector<std::int32_t> parent;
    std::vector<std::uint32_t> seg_next;  // successor of each point in its loop
    std::vector<std::int32_t> seg_loop;   // loop of each point
    std::vector<Box> seg_box;             // box of the segment from each point to its successor
    std::vector<std::array<std::uint32_t, 4>> seg_cells;  // its grid cells: x0, x1, y0, y1
    std::vector<std::uint32_t> cell_start;                // self-intersection grid (CSR)
    std::vector<std::uint32_t> cell_items;
    std::vector<Node> nodes;
    std::vector<std::uint32_t> holes;       // leftmost node of each hole ring
    std::vector<std::uint32_t> grid_start;  // reflex vertices by grid cell (CSR)
    std::vector<std::uint32_t> grid_items;
    std::array<std::vector<Candidate>, kBuckets> buckets;  // ear candidates by size class
    std::uint64_t nonempty = 0;          // bit k/2 set: bucket k or k+1 may hold candidates
    double key_scale = 1.0;              // 1 / region size^2
    std::vector<std::uint32_t> version;  // per node: bumped when its candidate goes stale
    bool use_grid = false;               // the current region has a reflex grid
    double gx0 = 0, gy0 = 0, ginv = 0;   // its frame: origin and cells per metre
    std::uint32_t gnx = 0, gny = 0;      // its size in cells

    std::uint32_t loops() const noexcept { return static_cast<std::uint32_t>(begin.size() - 1); }
    std::uint32_t loop_size(std::uint32_t l) const noexcept { return begin[l + 1] - begin[l]; }
    std::uint32_t next_in_loop(std::uint32_t p, std::uint32_t l) const noexcept {
        return p + 1 == begin[l + 1] ? begin[l] : p + 1;
    }

    Status<TriangulateError> load(std::span<const std::span<const Point2>> loops_in);
    Status<TriangulateError> measure();
    void build_segments();
    Status<TriangulateError> check_crossings();
    Point2 centroid(std::uint32_t l) const noexcept;
    bool star_shaped_about(std::uint32_t l, const Point2& c) const noexcept;
    bool segments_meet(std::uint32_t s, std::uint32_t t) const noexcept;
    void find_nesting();
    bool point_in_loop(const Point2& p, std::uint32_t l) const noexcept;

    bool strictly_convex(std::uint32_t l) const noexcept;
    void fan(std::uint32_t l, std::vector<Triangle>& out) const;
    bool strip(std::uint32_t l, std::uint32_t h, std::vector<Triangle>& out) const;
    std::uint32_t make_ring(std::uint32_t l, bool ccw);
    std::uint32_t add_node(std::uint32_t point);
    void unlink(std::uint32_t n) noexcept;
    double turn(std::uint32_t n) const noexcept;
    void eliminate_holes(std::uint32_t outer);
    std::uint32_t find_bridge(std::uint32_t hole, std::uint32_t outer) const noexcept;
    bool locally_inside(std::uint32_t a, std::uint32_t b) const noexcept;
    bool sector_contains_sector(std::uint32_t m, std::uint32_t p) const noexcept;
    std::uint32_t split(std::uint32_t a, std::uint32_t b);
    void build_grid(std::uint32_t start);
    std::uint32_t cell_x(double x) const noexcept;
    std::uint32_t cell_y(double y) const noexcept;
    bool blocks(std::uint32_t p, std::uint32_t ear, bool strict) const noexcept;
    bool is_ear(std::uint32_t ear, bool strict) const noexcept;
    bool is_ear_gridded(std::uint32_t ear, bool strict) const noexcept;
    void clip(std::uint32_t start, std::vector<Triangle>& out, std::uint32_t& degenerate);
    void cut_ear(std::uint32_t ear, std::vector<Triangle>& out);
    void offer(std::uint32_t n);
    bool pop(Candidate& out) noexcept;
    std::uint32_t relaxed_ear(std::uint32_t start, int pass) const noexcept;
};

// ---- input, validation, nesting --------------------------------------------------------------

Status<TriangulateError> Triangulator::Impl::load(std::span<const std::span<const Point2>> in) {
    pts.clear();
    begin.clear();
    if (in.empty()) return Err{triangulate_error(TriangulateErrc::kNoLoops)};
    std::size_t total = 0;
    for (const auto& l : in) total += l.size();
    if (total + 2 * in.size() >= kNone / 2) {
        return Err{triangulate_error(TriangulateErrc::kTooManyPoints)};
    }
    pts.reserve(total);
    for (std::size_t l = 0; l < in.size(); ++l) {
        const auto li = static_cast<std::int32_t>(l);
        if (in[l].size() < 3) return Err{triangulate_error(TriangulateErrc::kTooFewPoints, li)};
        begin.push_back(static_cast<std::uint32_t>(pts.size()));
        for (const Point2& p : in[l]) {
            if (!std::isfinite(p[0]) || !std::isfinite(p[1])) {
                return Err{triangulate_error(TriangulateErrc::kNonFinite, li)};
            }
            pts.push_back(p);
        }
    }
    begin.push_back(static_cast<std::uint32_t>(pts.size()));
    return {};
}

Status<TriangulateError> Triangulator::Impl::measure() {
    box.assign(loops(), Box{});
    area.assign(loops(), 0.0);
    for (std::uint32_t l = 0; l < loops(); ++l) {
        for (std::uint32_t p = begin[l]; p < begin[l + 1]; ++p) box[l].add(pts[p]);
        area[l] = signed_area(std::span<const Point2>(pts.data() + begin[l], loop_size(l)));
        const double dx = box[l].x1 - box[l].x0;
        const double dy = box[l].y1 - box[l].y0;
        const double noise =
            4.0 * loop_size(l) * std::numeric_limits<double>::epsilon() * (dx * dx + dy * dy);
        if (!(std::abs(area[l]) > noise)) {
            return Err{triangulate_error(TriangulateErrc::kZeroArea, static_cast<std::int32_t>(l))};
        }
    }
    return {};
}

namespace {

inline int sign(double v) noexcept { return (v > 0) - (v < 0); }

inline bool on_segment(const Point2& a, const Point2& b, const Point2& p) noexcept {
    return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
           std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]);
}

inline double cross(const Point2& a, const Point2& b, const Point2& c) noexcept {
    return cross(a[0], a[1], b[0], b[1], c[0], c[1]);
}

/// Closed segments ab and cd share at least one point.
bool closed_segments_meet(const Point2& a, const Point2& b, const Point2& c,
                          const Point2& d) noexcept {
    const int o1 = sign(cross(a, b, c));
    const int o2 = sign(cross(a, b, d));
    const int o3 = sign(cross(c, d, a));
    const int o4 = sign(cross(c, d, b));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
    return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
           (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

}  // namespace

/// Segments are named by their first point; segment s runs from s to its successor in the loop.
bool Triangulator::Impl::segments_meet(std::uint32_t s, std::uint32_t t) const noexcept {
    const std::uint32_t s1 = seg_next[s];
    const std::uint32_t t1 = seg_next[t];
    if (s1 == t || t1 == s) {
        // Neighbours share one endpoint: they meet elsewhere only when they fold back onto
        // each other (collinear, pointing the same way from the shared point).
        const std::uint32_t shared = s1 == t ? t : s;
        const std::uint32_t u = s1 == t ? s : s1;
        const std::uint32_t w = s1 == t ? t1 : t;
        const Point2 du = pts[u] - pts[shared];
        const Point2 dw = pts[w] - pts[shared];
        if ((du | du) == 0.0 || (dw | dw) == 0.0) return true;  // repeated point
        return cross(pts[shared], pts[u], pts[w]) == 0.0 && (du | dw) > 0.0;
    }
    return closed_segments_meet(pts[s], pts[s1], pts[t], pts[t1]);
}

void Triangulator::Impl::build_segments() {
    const auto n = static_cast<std::uint32_t>(pts.size());
    seg_next.resize(n);
    seg_loop.resize(n);
    seg_box.resize(n);
    for (std::uint32_t l = 0; l < loops(); ++l) {
        for (std::uint32_t p = begin[l]; p < begin[l + 1]; ++p) {
            seg_next[p] = next_in_loop(p, l);
            seg_loop[p] = static_cast<std::int32_t>(l);
            seg_box[p] = Box{};
            seg_box[p].add(pts[p]);
            seg_box[p].add(pts[seg_next[p]]);
        }
    }
}

/// Every pair of segments whose boxes share a grid cell is tested once (in the cell holding the
/// low corner of their boxes' overlap). Cells are about two mean segment lengths wide, capped at
/// 4 cells per segment, so a smooth cross-section costs O(n).
Status<TriangulateError> Triangulator::Impl::check_crossings() {
    build_segments();
    const auto n = static_cast<std::uint32_t>(pts.size());
    Box all;
    double length = 0.0;
    for (std::uint32_t s = 0; s < n; ++s) {
        all.add(pts[s]);
        length += (pts[seg_next[s]] - pts[s]).norm();
    }
    const double w = all.x1 - all.x0;
    const double h = all.y1 - all.y0;
    const double cell = std::max(2.0 * length / n, std::sqrt(w * h / (4.0 * n)));
    const auto gx = static_cast<std::uint32_t>(std::clamp(w / cell, 1.0, 4096.0));
    const auto gy = static_cast<std::uint32_t>(std::clamp(h / cell, 1.0, 4096.0));
    const double sx = gx / std::max(w, 1e-300);
    const double sy = gy / std::max(h, 1e-300);
    auto cx_of = [&](double x) {
        return std::min(gx - 1, static_cast<std::uint32_t>((x - all.x0) * sx));
    };
    auto cy_of = [&](double y) {
        return std::min(gy - 1, static_cast<std::uint32_t>((y - all.y0) * sy));
    };
    seg_cells.resize(n);
    for (std::uint32_t s = 0; s < n; ++s) {
        const Box& b = seg_box[s];
        seg_cells[s] = {cx_of(b.x0), cx_of(b.x1), cy_of(b.y0), cy_of(b.y1)};
    }
    cell_start.assign(std::size_t{gx} * gy + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {  // count per cell, then fill (compressed rows)
        for (std::uint32_t s = 0; s < n; ++s) {
            const auto [cx0, cx1, cy0, cy1] = seg_cells[s];
            for (std::uint32_t cy = cy0; cy <= cy1; ++cy) {
                for (std::uint32_t cx = cx0; cx <= cx1; ++cx) {
                    const std::size_t c = std::size_t{cy} * gx + cx;
                    if (pass == 0)
                        ++cell_start[c + 1];
                    else
                        cell_items[cell_start[c]++] = s;
                }
            }
        }
        if (pass == 0) {
            for (std::size_t c = 1; c < cell_start.size(); ++c) cell_start[c] += cell_start[c - 1];
            cell_items.assign(cell_start.back(), 0);
        }
    }
    // After the fill, cell_start[c] is the END of cell c; cell c begins at cell_start[c - 1].
    for (std::size_t c = 0; c + 1 < cell_start.size(); ++c) {
        const std::uint32_t lo = c == 0 ? 0 : cell_start[c - 1];
        for (std::uint32_t i = lo; i < cell_start[c]; ++i) {
            for (std::uint32_t j = i + 1; j < cell_start[c]; ++j) {
                const Box& bs = seg_box[cell_items[i]];
                const Box& bt = seg_box[cell_items[j]];
                if (bs.x1 < bt.x0 || bt.x1 < bs.x0 || bs.y1 < bt.y0 || bt.y1 < bs.y0) continue;
                const std::size_t home =
                    std::size_t{cy_of(std::max(bs.y0, bt.y0))} * gx + cx_of(std::max(bs.x0, bt.x0));
                if (home != c || !segments_meet(cell_items[i], cell_items[j])) continue;
                return Err{triangulate_error(TriangulateErrc::kSelfIntersecting,
                                             seg_loop[cell_items[i]], seg_loop[cell_items[j]])};
            }
        }
    }
    return {};
}

/// The centroid of loop l's area (its first point when the area is too small to divide by).
Point2 Triangulator::Impl::centroid(std::uint32_t l) const noexcept {
    const Point2& o = pts[begin[l]];  // relative to the first point: no cancellation far away
    double cx = 0, cy = 0, twice = 0;
    for (std::uint32_t a = begin[l]; a < begin[l + 1]; ++a) {
        const Point2 p = pts[a] - o, q = pts[next_in_loop(a, l)] - o;
        const double w = p[0] * q[1] - p[1] * q[0];
        twice += w;
        cx += (p[0] + q[0]) * w;
        cy += (p[1] + q[1]) * w;
    }
    if (!(std::abs(twice) > 0)) return o;
    return Point2(o[0] + cx / (3.0 * twice), o[1] + cy / (3.0 * twice));
}

/// Whether loop l is star-shaped about c, and so simple: every edge turns clearly the loop's way
/// about c (a cross product beyond its rounding), so each edge spans an angle in (0, pi) about c
/// and the angles only rise, and they make exactly one turn (the loop crosses the ray from c
/// along +x once). Then every ray from c meets the loop once, so no two edges meet except
/// neighbours at their shared point.
bool Triangulator::Impl::star_shaped_about(std::uint32_t l, const Point2& c) const noexcept {
    const double dir = area[l] > 0 ? 1.0 : -1.0;
    constexpr double kClear = 64 * std::numeric_limits<double>::epsilon();
    std::uint32_t turns = 0;
    for (std::uint32_t a = begin[l]; a < begin[l + 1]; ++a) {
        const Point2 p = pts[a] - c, q = pts[next_in_loop(a, l)] - c;
        const double w = dir * (p[0] * q[1] - p[1] * q[0]);
        if (!(w > kClear * (std::abs(p[0]) + std::abs(p[1])) * (std::abs(q[0]) + std::abs(q[1]))))
            return false;
        // Crossing the ray y = 0, x > 0 (read with y mirrored for a clockwise loop, so the
        // angles rise and every crossing of that ray goes from below to above).
        if (dir * p[1] < 0 && !(dir * q[1] < 0)) {
            const double x = p[0] + (q[0] - p[0]) * (-p[1]) / (q[1] - p[1]);
            turns += x > 0 ? 1 : 0;
        }
    }
    return turns == 1;
}

bool Triangulator::Impl::point_in_loop(const Point2& p, std::uint32_t l) const noexcept {
    bool inside = false;
    for (std::uint32_t a = begin[l]; a < begin[l + 1]; ++a) {
        const Point2& pa = pts[a];
        const Point2& pb = pts[next_in_loop(a, l)];
        if ((pa[1] > p[1]) != (pb[1] > p[1]) &&
            p[0] < pa[0] + (p[1] - pa[1]) * (pb[0] - pa[0]) / (pb[1] - pa[1])) {
            inside = !inside;
        }
    }
    return inside;
}

/// depth = how many loops contain a loop; parent = the smallest of them (-1 for none).
void Triangulator::Impl::find_nesting() {
    depth.assign(loops(), 0);
    parent.assign(loops(), -1);
    for (std::uint32_t i = 0; i < loops(); ++i) {
        for (std::uint32_t j = 0; j < loops(); ++j) {
            if (i == j || !box[j].contains(box[i]) || !point_in_loop(pts[begin[i]], j)) continue;
            ++depth[i];
            const std::int32_t pi = parent[i];
            if (pi < 0 || std::abs(area[j]) < std::abs(area[static_cast<std::uint32_t>(pi)])) {
                parent[i] = static_cast<std::int32_t>(j);
            }
        }
    }
}

// ---- convex fast path ------------------------------------------------------------------------

bool Triangulator::Impl::strictly_convex(std::uint32_t l) const noexcept {
    const double dir = area[l] > 0 ? 1.0 : -1.0;
    for (std::uint32_t p = begin[l]; p < begin[l + 1]; ++p) {
        const std::uint32_t q = next_in_loop(p, l);
        if (!(dir * cross(pts[p], pts[q], pts[next_in_loop(q, l)]) > 0.0)) return false;
    }
    return true;  // all turns one way and (validated) simple: convex
}

void Triangulator::Impl::fan(std::uint32_t l, std::vector<Triangle>& out) const {
    const std::uint32_t o = begin[l];
    const bool ccw = area[l] > 0;
    for (std::uint32_t p = o + 1; p + 1 < begin[l + 1]; ++p) {
        out.push_back(ccw ? Triangle{o, p, p + 1} : Triangle{o, p + 1, p});
    }
}

// ---- one-hole fast path ----------------------------------------------------------------------

// A strip triangle must be counter-clockwise by this much of its longest edge squared (twice its
// area), far above rounding: then the orientations, and so the validity argument, are exact.
constexpr double kStripMinRelativeArea = 1e-9;

// A strip takes the in-circle test's answer only when it is this clear (plan_caps' flip bound).
constexpr double kStripClearInCircle = 1e-9;

bool Triangulator::Impl::strip(std::uint32_t l, std::uint32_t h, std::vector<Triangle>& out) const {
    const std::uint32_t no = loop_size(l), nh = loop_size(h);
    // Both loops read counter-clockwise: the region is left of the outer loop's edges and right
    // of the hole's, so (o_i, o_i+1, h_j) and (o_i, h_j+1, h_j) are counter-clockwise.
    // k < 2 no (outer) and k < 2 nh (hole) below: one subtraction wraps it.
    auto outer = [&](std::uint32_t k) {
        if (k >= no) k -= no;
        return area[l] > 0 ? begin[l] + k : begin[l] + (no - 1 - k);
    };
    auto hole = [&](std::uint32_t k) {
        if (k >= nh) k -= nh;
        return area[h] > 0 ? begin[h] + k : begin[h] + (nh - 1 - k);
    };
    using detail::sqrnorm, detail::sub;  // (p - q).sqrnorm() written out (vec_ops.hpp)
    // (a, b, c) counter-clockwise by kStripMinRelativeArea of its longest edge squared, from its
    // squared edge lengths (each rung's is worked out once and carried to the next step).
    auto clearly_ccw = [&](const Point2& a, const Point2& b, const Point2& c, double ab2,
                           double bc2, double ca2) {
        return cross(a, b, c) > kStripMinRelativeArea * std::max({ab2, bc2, ca2});
    };
    // The first rung: outer point 0 to the nearest hole point.
    std::uint32_t t = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t k = 0; k < nh; ++k) {
        const double d = sqrnorm(sub(pts[hole(k)], pts[outer(0)]));
        if (d < best) best = d, t = k;
    }
    const std::size_t first = out.size();
    std::uint32_t i = 0, j = t;
    double rung2 = best;  // the current rung's squared length, o to hj
    while (i < no || j < t + nh) {
        const bool more_outer = i < no, more_hole = j < t + nh;
        const std::uint32_t o = outer(i), hj = hole(j);
        const std::uint32_t o1 = more_outer ? outer(i + 1) : o, h1 = more_hole ? hole(j + 1) : hj;
        const Point2 &po = pts[o], &phj = pts[hj], &po1 = pts[o1], &ph1 = pts[h1];
        // The next rung either way: o1-hj (outer), o-h1 (hole).
        const double a2 = more_outer ? sqrnorm(sub(po1, phj)) : 0.0;
        const double b2 = more_hole ? sqrnorm(sub(ph1, po)) : 0.0;
        // The one way left at the end of a loop; otherwise the quad (o, o1, h1, hj): taking the
        // outer point makes o1-hj the next rung, which is locally Delaunay unless h1 lies
        // clearly inside the circle through (o, o1, hj); a near tie (cocircular, as on a round
        // bone's evenly spaced loops) takes the shorter rung. Delaunay here leaves the cap's flip
        // pass (plan_caps) next to nothing to do. The way preferred is taken if its triangle is
        // clearly counter-clockwise, else the other if its is.
        bool take_outer = !more_hole;
        if (more_outer && more_hole) {
            const double inside = detail::in_circle(po, po1, phj, ph1);
            const double clear = kStripClearInCircle * (b2 * sqrnorm(sub(po1, ph1)));
            if (inside > clear)
                take_outer = false;
            else if (inside < -clear)
                take_outer = true;
            else
                take_outer = a2 <= b2;
        }
        auto valid = [&](bool outer_way) {
            return outer_way ? clearly_ccw(po, po1, phj, sqrnorm(sub(po, po1)), a2, rung2)
                             : clearly_ccw(po, ph1, phj, b2, sqrnorm(sub(ph1, phj)), rung2);
        };
        if (!valid(take_outer)) {
            take_outer = !take_outer;
            if (!(more_outer && more_hole) || !valid(take_outer)) {
                out.resize(first);
                return false;
            }
        }
        if (take_outer) {
            out.push_back(Triangle{o, o1, hj});
            rung2 = a2;
            ++i;
        } else {
            out.push_back(Triangle{o, h1, hj});
            rung2 = b2;
            ++j;
        }
    }
    return true;
}

// ---- rings -----------------------------------------------------------------------------------

std::uint32_t Triangulator::Impl::add_node(std::uint32_t point) {
    const auto id = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back(Node{pts[point][0], pts[point][1], point, id, id, true});
    return id;
}

/// Links loop l into a ring turning the requested way; returns its leftmost node.
std::uint32_t Triangulator::Impl::make_ring(std::uint32_t l, bool ccw) {
    const bool forward = (area[l] > 0) == ccw;
    const std::uint32_t n = loop_size(l);
    const auto first = static_cast<std::uint32_t>(nodes.size());
    std::uint32_t leftmost = first;
    for (std::uint32_t k = 0; k < n; ++k) {
        const std::uint32_t id = add_node(forward ? begin[l] + k : begin[l + 1] - 1 - k);
        nodes[id].prev = k == 0 ? first + n - 1 : id - 1;
        nodes[id].next = k + 1 == n ? first : id + 1;
        const Node& m = nodes[leftmost];
        if (nodes[id].x < m.x || (nodes[id].x == m.x && nodes[id].y < m.y)) leftmost = id;
    }
    return leftmost;
}

void Triangulator::Impl::unlink(std::uint32_t n) noexcept {
    Node& node = nodes[n];
    nodes[node.next].prev = node.prev;
    nodes[node.prev].next = node.next;
    node.alive = false;
}

double Triangulator::Impl::turn(std::uint32_t n) const noexcept {
    const Node& a = nodes[nodes[n].prev];
    const Node& b = nodes[n];
    const Node& c = nodes[nodes[n].next];
    return cross(a.x, a.y, b.x, b.y, c.x, c.y);
}

/// Joins a to b by a zero-width slit: a -> b ... and a' <- b' closing the other side.
std::uint32_t Triangulator::Impl::split(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t a2 = add_node(nodes[a].i);
    const std::uint32_t b2 = add_node(nodes[b].i);
    const std::uint32_t an = nodes[a].next;
    const std::uint32_t bp = nodes[b].prev;
    nodes[a].next = b;
    nodes[b].prev = a;
    nodes[a2].next = an;
    nodes[an].prev = a2;
    nodes[b2].next = a2;
    nodes[a2].prev = b2;
    nodes[bp].next = b2;
    nodes[b2].prev = bp;
    return b2;
}

bool Triangulator::Impl::locally_inside(std::uint32_t a, std::uint32_t b) const noexcept {
    const Node& na = nodes[a];
    const Node& p = nodes[na.prev];
    const Node& n = nodes[na.next];
    const Node& nb = nodes[b];
    if (turn(a) > 0) {
        return cross(na.x, na.y, nb.x, nb.y, n.x, n.y) <= 0 &&
               cross(na.x, na.y, p.x, p.y, nb.x, nb.y) <= 0;
    }
    return cross(na.x, na.y, nb.x, nb.y, p.x, p.y) > 0 ||
           cross(na.x, na.y, n.x, n.y, nb.x, nb.y) > 0;
}

bool Triangulator::Impl::sector_contains_sector(std::uint32_t m, std::uint32_t p) const noexcept {
    const Node& nm = nodes[m];
    const Node& mp = nodes[nm.prev];
    const Node& mn = nodes[nm.next];
    const Node& pp = nodes[nodes[p].prev];
    const Node& pn = nodes[nodes[p].next];
    return cross(mp.x, mp.y, nm.x, nm.y, pp.x, pp.y) > 0 &&
           cross(pn.x, pn.y, nm.x, nm.y, mn.x, mn.y) > 0;
}

/// Eberly's bridge: cast a ray left from the hole's leftmost point, take the nearest boundary
/// edge it hits, then the visible vertex of smallest angle inside the triangle it spans.
std::uint32_t Triangulator::Impl::find_bridge(std::uint32_t hole,
                                              std::uint32_t outer) const noexcept {
    const double hx = nodes[hole].x;
    const double hy = nodes[hole].y;
    double qx = -std::numeric_limits<double>::infinity();
    std::uint32_t m = kNone;
    std::uint32_t p = outer;
    do {
        const Node& a = nodes[p];
        const Node& b = nodes[a.next];
        if (hy <= a.y && hy >= b.y && b.y != a.y) {
            const double x = a.x + (hy - a.y) * (b.x - a.x) / (b.y - a.y);
            if (x <= hx && x > qx) {
                qx = x;
                m = a.x < b.x ? p : a.next;
            }
        }
        p = a.next;
    } while (p != outer);
    if (m == kNone) return kNone;
    const std::uint32_t stop = m;
    const double mx = nodes[m].x;
    const double my = nodes[m].y;
    double tan_min = std::numeric_limits<double>::infinity();
    const double ax = hy < my ? hx : qx;
    const double cx = hy < my ? qx : hx;
    p = m;
    do {
        const Node& np = nodes[p];
        if (hx >= np.x && np.x >= mx && hx != np.x && cross(ax, hy, mx, my, np.x, np.y) >= 0 &&
            cross(mx, my, cx, hy, np.x, np.y) >= 0 && cross(cx, hy, ax, hy, np.x, np.y) >= 0) {
            const double tan = std::abs(hy - np.y) / (hx - np.x);
            if (locally_inside(p, hole) &&
                (tan < tan_min ||
                 (tan == tan_min &&
                  (np.x > nodes[m].x || (np.x == nodes[m].x && sector_contains_sector(m, p)))))) {
                m = p;
                tan_min = tan;
            }
        }
        p = np.next;
    } while (p != stop);
    return m;
}

void Triangulator::Impl::eliminate_holes(std::uint32_t outer) {
    std::sort(holes.begin(), holes.end(), [&](std::uint32_t a, std::uint32_t b) {
        const Node& na = nodes[a];
        const Node& nb = nodes[b];
        return na.x != nb.x ? na.x < nb.x : (na.y != nb.y ? na.y < nb.y : a < b);
    });
    for (const std::uint32_t h : holes) {
        std::uint32_t bridge = find_bridge(h, outer);
        if (bridge == kNone) {  // rounding only: join to the nearest boundary node instead
            double best = std::numeric_limits<double>::infinity();
            std::uint32_t p = outer;
            do {
                const double d = std::hypot(nodes[p].x - nodes[h].x, nodes[p].y - nodes[h].y);
                if (d < best) {
                    best = d;
                    bridge = p;
                }
                p = nodes[p].next;
            } while (p != outer);
        }
        split(bridge, h);
    }
}

// ---- reflex grid ---------------------------------------------------------------------------

std::uint32_t Triangulator::Impl::cell_x(double x) const noexcept {
    return static_cast<std::uint32_t>(std::clamp((x - gx0) * ginv, 0.0, gnx - 1.0));
}

std::uint32_t Triangulator::Impl::cell_y(double y) const noexcept {
    return static_cast<std::uint32_t>(std::clamp((y - gy0) * ginv, 0.0, gny - 1.0));
}

/// Buckets the ring's reflex and straight vertices (the only ones that can lie inside an ear)
/// into about one cell per vertex. Clipping never makes a vertex reflex, so the grid only loses
/// members (dead or now convex ones are skipped when met).
void Triangulator::Impl::build_grid(std::uint32_t start) {
    Box b;
    std::uint32_t count = 0;
    std::uint32_t p = start;
    do {
        b.add(Point2(nodes[p].x, nodes[p].y));
        ++count;
        p = nodes[p].next;
    } while (p != start);
    const double w = std::max(b.x1 - b.x0, 1e-300);
    const double h = std::max(b.y1 - b.y0, 1e-300);
    const double cell = std::max(std::sqrt(w * h / count), std::max(w, h) / 4096.0);
    gx0 = b.x0;
    gy0 = b.y0;
    ginv = 1.0 / cell;
    gnx = static_cast<std::uint32_t>(std::clamp(w / cell, 1.0, 4096.0));
    gny = static_cast<std::uint32_t>(std::clamp(h / cell, 1.0, 4096.0));
    grid_start.assign(std::size_t{gnx} * gny + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        p = start;
        do {
            if (turn(p) <= 0) {
                const std::size_t c = std::size_t{cell_y(nodes[p].y)} * gnx + cell_x(nodes[p].x);
                if (pass == 0)
                    ++grid_start[c + 1];
                else
                    grid_items[grid_start[c]++] = p;
            }
            p = nodes[p].next;
        } while (p != start);
        if (pass == 0) {
            for (std::size_t c = 1; c < grid_start.size(); ++c) grid_start[c] += grid_start[c - 1];
            grid_items.assign(grid_start.back(), 0);
        }
    }
    // After the fill grid_start[c] is the end of cell c; cell c begins at grid_start[c - 1].
}

// ---- ear clipping ----------------------------------------------------------------------------

/// Node p (not a corner of the ear) stops the ear: a reflex or straight vertex inside it (on its
/// boundary too unless `strict`). Points at a corner's position (bridge copies) never stop it.
bool Triangulator::Impl::blocks(std::uint32_t p, std::uint32_t ear, bool strict) const noexcept {
    const Node& b = nodes[ear];
    const Node& a = nodes[b.prev];
    const Node& c = nodes[b.next];
    const Node& q = nodes[p];
    if (p == b.prev || p == b.next || p == ear) return false;
    if ((q.x == a.x && q.y == a.y) || (q.x == b.x && q.y == b.y) || (q.x == c.x && q.y == c.y)) {
        return false;
    }
    const double d1 = cross(a.x, a.y, b.x, b.y, q.x, q.y);
    const double d2 = cross(b.x, b.y, c.x, c.y, q.x, q.y);
    const double d3 = cross(c.x, c.y, a.x, a.y, q.x, q.y);
    const bool inside = strict ? (d1 > 0 && d2 > 0 && d3 > 0) : (d1 >= 0 && d2 >= 0 && d3 >= 0);
    return inside && turn(p) <= 0;
}

bool Triangulator::Impl::is_ear(std::uint32_t ear, bool strict) const noexcept {
    if (!(turn(ear) > 0)) return false;
    const std::uint32_t stop = nodes[ear].prev;
    for (std::uint32_t p = nodes[nodes[ear].next].next; p != stop; p = nodes[p].next) {
        if (blocks(p, ear, strict)) return false;
    }
    return true;
}

bool Triangulator::Impl::is_ear_gridded(std::uint32_t ear, bool strict) const noexcept {
    if (!(turn(ear) > 0)) return false;
    const Node& a = nodes[nodes[ear].prev];
    const Node& b = nodes[ear];
    const Node& c = nodes[b.next];
    const double x0 = std::min({a.x, b.x, c.x});
    const double x1 = std::max({a.x, b.x, c.x});
    const double y0 = std::min({a.y, b.y, c.y});
    const double y1 = std::max({a.y, b.y, c.y});
    const std::uint32_t cx0 = cell_x(x0);
    const std::uint32_t cx1 = cell_x(x1);
    for (std::uint32_t cy = cell_y(y0); cy <= cell_y(y1); ++cy) {
        const std::size_t row = std::size_t{cy} * gnx;
        const std::uint32_t lo = row + cx0 == 0 ? 0 : grid_start[row + cx0 - 1];
        const std::uint32_t hi = grid_start[row + cx1];
        for (std::uint32_t k = lo; k < hi; ++k) {
            const Node& q = nodes[grid_items[k]];
            if (!q.alive || q.x < x0 || q.x > x1 || q.y < y0 || q.y > y1) continue;
            if (blocks(grid_items[k], ear, strict)) return false;
        }
    }
    return true;
}

/// When no proper ear is left (rounding): pass 1 accepts points on the ear's boundary, pass 2 a
/// straight vertex (a zero-area ear), pass 3 the most convex vertex. Returns kNone if none.
std::uint32_t Triangulator::Impl::relaxed_ear(std::uint32_t start, int pass) const noexcept {
    std::uint32_t best = kNone;
    double best_turn = -std::numeric_limits<double>::infinity();
    std::uint32_t p = start;
    do {
        if (pass == 1 && (use_grid ? is_ear_gridded(p, true) : is_ear(p, true))) return p;
        if (pass == 2 && turn(p) == 0.0) return p;
        if (pass == 3 && turn(p) > best_turn) {
            best_turn = turn(p);
            best = p;
        }
        p = nodes[p].next;
    } while (p != start);
    return best;
}

/// Queues node n as an ear candidate if it is convex, in the bucket of its ear's size (buckets
/// by powers of two of the longest edge squared: smaller ears pop first, O(1) per operation).
void Triangulator::Impl::offer(std::uint32_t n) {
    ++version[n];
    if (!(turn(n) > 0)) return;
    const Node& b = nodes[n];
    const Node& a = nodes[b.prev];
    const Node& c = nodes[b.next];
    auto sq = [](const Node& u, const Node& v) {
        return (u.x - v.x) * (u.x - v.x) + (u.y - v.y) * (u.y - v.y);
    };
    const double key = std::max({sq(a, b), sq(b, c), sq(c, a)}) * key_scale;
    const int e = key > 0 ? std::ilogb(key) : -1000;
    const auto k = static_cast<std::uint32_t>(std::clamp(e + 64, 0, int{kBuckets} - 1));
    buckets[k].push_back(Candidate{n, version[n]});
    nonempty |= std::uint64_t{1} << (k / 2);
}

bool Triangulator::Impl::pop(Candidate& out) noexcept {
    while (nonempty != 0) {
        const auto pair = static_cast<std::uint32_t>(std::countr_zero(nonempty));
        for (std::uint32_t k = 2 * pair; k < 2 * pair + 2; ++k) {
            if (buckets[k].empty()) continue;
            out = buckets[k].back();
            buckets[k].pop_back();
            return true;
        }
        nonempty &= ~(std::uint64_t{1} << pair);
    }
    return false;
}

void Triangulator::Impl::cut_ear(std::uint32_t ear, std::vector<Triangle>& out) {
    const Node& e = nodes[ear];
    out.push_back(Triangle{nodes[e.prev].i, e.i, nodes[e.next].i});
    unlink(ear);
    ++version[ear];
    offer(e.prev);
    offer(e.next);
}

/// Clips the smallest ear first, so triangles stay local and each ear test looks at few points.
/// Clipping an ear changes only its two neighbours' ear status (a vertex inside another ear stays
/// inside it), so only they are re-queued: O(n log n) for a smooth region. If the queue runs dry
/// early (rounding), a full turn with relaxed tests picks the next ear, so the loop always ends.
void Triangulator::Impl::clip(std::uint32_t start, std::vector<Triangle>& out,
                              std::uint32_t& degenerate) {
    version.assign(nodes.size(), 0);
    for (auto& b : buckets) b.clear();
    nonempty = 0;
    Box frame;
    for (const Node& n : nodes) frame.add(Point2(n.x, n.y));
    const double size = std::max(frame.x1 - frame.x0, frame.y1 - frame.y0);
    key_scale = size > 0 ? 1.0 / (size * size) : 1.0;
    std::uint32_t left = 0;
    std::uint32_t p = start;
    do {
        offer(p);
        ++left;
        p = nodes[p].next;
    } while (p != start);
    std::uint32_t any = start;  // a live node
    while (left > 2) {
        if (Candidate c{}; pop(c)) {
            if (c.version != version[c.node]) continue;
            if (!(use_grid ? is_ear_gridded(c.node, false) : is_ear(c.node, false))) continue;
            any = nodes[c.node].next;
            cut_ear(c.node, out);
            --left;
            continue;
        }
        std::uint32_t forced = kNone;
        for (int pass = 1; pass <= 3 && forced == kNone; ++pass) {
            forced = relaxed_ear(any, pass);
            if (forced != kNone && pass >= 2) ++degenerate;
        }
        any = nodes[forced].next;
        cut_ear(forced, out);
        --left;
    }
}

// ---- public ----------------------------------------------------------------------------------

Triangulator::Triangulator() : impl_(std::make_unique<Impl>()) {}
Triangulator::~Triangulator() = default;
Triangulator::Triangulator(Triangulator&&) noexcept = default;
Triangulator& Triangulator::operator=(Triangulator&&) noexcept = default;

Status<TriangulateError> Triangulator::triangulate(std::span<const std::span<const Point2>> loops,
                                                   std::vector<Triangle>& out) {
    out.clear();
    stats_ = TriangulateStats{};
    stats_.loops = static_cast<std::uint32_t>(loops.size());
    Impl& m = *impl_;
    if (auto s = m.load(loops); !s) return s;
    if (auto s = m.measure(); !s) return s;
    if (auto s = m.check_crossings(); !s) return s;
    m.find_nesting();
    out.reserve(m.pts.size() + 2 * m.loops());
    for (std::uint32_t l = 0; l < m.loops(); ++l) {
        if (m.depth[l] % 2 == 1) {
            ++stats_.holes;
            continue;
        }
        ++stats_.outer_loops;
        auto is_hole_of_l = [&](std::uint32_t h) {
            return m.parent[h] == static_cast<std::int32_t>(l) && m.depth[h] % 2 == 1;
        };
        // The fan and the strip read the loops as they are: only the ear clipper needs the rings.
        std::uint32_t hole_count = 0, first_hole = 0;
        for (std::uint32_t h = m.loops(); h-- > 0;)
            if (is_hole_of_l(h)) ++hole_count, first_hole = h;
        if (hole_count == 0 && m.strictly_convex(l)) {
            m.fan(l, out);
            ++stats_.fans;
            continue;
        }
        if (hole_count == 1 && m.strip(l, first_hole, out)) {
            ++stats_.strips;
            continue;
        }
        m.nodes.clear();
        m.holes.clear();
        const std::uint32_t outer = m.make_ring(l, true);
        for (std::uint32_t h = 0; h < m.loops(); ++h)
            if (is_hole_of_l(h)) m.holes.push_back(m.make_ring(h, false));
        m.eliminate_holes(outer);
        m.use_grid = m.nodes.size() >= kGridThreshold;
        if (m.use_grid) m.build_grid(outer);
        m.clip(outer, out, stats_.degenerate_ears);
    }
    return {};
}

bool Triangulator::triangulate_strip(std::span<const std::span<const Point2>> loops,
                                     std::vector<Triangle>& out) {
    out.clear();
    stats_ = TriangulateStats{};
    stats_.loops = static_cast<std::uint32_t>(loops.size());
    Impl& m = *impl_;
    if (loops.size() != 2 || !m.load(loops) || !m.measure()) return false;
    // Two loops each star-shaped about the hole's centroid are simple (star_shaped_about); that
    // they neither cross nor touch each other follows from every strip triangle being clearly
    // counter-clockwise (strip). Otherwise the general check: a bone whose cortex folds round.
    const Point2 centre = m.centroid(std::abs(m.area[0]) < std::abs(m.area[1]) ? 0 : 1);
    if (!(m.star_shaped_about(0, centre) && m.star_shaped_about(1, centre)) && !m.check_crossings())
        return false;
    m.find_nesting();
    const std::uint32_t outer = m.depth[0] == 0 ? 0 : 1, hole = 1 - outer;
    if (m.depth[outer] != 0 || m.depth[hole] != 1 ||
        m.parent[hole] != static_cast<std::int32_t>(outer))
        return false;
    out.reserve(m.pts.size() + 2);
    if (!m.strip(outer, hole, out)) return false;
    stats_.outer_loops = 1;
    stats_.holes = 1;
    stats_.strips = 1;
    return true;
}

Result<std::vector<Triangle>, TriangulateError> triangulate_loops(
    std::span<const std::span<const Point2>> loops) {
    Triangulator t;
    std::vector<Triangle> out;
    if (auto s = t.triangulate(loops, out); !s) return Err{s.error()};
    return out;
}

}  // namespace kerf::cut
