#include "display/cut/face_tree.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <numeric>

#include "display/cut/vec_ops.hpp"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace kerf::cut::detail {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A float not above x / not below x (float rounding must never shrink a box): x rounded to
// float, stepped one float towards -inf / +inf when the rounding went the wrong way (0 and -0
// step to -/+ the smallest denormal, +/-inf to the largest finite float; NaN is never stepped):
// std::nextafter's values, checked bit for bit on 60 million doubles and the special values.
// On the bits with masks, no branch: the direction of the rounding is random from coordinate to
// coordinate, and its mispredicted branches were most of a face-tree insert.
float round_down(double x) {
    const auto f = static_cast<float>(x);
    const auto bits = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t zero = 0u - static_cast<std::uint32_t>((bits << 1) == 0);
    const std::uint32_t down = (zero & 0x80000001u) | (~zero & (bits + 2 * (bits >> 31) - 1));
    const std::uint32_t step = 0u - static_cast<std::uint32_t>(static_cast<double>(f) > x);
    return std::bit_cast<float>(bits ^ ((bits ^ down) & step));
}
float round_up(double x) {
    const auto f = static_cast<float>(x);
    const auto bits = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t zero = 0u - static_cast<std::uint32_t>((bits << 1) == 0);
    const std::uint32_t up = (zero & 0x00000001u) | (~zero & (bits + 1 - 2 * (bits >> 31)));
    const std::uint32_t step = 0u - static_cast<std::uint32_t>(static_cast<double>(f) < x);
    return std::bit_cast<float>(bits ^ ((bits ^ up) & step));
}

}  // namespace

#if defined(__SSE2__)
// round_down (up = false) or round_up (up = true) of a0, a1, b0, b1 in the four lanes, with SSE2:
// the same conversion (cvtpd2ps, as static_cast<float>), the same comparison back in double and
// the same one-float step of the bits, lane by lane. The step is +1 on the bits of a positive
// float and -1 on a negative one's ((bits >> 31, arithmetic) | 1), added for up, subtracted for
// down: round_down's and round_up's special case for a zero is never stepped here with another
// value, since a zero that must step down is -0 (x < 0 rounds to -0) and one that must step up
// is +0. Checked bit for bit against the masked form on 100 million lane values (random doubles,
// doubles at and next to floats, zeros, denormals, the float range's ends, infinities, NaN).
[[gnu::always_inline]] inline __m128 round4(__m128d a, __m128d b, bool up) {
    const __m128 fa = _mm_cvtpd_ps(a), fb = _mm_cvtpd_ps(b);
    const __m128d back_a = _mm_cvtps_pd(fa), back_b = _mm_cvtps_pd(fb);
    const __m128d wrong_a = up ? _mm_cmplt_pd(back_a, a) : _mm_cmpgt_pd(back_a, a);
    const __m128d wrong_b = up ? _mm_cmplt_pd(back_b, b) : _mm_cmpgt_pd(back_b, b);
    const __m128i step = _mm_castps_si128(
        _mm_shuffle_ps(_mm_castpd_ps(wrong_a), _mm_castpd_ps(wrong_b), _MM_SHUFFLE(2, 0, 2, 0)));
    const __m128i bits = _mm_castps_si128(_mm_movelh_ps(fa, fb));
    const __m128i away = _mm_or_si128(_mm_srai_epi32(bits, 31), _mm_set1_epi32(1));
    const __m128i delta = _mm_and_si128(away, step);
    return _mm_castsi128_ps(up ? _mm_add_epi32(bits, delta) : _mm_sub_epi32(bits, delta));
}
#endif

float round_down_float(double x) { return round_down(x); }
float round_up_float(double x) { return round_up(x); }

namespace {

// Spreads the low 21 bits of x to every third bit.
std::uint64_t spread_bits(std::uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

// spread_bits of every 11-bit number: a 16 KB table (L1-resident).
const std::array<std::uint64_t, 2048> kSpread11 = [] {
    std::array<std::uint64_t, 2048> t{};
    for (std::uint64_t x = 0; x < t.size(); ++x) t[x] = spread_bits(x);
    return t;
}();

// spread_bits(x) for x < 2^21, from the table: bits 11-20 land on 33-60.
std::uint64_t spread_21_bits(std::uint64_t x) {
    return kSpread11[x & 2047] | kSpread11[(x >> 11) & 1023] << 33;
}

// 12 bytes, not 16: the sort reads and writes a quarter less, and its two arrays page in 8 MB
// less on a 1M-face mesh.
#pragma pack(push, 4)
struct Keyed {
    std::uint64_t code;
    std::uint32_t index;
};
#pragma pack(pop)
static_assert(sizeof(Keyed) == 12);

// The sort's digits: pass p orders the keys by kDigitBits[p] bits of the code from
// kDigitShift[p] up (see radix_sort). The low digits are short, so that a pass writes to few
// places at once: 10 and 12 bits (1,024 and 4,096 buckets) took 3.5 and 4.4 ms a pass on the 1M
// foot where 13 bits (8,192) took 6.3 and 5.5 ms; the top digit, 15 bits, has far fewer distinct
// values than buckets (the centres lie on a surface, in 32 cells a side): 3.0 ms.
constexpr int kSkippedBits = 26, kPasses = 3;
constexpr int kDigitBits[kPasses] = {10, 12, 15};
constexpr int kDigitShift[kPasses] = {kSkippedBits, kSkippedBits + kDigitBits[0],
                                      kSkippedBits + kDigitBits[0] + kDigitBits[1]};
static_assert(kDigitShift[2] + kDigitBits[2] == 63);  // the code's bits 26 to 62
// Where each pass's counts start in the one count array, and its size.
constexpr std::size_t kCountOffset[kPasses] = {
    0, std::size_t{1} << kDigitBits[0],
    (std::size_t{1} << kDigitBits[0]) + (std::size_t{1} << kDigitBits[1])};
constexpr std::size_t kCounts = kCountOffset[2] + (std::size_t{1} << kDigitBits[2]);

constexpr std::uint32_t digit(std::uint64_t code, int pass) {
    return static_cast<std::uint32_t>(code >> kDigitShift[pass]) & ((1u << kDigitBits[pass]) - 1);
}

// (a.code, a.index) < (b.code, b.index)
inline bool key_before(const Keyed& a, const Keyed& b) {
    return a.code != b.code ? a.code < b.code : a.index < b.index;
}

// The digit counts of the three passes, count[kCountOffset[pass] + digit], in one read of the
// keys (the three increments written out: the loop over the passes cost twice the instructions).
void count_digits(const Keyed* v, std::size_t n, std::uint32_t* count) {
    static_assert(kPasses == 3);
    std::uint32_t* const c0 = count + kCountOffset[0];
    std::uint32_t* const c1 = count + kCountOffset[1];
    std::uint32_t* const c2 = count + kCountOffset[2];
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t c = v[i].code;
        ++c0[digit(c, 0)];
        ++c1[digit(c, 1)];
        ++c2[digit(c, 2)];
    }
}

// Sorts v[0, k) by (code, index) by insertion: the runs radix_sort leaves are short (2 to 22 keys
// on the 1M foot), where a std::sort call cost more than its sorting. Any sort gives the same
// order: the indices are distinct.
void insertion_sort(Keyed* v, std::size_t k) {
    for (std::size_t i = 1; i < k; ++i) {
        const Keyed x = v[i];
        std::size_t j = i;
        for (; j > 0 && key_before(x, v[j - 1]); --j) v[j] = v[j - 1];
        v[j] = x;
    }
}

// Sorts each run of v[0, n) equal in the code's bits from kSkippedBits up by (code, index):
// by insertion up to kInsertionRun keys, else std::sort (so a crowded cell costs O(k log k)).
void sort_runs(Keyed* v, std::size_t n) {
    constexpr std::size_t kInsertionRun = 32;
    for (std::size_t i = 0; i < n;) {
        const std::uint64_t high = v[i].code >> kSkippedBits;
        std::size_t j = i + 1;
        while (j < n && v[j].code >> kSkippedBits == high) ++j;
        if (j - i <= kInsertionRun)
            insertion_sort(v + i, j - i);
        else
            std::sort(v + i, v + j, key_before);
        i = j;
    }
}

// One stable pass of radix_sort: v[0, n) into tmp in order of digit `pass`, from that digit's
// counts (turned into the first position of each digit's keys).
void scatter_pass(const Keyed* v, Keyed* tmp, std::size_t n, int pass, std::uint32_t* counts) {
    std::uint32_t sum = 0;
    for (std::uint32_t d = 0; d < (1u << kDigitBits[pass]); ++d) {
        const std::uint32_t here = counts[d];
        counts[d] = sum;
        sum += here;
    }
    const int shift = kDigitShift[pass];
    const std::uint32_t mask = (1u << kDigitBits[pass]) - 1;
    for (std::size_t i = 0; i < n; ++i) tmp[counts[(v[i].code >> shift) & mask]++] = v[i];
}

// Sorts v[0, n) (in order of index) by (code, index), the order a stable sort by code gives.
// `tmp` holds n; returns the array holding the result (v or tmp). O(n) for the codes of a
// surface's face centres.
//
// A stable LSD radix sort by the code's bits from kSkippedBits up (63 bits used) in three passes
// of kDigitBits, instead of the five that all 63 bits take (each pass a read and a scattered
// write of n keys). That orders keys by (code >> kSkippedBits, index); the runs of keys equal in
// those bits are then sorted by (code, index), which gives the full order exactly. The skipped
// bits are the low 8.67 bits of each axis of the centres' box: a run holds the faces whose
// centres fall in one cell 1/5,000 of the box across: on the 1M-face foot 269k runs of 2 to 22
// keys (549k keys), sorted in 3 ms, where the two passes left out took about 8. Passes whose
// digit is the same for every code are skipped.
Keyed* radix_sort(Keyed* v, Keyed* tmp, std::size_t n) {
    std::vector<std::uint32_t> counts(kCounts, 0u);
    count_digits(v, n, counts.data());
    for (int pass = 0; pass < kPasses && n > 0; ++pass) {
        std::uint32_t* const c = counts.data() + kCountOffset[pass];
        if (c[digit(v[0].code, pass)] == n) continue;
        scatter_pass(v, tmp, n, pass, c);
        std::swap(v, tmp);
    }
    sort_runs(v, n);
    return v;
}

#if defined(__SSE2__)
// A face's box on SSE2 lanes (also the pass over the faces' arithmetic, below), each operation
// the one the scalar expression beside it performs, so every float and double is bit-identical:
// std::min(a, b), which is b < a ? b : a, is minpd(b, a); std::max(a, b), a < b ? b : a, is
// maxpd(b, a). OpenMesh's Vec3 operations, which the scalar forms used, are std::transform
// loops that gcc -O2 leaves going through memory.

/// A point as its (x, y) lanes and its z (low lane).
struct Lanes3 {
    __m128d xy, z;
};

inline Lanes3 lanes_of(const Vec3& p) {
    return {_mm_loadu_pd(p.data()), _mm_load_sd(p.data() + 2)};
}

/// A face's box, rounded outwards: lo in `down`, hi in `up` (lanes x, y, z, z).
struct BoxLanes {
    __m128 down, up;
};

/// Vec3::minimize / maximize from p0 by p1, then p2 (std::min(std::min(p0, p1), p2) per
/// coordinate), then the six roundings four lanes at a time (the third coordinate twice).
[[gnu::always_inline]] inline BoxLanes box_lanes(const Lanes3& p0, const Lanes3& p1,
                                                 const Lanes3& p2) {
    const __m128d lo_xy = _mm_min_pd(p2.xy, _mm_min_pd(p1.xy, p0.xy));
    const __m128d hi_xy = _mm_max_pd(p2.xy, _mm_max_pd(p1.xy, p0.xy));
    const __m128d lo_z = _mm_min_sd(p2.z, _mm_min_sd(p1.z, p0.z));
    const __m128d hi_z = _mm_max_sd(p2.z, _mm_max_sd(p1.z, p0.z));
    return {round4(lo_xy, _mm_unpacklo_pd(lo_z, lo_z), false),
            round4(hi_xy, _mm_unpacklo_pd(hi_z, hi_z), true)};
}

/// Writes the box: lo[0..2] and hi[0] in one 16-byte store, hi[1..2] in 8 bytes.
inline void store_box(const BoxLanes& b, FaceTree::Box& out) {
    static_assert(sizeof(FaceTree::Box) == 6 * sizeof(float));
    auto* const f = reinterpret_cast<float*>(&out);
    const __m128 z_and_x = _mm_shuffle_ps(b.down, b.up, _MM_SHUFFLE(0, 0, 2, 2));
    _mm_storeu_ps(f, _mm_shuffle_ps(b.down, z_and_x, _MM_SHUFFLE(2, 0, 1, 0)));
    _mm_storel_pi(reinterpret_cast<__m64*>(f + 4),
                  _mm_shuffle_ps(b.up, b.up, _MM_SHUFFLE(3, 3, 2, 1)));
}

FaceTree::Box rounded_box(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    FaceTree::Box b;
    store_box(box_lanes(lanes_of(p0), lanes_of(p1), lanes_of(p2)), b);
    return b;
}
#else
FaceTree::Box rounded_box(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    FaceTree::Box b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = round_down(std::min(std::min(p0[a], p1[a]), p2[a]));
        b.hi[a] = round_up(std::max(std::max(p0[a], p1[a]), p2[a]));
    }
    return b;
}
#endif

}  // namespace

FaceTree::Item FaceTree::item_of(const mesh::TriMesh& mesh, mesh::FaceHandle f) {
    // The three corners straight from the halfedge arrays (a circulator costs several times more).
    const mesh::HalfedgeHandle h0 = mesh.halfedge_handle(f);
    const mesh::HalfedgeHandle h1 = mesh.next_halfedge_handle(h0);
    const mesh::HalfedgeHandle h2 = mesh.next_halfedge_handle(h1);
    return item_from(f.idx(), mesh.point(mesh.to_vertex_handle(h0)),
                     mesh.point(mesh.to_vertex_handle(h1)), mesh.point(mesh.to_vertex_handle(h2)));
}

inline FaceTree::Item FaceTree::item_from(std::int32_t face, const Vec3& p0, const Vec3& p1,
                                          const Vec3& p2) {
    Item e;
    e.face = face;
    e.box = rounded_box(p0, p1, p2);
    return e;
}

inline std::uint64_t FaceTree::code_of(const float* point) const noexcept {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const double x = (point[a] - code_lo_[a]) * code_scale_;
        const double q = x >= 0.0 ? std::min(x, 2097151.0) : 0.0;  // NaN -> 0
        code |= spread_21_bits(static_cast<std::uint64_t>(q)) << a;
    }
    return code;
}

namespace {

// The centre of an item's box.
std::array<float, 3> centre_of(const FaceTree::Box& b) {
    return {0.5f * (b.lo[0] + b.hi[0]), 0.5f * (b.lo[1] + b.hi[1]), 0.5f * (b.lo[2] + b.hi[2])};
}

}  // namespace

void FaceTree::write_codes(const Box* boxes, std::size_t n, void* keys) const noexcept {
    auto* const out = static_cast<Keyed*>(keys);
#if defined(__SSE2__)
    // code_of(centre_of(box)) for each box, the arithmetic on lanes (the same operations: the
    // float centre, (c - lo) * scale in double, std::min(x, 2^21 - 1) as minpd(2^21 - 1, x),
    // a NaN or negative x to 0, truncated to an integer), then the spread by table.
    const __m128d lo_xy = _mm_loadu_pd(code_lo_), lo_z = _mm_load_sd(code_lo_ + 2);
    const __m128d scale = _mm_set1_pd(code_scale_), top = _mm_set1_pd(2097151.0);
    for (std::size_t i = 0; i < n; ++i) {
        const auto* const f = reinterpret_cast<const float*>(boxes + i);
        const __m128 lo = _mm_loadu_ps(f);        // lo0 lo1 lo2 hi0
        const __m128 tail = _mm_loadu_ps(f + 2);  // lo2 hi0 hi1 hi2
        const __m128 hi = _mm_shuffle_ps(tail, tail, _MM_SHUFFLE(3, 3, 2, 1));
        const __m128 c = _mm_mul_ps(_mm_set1_ps(0.5f), _mm_add_ps(lo, hi));
        const __m128d x_xy = _mm_mul_pd(_mm_sub_pd(_mm_cvtps_pd(c), lo_xy), scale);
        const __m128d x_z = _mm_mul_sd(_mm_sub_sd(_mm_cvtps_pd(_mm_movehl_ps(c, c)), lo_z), scale);
        const __m128d q_xy =
            _mm_and_pd(_mm_cmpge_pd(x_xy, _mm_setzero_pd()), _mm_min_pd(top, x_xy));
        const __m128d q_z = _mm_and_pd(_mm_cmpge_sd(x_z, _mm_setzero_pd()), _mm_min_sd(top, x_z));
        const __m128i qi_xy = _mm_cvttpd_epi32(q_xy);
        const auto qx = static_cast<std::uint32_t>(_mm_cvtsi128_si32(qi_xy));
        const auto qy = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_srli_si128(qi_xy, 4)));
        const auto qz = static_cast<std::uint32_t>(_mm_cvttsd_si32(q_z));
        out[i] = Keyed{spread_21_bits(qx) | spread_21_bits(qy) << 1 | spread_21_bits(qz) << 2,
                       static_cast<std::uint32_t>(i)};
    }
#else
    for (std::size_t i = 0; i < n; ++i)
        out[i] = Keyed{code_of(centre_of(boxes[i]).data()), static_cast<std::uint32_t>(i)};
#endif
}

bool FaceTree::enlarge(Box& b, const Box& by) noexcept {
    bool grew = false;
    for (int a = 0; a < 3; ++a) {
        grew |= by.lo[a] < b.lo[a] || by.hi[a] > b.hi[a];
        b.lo[a] = std::min(b.lo[a], by.lo[a]);
        b.hi[a] = std::max(b.hi[a], by.hi[a]);
    }
    return grew;
}

namespace {

// The largest |coordinate| of a box (infinite for a box with a NaN or infinite coordinate, which
// makes every group test pass: a float bound cannot hold there).
double max_abs_of(const FaceTree::Box& b) {
    double m = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double lo = std::abs(double(b.lo[a])), hi = std::abs(double(b.hi[a]));
        if (!(lo <= m)) m = std::isnan(lo) ? std::numeric_limits<double>::infinity() : lo;
        if (!(hi <= m)) m = std::isnan(hi) ? std::numeric_limits<double>::infinity() : hi;
    }
    return m;
}

}  // namespace

namespace {

constexpr int kMinStepExp = -126, kMaxStepExp = 127;  // normal floats: q x step is exact

// 2^e as a float, e in [kMinStepExp, kMaxStepExp].
inline float step_of(int e) {
    return std::bit_cast<float>(static_cast<std::uint32_t>(e + 127) << 23);
}

// The bound quantised value q stands for: origin + q x step, the product exact, the sum rounded
// once (as the group tests compute it, with or without a fused multiply-add).
inline float bound_of(float origin, std::uint32_t q, float step) {
    return origin + static_cast<float>(q) * step;
}

// Quantised bounds of [lo, hi] against (origin, step): the largest qlo whose bound is not above
// lo and the smallest qhi whose bound is not below hi; whether both fit 8 bits (lo not below
// origin, qhi at most 255). The double products give the candidates; the float bounds themselves
// settle them.
inline bool quantise_bounds(float lo, float hi, float origin, float step, std::uint32_t& qlo,
                            std::uint32_t& qhi) {
    if (!(lo >= origin)) return false;  // below the frame (or NaN)
    const double inv = 1.0 / static_cast<double>(step);
    const double l = std::floor((double(lo) - origin) * inv);
    const double h = std::ceil((double(hi) - origin) * inv);
    if (!(h <= 256.0)) return false;
    qlo = static_cast<std::uint32_t>(std::max(l, 0.0));
    while (qlo > 0 && bound_of(origin, qlo, step) > lo) --qlo;
    qhi = h > 0.0 ? static_cast<std::uint32_t>(h) : 0u;
    while (qhi <= 255 && bound_of(origin, qhi, step) < hi) ++qhi;
    return qhi <= 255;
}

// Opens g: a NaN origin makes every bound NaN, so every live lane passes every test (a box with
// a NaN or infinite coordinate, which no float bound holds).
inline void open_group(float* origin) {
    for (int a = 0; a < 3; ++a) origin[a] = std::numeric_limits<float>::quiet_NaN();
}

inline bool box_finite(const FaceTree::Box& b) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a])) return false;
    return true;
}

}  // namespace

FaceTree::Box FaceTree::lane_box(const Group& g, std::uint32_t k) noexcept {
    Box b;
    for (int a = 0; a < 3; ++a) {
        const float step = step_of(g.step_exp[a]);
        b.lo[a] = bound_of(g.origin[a], g.qlo[a][k], step);
        b.hi[a] = bound_of(g.origin[a], g.qhi[a][k], step);
    }
    return b;
}

FaceTree::Box FaceTree::group_box(const Group& g) noexcept {
    Box b{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
    for (std::uint32_t k = 0; k < kLanes; ++k) {
        if (!(g.live >> k & 1u)) continue;
        const Box l = lane_box(g, k);
        for (int a = 0; a < 3; ++a) {
            // NaN bounds (an open group) stay NaN: the parent's lane opens its group too.
            b.lo[a] = std::isnan(l.lo[a]) ? l.lo[a] : std::min(b.lo[a], l.lo[a]);
            b.hi[a] = std::isnan(l.hi[a]) ? l.hi[a] : std::max(b.hi[a], l.hi[a]);
        }
    }
    return b;
}

void FaceTree::quantise(Group& g, const Box* boxes, std::uint32_t live) noexcept {
    g.live = static_cast<std::uint8_t>(live);
    std::memset(g.qlo, 0, sizeof g.qlo);
    std::memset(g.qhi, 0, sizeof g.qhi);
    float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    bool finite = true;
    for (std::uint32_t k = 0; k < kLanes; ++k) {
        if (!(live >> k & 1u)) continue;
        finite &= box_finite(boxes[k]);
        for (int a = 0; a < 3; ++a)
            lo[a] = std::min(lo[a], boxes[k].lo[a]), hi[a] = std::max(hi[a], boxes[k].hi[a]);
    }
    if (!finite) {
        open_group(g.origin);
        for (int a = 0; a < 3; ++a) g.step_exp[a] = 0;
        max_abs_ = std::numeric_limits<double>::infinity();
        return;
    }
    if (live == 0) {
        for (int a = 0; a < 3; ++a) g.origin[a] = 0.0f, g.step_exp[a] = 0;
        return;
    }
    for (int a = 0; a < 3; ++a) {
        // The smallest step that spans the frame in 254 steps (one to spare for the rounding of
        // the bounds), larger while a bound does not fit.
        const double extent = double(hi[a]) - lo[a];
        int e = kMinStepExp;
        if (extent > 0.0) {
            std::frexp(extent / 254.0, &e);
            e = std::clamp(e, kMinStepExp, kMaxStepExp);
        }
        for (;; ++e) {
            const float step = step_of(e);
            bool fits = true;
            for (std::uint32_t k = 0; k < kLanes && fits; ++k) {
                if (!(live >> k & 1u)) continue;
                std::uint32_t ql = 0, qh = 0;
                fits = quantise_bounds(boxes[k].lo[a], boxes[k].hi[a], lo[a], step, ql, qh);
                g.qlo[a][k] = static_cast<std::uint8_t>(ql);
                g.qhi[a][k] = static_cast<std::uint8_t>(qh);
            }
            if (fits || e == kMaxStepExp) break;
        }
        g.origin[a] = lo[a];
        g.step_exp[a] = static_cast<std::int8_t>(e);
        const float step = step_of(e);
        for (std::uint32_t k = 0; k < kLanes; ++k) {
            if (!(live >> k & 1u)) continue;
            max_abs_ = std::max({max_abs_, std::abs(double(bound_of(lo[a], g.qlo[a][k], step))),
                                 std::abs(double(bound_of(lo[a], g.qhi[a][k], step)))});
        }
    }
}

#if defined(__SSE2__)
void FaceTree::quantise_leaf(Group& g, const Box* boxes, std::uint32_t count,
                             const Box& box) noexcept {
    // Axes whose step would leave the range where 2^-e is a normal float, and boxes that are not
    // finite (an open group), go the general way.
    bool simple = count > 0 && box_finite(box);
    for (std::uint32_t k = 0; k < count && simple; ++k) simple = box_finite(boxes[k]);
    int exps[3] = {0, 0, 0};
    for (int a = 0; a < 3 && simple; ++a) {
        const double extent = double(box.hi[a]) - box.lo[a];
        int e = kMinStepExp;
        if (extent > 0.0) std::frexp(extent / 254.0, &e);
        exps[a] = std::max(e, -100);
        simple = e <= 100;
    }
    if (!simple) {
        quantise(g, boxes, (2u << (count - 1)) - 1);
        return;
    }
    g.live = static_cast<std::uint8_t>((2u << (count - 1)) - 1);
    alignas(16) float lo[3][kLanes], hi[3][kLanes];
    for (std::uint32_t k = 0; k < kLanes; ++k)
        for (int a = 0; a < 3; ++a) {
            // Dead lanes stand at the origin (their bounds 0, as quantise leaves them).
            lo[a][k] = k < count ? boxes[k].lo[a] : box.lo[a];
            hi[a][k] = k < count ? boxes[k].hi[a] : box.lo[a];
        }
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    __m128 widest = _mm_setzero_ps();
    for (int a = 0; a < 3; ++a) {
        const __m128 origin = _mm_set1_ps(box.lo[a]);
        for (int e = exps[a];; ++e) {
            const __m128 step = _mm_set1_ps(step_of(e));
            const __m128 inv = _mm_set1_ps(step_of(-e));
            bool fits = true;
            __m128i qlo[2], qhi[2];
            __m128 bound_lo[2], bound_hi[2];
            for (int h = 0; h < 2 && fits; ++h) {
                const __m128 l = _mm_load_ps(&lo[a][4 * h]), u = _mm_load_ps(&hi[a][4 * h]);
                // Candidates from the float offsets (both at least 0: truncation floors), then
                // each bound settled against the box itself: down while the lower one is above
                // lo (0 never is: its bound is the origin), up while the upper one is below hi.
                __m128i ql = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(l, origin), inv));
                const __m128 uh = _mm_mul_ps(_mm_sub_ps(u, origin), inv);
                __m128i qh = _mm_cvttps_epi32(uh);
                qh = _mm_sub_epi32(qh, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(qh), uh)));
                for (;;) {
                    bound_lo[h] = _mm_add_ps(origin, _mm_mul_ps(_mm_cvtepi32_ps(ql), step));
                    const __m128 above = _mm_cmpgt_ps(bound_lo[h], l);
                    if (_mm_movemask_ps(above) == 0) break;
                    ql = _mm_add_epi32(ql, _mm_castps_si128(above));  // -1 where above
                }
                for (;;) {
                    bound_hi[h] = _mm_add_ps(origin, _mm_mul_ps(_mm_cvtepi32_ps(qh), step));
                    const __m128 below = _mm_cmplt_ps(bound_hi[h], u);
                    if (_mm_movemask_ps(below) == 0) break;
                    qh = _mm_sub_epi32(qh, _mm_castps_si128(below));  // +1 where below
                }
                fits = _mm_movemask_epi8(_mm_cmpgt_epi32(qh, _mm_set1_epi32(255))) == 0;
                qlo[h] = ql, qhi[h] = qh;
            }
            if (!fits) continue;  // one step larger (e stays at most 101: the extent fits)
            for (int h = 0; h < 2; ++h) {
                alignas(16) std::int32_t l[4], u[4];
                _mm_store_si128(reinterpret_cast<__m128i*>(l), qlo[h]);
                _mm_store_si128(reinterpret_cast<__m128i*>(u), qhi[h]);
                for (int k = 0; k < 4; ++k) {
                    g.qlo[a][4 * h + k] = static_cast<std::uint8_t>(l[k]);
                    g.qhi[a][4 * h + k] = static_cast<std::uint8_t>(u[k]);
                }
                widest = _mm_max_ps(widest, _mm_and_ps(bound_lo[h], abs_mask));
                widest = _mm_max_ps(widest, _mm_and_ps(bound_hi[h], abs_mask));
            }
            g.origin[a] = box.lo[a];
            g.step_exp[a] = static_cast<std::int8_t>(e);
            break;
        }
    }
    alignas(16) float w[4];
    _mm_store_ps(w, widest);
    max_abs_ = std::max({max_abs_, double(w[0]), double(w[1]), double(w[2]), double(w[3])});
}
#else
void FaceTree::quantise_leaf(Group& g, const Box* boxes, std::uint32_t count, const Box&) noexcept {
    quantise(g, boxes, count == 0 ? 0u : (2u << (count - 1)) - 1);
}
#endif

bool FaceTree::enlarge(Group& g, std::uint32_t lane, Box& by) noexcept {
    const std::uint32_t bit = 1u << lane;
    if (!box_finite(by)) {  // the group opens (and so does every group above it)
        open_group(g.origin);
        g.live = static_cast<std::uint8_t>(g.live | bit);
        max_abs_ = std::numeric_limits<double>::infinity();
        return true;
    }
    Box b = (g.live & bit) ? lane_box(g, lane) : by;
    if ((g.live & bit) && !enlarge(b, by)) return false;  // NaN bounds (open) hold everything
    // Inside the frame: the lane alone. Else the whole group, from the boxes its lanes stand for.
    std::uint32_t qlo[3], qhi[3];
    bool fits = !std::isnan(g.origin[0]) && g.live != 0 && box_finite(b);
    for (int a = 0; a < 3 && fits; ++a)
        fits =
            quantise_bounds(b.lo[a], b.hi[a], g.origin[a], step_of(g.step_exp[a]), qlo[a], qhi[a]);
    if (fits) {
        for (int a = 0; a < 3; ++a) {
            g.qlo[a][lane] = static_cast<std::uint8_t>(qlo[a]);
            g.qhi[a][lane] = static_cast<std::uint8_t>(qhi[a]);
        }
        g.live = static_cast<std::uint8_t>(g.live | bit);
        by = lane_box(g, lane);
        max_abs_ = std::max(max_abs_, max_abs_of(by));
        return true;
    }
    if (std::isnan(g.origin[0])) {  // open: stays open, and its parent's lane is open too
        g.live = static_cast<std::uint8_t>(g.live | bit);
        return false;
    }
    Box boxes[kLanes];
    for (std::uint32_t k = 0; k < kLanes; ++k)
        if (g.live >> k & 1u) boxes[k] = lane_box(g, k);
    boxes[lane] = b;
    quantise(g, boxes, g.live | bit);
    by = group_box(g);
    return true;
}

double FaceTree::float_error_m(double query_abs) const noexcept {
    // Each group test sums three products of float sums of coordinates up to max_abs_ (which
    // holds the quantised bounds too) and the query's own up to query_abs: a few roundings of
    // relative 2^-24 each, bounded generously.
    return 16.0 * std::numeric_limits<float>::epsilon() * (max_abs_ + query_abs);
}

// The group tests: four lanes at a time with SSE (every x86-64 has it), one at a time elsewhere,
// on the bounds the lanes stand for (bound_of, computed the same way). Comparisons are written
// so that a NaN passes: a test may keep a box it need not, never drop one.
#if defined(__SSE2__)

namespace {

// The float bounds of lanes [h, h + 4) on one axis: origin + q x step, as bound_of.
[[gnu::always_inline]] inline __m128 bounds4(const std::uint8_t* q, __m128 origin, __m128 step) {
    std::int32_t bytes;
    std::memcpy(&bytes, q, sizeof bytes);
    const __m128i zero = _mm_setzero_si128();
    const __m128i wide =
        _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(bytes), zero), zero);
    return _mm_add_ps(origin, _mm_mul_ps(_mm_cvtepi32_ps(wide), step));
}

// The group's origin and step on axis a, in every lane.
[[gnu::always_inline]] inline void frame4(const float* origin, const std::int8_t* step_exp, int a,
                                          __m128& o, __m128& step) {
    o = _mm_set1_ps(origin[a]);
    step = _mm_castsi128_ps(_mm_set1_epi32((step_exp[a] + 127) << 23));
}

}  // namespace

std::uint32_t FaceTree::plane_mask_narrow(const Group& g, const PlaneLanes& q) noexcept {
    const __m128 abs_bits = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    __m128 origin[3], step[3];
    for (int a = 0; a < 3; ++a) frame4(g.origin, g.step_exp, a, origin[a], step[a]);
    std::uint32_t mask = 0;
    for (std::uint32_t h = 0; h < kLanes; h += 4) {
        __m128 keep = _mm_castsi128_ps(_mm_set1_epi32(-1));
        __m128 centre = _mm_setzero_ps(), extent = _mm_setzero_ps();
        for (int a = 0; a < 3; ++a) {
            const __m128 lo = bounds4(&g.qlo[a][h], origin[a], step[a]);
            const __m128 hi = bounds4(&g.qhi[a][h], origin[a], step[a]);
            keep = _mm_and_ps(keep, _mm_cmpngt_ps(lo, _mm_set1_ps(q.hi[a])));
            keep = _mm_and_ps(keep, _mm_cmpnlt_ps(hi, _mm_set1_ps(q.lo[a])));
            centre = _mm_add_ps(centre, _mm_mul_ps(_mm_set1_ps(q.n[a]), _mm_add_ps(lo, hi)));
            extent = _mm_add_ps(extent, _mm_mul_ps(_mm_set1_ps(q.abs_n[a]), _mm_sub_ps(hi, lo)));
        }
        const __m128 off = _mm_and_ps(_mm_sub_ps(centre, _mm_set1_ps(q.twice_c0)), abs_bits);
        keep = _mm_and_ps(keep, _mm_cmpngt_ps(off, _mm_add_ps(extent, _mm_set1_ps(q.twice_slack))));
        mask |= static_cast<std::uint32_t>(_mm_movemask_ps(keep)) << h;
    }
    return mask & g.live;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define KERF_FACE_TREE_WIDE 1

namespace {

// bounds4 on eight lanes.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256 bounds8(const std::uint8_t* q,
                                                                  __m256 origin, __m256 step) {
    std::int64_t bytes;
    std::memcpy(&bytes, q, sizeof bytes);
    const __m256i wide = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(bytes));
    return _mm256_add_ps(origin, _mm256_mul_ps(_mm256_cvtepi32_ps(wide), step));
}

}  // namespace

// plane_mask_narrow on all eight lanes at once with AVX2: the same operations in the same order
// on every lane (no FMA: the bounds round as bound_of's), so the same masks (a test checks both
// ways on random groups), in about half the instructions. The plane query of a localised cut
// runs a few hundred of these; on a 4M-triangle tube of long thin faces they were the largest
// part of the cut's growth over 100k (issue 10, item 7).
[[gnu::target("avx2")]] std::uint32_t FaceTree::plane_mask_wide(const Group& g,
                                                                const PlaneLanes& q) noexcept {
    const __m256 abs_bits = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    __m256 keep = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    __m256 centre = _mm256_setzero_ps(), extent = _mm256_setzero_ps();
    for (int a = 0; a < 3; ++a) {
        const __m256 origin = _mm256_set1_ps(g.origin[a]);
        const __m256 step = _mm256_castsi256_ps(_mm256_set1_epi32((g.step_exp[a] + 127) << 23));
        const __m256 lo = bounds8(g.qlo[a], origin, step), hi = bounds8(g.qhi[a], origin, step);
        keep = _mm256_and_ps(keep, _mm256_cmp_ps(lo, _mm256_set1_ps(q.hi[a]), _CMP_NGT_UQ));
        keep = _mm256_and_ps(keep, _mm256_cmp_ps(hi, _mm256_set1_ps(q.lo[a]), _CMP_NLT_UQ));
        centre =
            _mm256_add_ps(centre, _mm256_mul_ps(_mm256_set1_ps(q.n[a]), _mm256_add_ps(lo, hi)));
        extent =
            _mm256_add_ps(extent, _mm256_mul_ps(_mm256_set1_ps(q.abs_n[a]), _mm256_sub_ps(hi, lo)));
    }
    const __m256 off = _mm256_and_ps(_mm256_sub_ps(centre, _mm256_set1_ps(q.twice_c0)), abs_bits);
    keep = _mm256_and_ps(
        keep,
        _mm256_cmp_ps(off, _mm256_add_ps(extent, _mm256_set1_ps(q.twice_slack)), _CMP_NGT_UQ));
    return static_cast<std::uint32_t>(_mm256_movemask_ps(keep)) & g.live;
}

#endif

std::uint32_t FaceTree::point_mask(const Group& g, const PointLanes& q) noexcept {
    __m128 origin[3], step[3];
    for (int a = 0; a < 3; ++a) frame4(g.origin, g.step_exp, a, origin[a], step[a]);
    std::uint32_t mask = 0;
    for (std::uint32_t h = 0; h < kLanes; h += 4) {
        __m128 d2 = _mm_setzero_ps();
        for (int a = 0; a < 3; ++a) {
            const __m128 p = _mm_set1_ps(q.p[a]);
            const __m128 below = _mm_sub_ps(bounds4(&g.qlo[a][h], origin[a], step[a]), p);
            const __m128 above = _mm_sub_ps(p, bounds4(&g.qhi[a][h], origin[a], step[a]));
            const __m128 d = _mm_max_ps(_mm_max_ps(below, above), _mm_setzero_ps());
            d2 = _mm_add_ps(d2, _mm_mul_ps(d, d));
        }
        const __m128 keep = _mm_cmpngt_ps(d2, _mm_set1_ps(q.r2));
        mask |= static_cast<std::uint32_t>(_mm_movemask_ps(keep)) << h;
    }
    return mask & g.live;
}

#else

std::uint32_t FaceTree::plane_mask_narrow(const Group& g, const PlaneLanes& q) noexcept {
    std::uint32_t mask = 0;
    for (std::uint32_t k = 0; k < kLanes; ++k) {
        bool keep = true;
        float centre = 0.0f, extent = 0.0f;
        const Box b = lane_box(g, k);
        for (int a = 0; a < 3; ++a) {
            const float lo = b.lo[a], hi = b.hi[a];
            keep &= !(lo > q.hi[a]) && !(hi < q.lo[a]);
            centre += q.n[a] * (lo + hi);
            extent += q.abs_n[a] * (hi - lo);
        }
        keep &= !(std::abs(centre - q.twice_c0) > extent + q.twice_slack);
        mask |= static_cast<std::uint32_t>(keep) << k;
    }
    return mask & g.live;
}

std::uint32_t FaceTree::point_mask(const Group& g, const PointLanes& q) noexcept {
    std::uint32_t mask = 0;
    for (std::uint32_t k = 0; k < kLanes; ++k) {
        float d2 = 0.0f;
        const Box b = lane_box(g, k);
        for (int a = 0; a < 3; ++a) {
            const float below = b.lo[a] - q.p[a], above = q.p[a] - b.hi[a];
            const float d = std::isnan(below) || std::isnan(above)
                                ? 0.0f
                                : std::max(std::max(below, above), 0.0f);
            d2 += d * d;
        }
        mask |= static_cast<std::uint32_t>(!(d2 > q.r2)) << k;
    }
    return mask & g.live;
}

#endif

namespace {

std::atomic<bool> wide_group_tests{[] {
#if defined(KERF_FACE_TREE_WIDE)
    return __builtin_cpu_supports("avx2") != 0;
#else
    return false;
#endif
}()};

}  // namespace

bool FaceTree::set_wide_group_tests(bool on) noexcept {
#if defined(KERF_FACE_TREE_WIDE)
    return wide_group_tests.exchange(on && __builtin_cpu_supports("avx2") != 0,
                                     std::memory_order_relaxed);
#else
    (void)on;
    return false;
#endif
}

std::uint32_t FaceTree::plane_mask(const Group& g, const PlaneLanes& q) noexcept {
#if defined(KERF_FACE_TREE_WIDE)
    if (wide_group_tests.load(std::memory_order_relaxed)) return plane_mask_wide(g, q);
#endif
    return plane_mask_narrow(g, q);
}

namespace {

/// What the pass over the faces measures besides their boxes (FaceTree::build's first step).
struct FaceScan {
    std::size_t count = 0;               ///< boxes written: the live faces, in face order
    bool every_face_live = true;         ///< no deleted face met
    std::vector<std::int32_t> faces_of;  ///< each box's face, from the first deleted face on
    double centre_lo[3] = {1e300, 1e300, 1e300};     ///< the box of the boxes' centres, as
    double centre_hi[3] = {-1e300, -1e300, -1e300};  ///< Vec3::minimize / maximize grow it
    double longest_sq = 0.0;             ///< the longest edge no flagged face borders, squared
    std::size_t boundary_halfedges = 0;  ///< the faces' halfedges with no face opposite
    double max_abs = 0.0;                ///< the largest max_abs_of of the boxes
};

/// The three halfedges of face `fi` and the faces across them (-1: none).
struct FaceRing {
    mesh::HalfedgeHandle h0, h1, h2;
    int across0, across1, across2;
};

inline FaceRing ring_of(const mesh::TriMesh& mesh, int fi) {
    FaceRing r;
    r.h0 = mesh.halfedge_handle(mesh::FaceHandle(fi));
    r.h1 = mesh.next_halfedge_handle(r.h0);
    r.h2 = mesh.next_halfedge_handle(r.h1);
    r.across0 = mesh.face_handle(mesh.opposite_halfedge_handle(r.h0)).idx();
    r.across1 = mesh.face_handle(mesh.opposite_halfedge_handle(r.h1)).idx();
    r.across2 = mesh.face_handle(mesh.opposite_halfedge_handle(r.h2)).idx();
    return r;
}

/// Whether an edge between faces f (live) and g (-1: none) counts for the longest edge: neither
/// is flagged.
template <bool kFlagged>
inline bool edge_counts(const std::uint8_t* flagged, int f, int g) {
    return !kFlagged || (flagged[f] == 0 && (g < 0 || flagged[g] == 0));
}

#if defined(__SSE2__)
/// (a - b).sqrnorm(), in the low lane: (dx² + dy²) + dz², as OpenMesh sums it.
inline __m128d sqrdist_sd(const Lanes3& a, const Lanes3& b) {
    const __m128d dxy = _mm_sub_pd(a.xy, b.xy), dz = _mm_sub_sd(a.z, b.z);
    const __m128d sq = _mm_mul_pd(dxy, dxy);
    return _mm_add_sd(_mm_add_sd(sq, _mm_unpackhi_pd(sq, sq)), _mm_mul_sd(dz, dz));
}

/// The pass's running measures, in registers.
class ScanLanes {
public:
    /// Widens the centres' box by the box's centre (centre_of's floats, 0.5f * (lo + hi)):
    /// lo = std::min(lo, c), hi = std::max(hi, c). In float, from +/-inf, for the double box
    /// that starts at +/-1e300: every float but an infinity is inside +/-1e300, so both take the
    /// same values, except that the double bound stays at 1e300 where the float one stays at
    /// infinity (no centre, or only infinite ones): write() maps that back.
    void add_centre(const BoxLanes& b) {
        const __m128 c = _mm_mul_ps(_mm_set1_ps(0.5f), _mm_add_ps(b.down, b.up));
        lo_ = _mm_min_ps(c, lo_);
        hi_ = _mm_max_ps(c, hi_);
    }
    /// The largest |coordinate|, as max_abs_of: maxps(x, m) is x > m ? x : m, so a NaN x leaves
    /// m and is remembered apart (max_abs_of is infinite for it).
    void add_abs(const BoxLanes& b) {
        const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        abs_ = _mm_max_ps(_mm_and_ps(b.down, abs_mask), abs_);
        abs_ = _mm_max_ps(_mm_and_ps(b.up, abs_mask), abs_);
        nan_ = _mm_or_ps(nan_, _mm_cmpunord_ps(b.down, b.up));
    }
    /// longest = std::max(longest, l)
    void add_length(__m128d l) { longest_ = _mm_max_sd(l, longest_); }

    void write(FaceScan& out) const {
        float lo[4], hi[4];
        _mm_storeu_ps(lo, lo_);
        _mm_storeu_ps(hi, hi_);
        for (int a = 0; a < 3; ++a) {
            out.centre_lo[a] = lo[a] == kInf ? 1e300 : double(lo[a]);
            out.centre_hi[a] = hi[a] == -kInf ? -1e300 : double(hi[a]);
        }
        out.longest_sq = _mm_cvtsd_f64(longest_);
        float m[4];
        _mm_storeu_ps(m, abs_);
        out.max_abs = _mm_movemask_ps(nan_) != 0
                          ? std::numeric_limits<double>::infinity()
                          : std::max({0.0, double(m[0]), double(m[1]), double(m[2])});
    }

private:
    __m128 lo_ = _mm_set1_ps(kInf), hi_ = _mm_set1_ps(-kInf);
    __m128d longest_ = _mm_setzero_pd();
    __m128 abs_ = _mm_setzero_ps(), nan_ = _mm_setzero_ps();
};

/// Measures live face `fi`: its box into `box`, its edges.
template <bool kFlagged>
[[gnu::always_inline]] inline void scan_face(const mesh::TriMesh& mesh, const Vec3* points,
                                             const std::uint8_t* flagged, int fi,
                                             FaceTree::Box& box, ScanLanes& lanes,
                                             std::size_t& boundary) {
    const FaceRing r = ring_of(mesh, fi);
    const Lanes3 p0 = lanes_of(points[mesh.to_vertex_handle(r.h0).idx()]);
    const Lanes3 p1 = lanes_of(points[mesh.to_vertex_handle(r.h1).idx()]);
    const Lanes3 p2 = lanes_of(points[mesh.to_vertex_handle(r.h2).idx()]);
    const BoxLanes b = box_lanes(p0, p1, p2);
    store_box(b, box);
    lanes.add_centre(b);
    lanes.add_abs(b);
    boundary += static_cast<std::size_t>((r.across0 < 0) + (r.across1 < 0) + (r.across2 < 0));
    // The face's edges: h0 runs p2 -> p0, h1 p0 -> p1, h2 p1 -> p2, |d|² the same either way
    // along an edge. An edge counts unless a face on either side is flagged.
    if (edge_counts<kFlagged>(flagged, fi, r.across0)) lanes.add_length(sqrdist_sd(p0, p2));
    if (edge_counts<kFlagged>(flagged, fi, r.across1)) lanes.add_length(sqrdist_sd(p1, p0));
    if (edge_counts<kFlagged>(flagged, fi, r.across2)) lanes.add_length(sqrdist_sd(p2, p1));
}
#else
/// The pass's running measures.
class ScanLanes {
public:
    void add_centre(const FaceTree::Box& b) {
        const auto c = centre_of(b);
        for (int a = 0; a < 3; ++a) lo_[a] = std::min(lo_[a], double(c[a]));
        for (int a = 0; a < 3; ++a) hi_[a] = std::max(hi_[a], double(c[a]));
    }
    void add_abs(const FaceTree::Box& b) { max_abs_ = std::max(max_abs_, max_abs_of(b)); }
    void add_length(double l) { longest_ = std::max(longest_, l); }
    void write(FaceScan& out) const {
        for (int a = 0; a < 3; ++a) out.centre_lo[a] = lo_[a], out.centre_hi[a] = hi_[a];
        out.longest_sq = longest_;
        out.max_abs = max_abs_;
    }

private:
    double lo_[3] = {1e300, 1e300, 1e300}, hi_[3] = {-1e300, -1e300, -1e300};
    double longest_ = 0.0, max_abs_ = 0.0;
};

template <bool kFlagged>
[[gnu::always_inline]] inline void scan_face(const mesh::TriMesh& mesh, const Vec3* points,
                                             const std::uint8_t* flagged, int fi,
                                             FaceTree::Box& box, ScanLanes& lanes,
                                             std::size_t& boundary) {
    const FaceRing r = ring_of(mesh, fi);
    const Vec3& p0 = points[mesh.to_vertex_handle(r.h0).idx()];
    const Vec3& p1 = points[mesh.to_vertex_handle(r.h1).idx()];
    const Vec3& p2 = points[mesh.to_vertex_handle(r.h2).idx()];
    box = rounded_box(p0, p1, p2);
    lanes.add_centre(box);
    lanes.add_abs(box);
    boundary += static_cast<std::size_t>((r.across0 < 0) + (r.across1 < 0) + (r.across2 < 0));
    if (edge_counts<kFlagged>(flagged, fi, r.across0)) lanes.add_length(sqrdist(p0, p2));
    if (edge_counts<kFlagged>(flagged, fi, r.across1)) lanes.add_length(sqrdist(p1, p0));
    if (edge_counts<kFlagged>(flagged, fi, r.across2)) lanes.add_length(sqrdist(p2, p1));
}
#endif

/// The pass over the faces: each live face's box into boxes[0, count), in face order, and the
/// measures of FaceScan. While no face is deleted the loop keeps no list of faces (a box's face
/// is its position).
template <bool kFlagged>
FaceScan scan_faces(const mesh::TriMesh& mesh, const std::uint8_t* flagged, FaceTree::Box* boxes) {
    FaceScan out;
    ScanLanes lanes;
    const auto nf = static_cast<int>(mesh.n_faces());
    const Vec3* const points = mesh.points();
    const OpenMesh::Attributes::StatusInfo* const status =
        mesh.property(mesh.face_status_pph()).data_vector().data();
    std::size_t count = 0, boundary = 0;
    int fi = 0;
    for (; fi < nf && !status[fi].deleted(); ++fi)
        scan_face<kFlagged>(mesh, points, flagged, fi, boxes[count++], lanes, boundary);
    if (fi < nf) {
        out.every_face_live = false;
        out.faces_of.resize(count);
        std::iota(out.faces_of.begin(), out.faces_of.end(), 0);
        for (; fi < nf; ++fi) {
            if (status[fi].deleted()) continue;
            scan_face<kFlagged>(mesh, points, flagged, fi, boxes[count++], lanes, boundary);
            out.faces_of.push_back(fi);
        }
    }
    lanes.write(out);
    out.count = count;
    out.boundary_halfedges = boundary;
    return out;
}

/// Whether any of the n bytes at p is non-zero, eight at a time.
bool any_nonzero(const std::uint8_t* p, std::size_t n) {
    std::uint64_t any = 0;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t w;
        std::memcpy(&w, p + i, sizeof w);
        any |= w;
    }
    for (; i < n; ++i) any |= p[i];
    return any != 0;
}

/// Whether the pass met every edge from a face, so that its longest edge is the mesh's: no
/// element is deleted and the faces account for every edge (interior edges twice, boundary
/// edges once).
bool scan_met_every_edge(const mesh::TriMesh& mesh, const FaceScan& scan) {
    if (!scan.every_face_live) return false;
    const std::size_t ne = mesh.n_edges();
    const OpenMesh::Attributes::StatusInfo* const edge_status =
        mesh.property(mesh.edge_status_pph()).data_vector().data();
    std::size_t live_edges = 0;
    for (std::size_t ei = 0; ei < ne; ++ei) live_edges += !edge_status[ei].deleted();
    return live_edges == ne && 3 * scan.count == 2 * live_edges - scan.boundary_halfedges;
}

}  // namespace

namespace {

// A leaf's box folded from an empty one box by box (std::min / std::max in order: a NaN ignored
// as enlarge ignores it), then quantised with its group's other leaves.
class LeafBox {
public:
#if defined(__SSE2__)
    // Folds `box` in: minps(by, b) is std::min(b, by), maxps(by, b) std::max(b, by). Lanes lo0
    // lo1 lo2 (hi0) and hi0 hi1 hi2 (hi2).
    void add(const FaceTree::Box& box) {
        const auto* const f = reinterpret_cast<const float*>(&box);
        const __m128 head = _mm_loadu_ps(f), tail = _mm_loadu_ps(f + 2);  // lo0-hi0, lo2-hi2
        lo_ = _mm_min_ps(head, lo_);
        hi_ = _mm_max_ps(_mm_shuffle_ps(tail, tail, _MM_SHUFFLE(3, 3, 2, 1)), hi_);
    }
    FaceTree::Box box() const {
        float lo[4], hi[4];
        _mm_storeu_ps(lo, lo_);
        _mm_storeu_ps(hi, hi_);
        FaceTree::Box b;
        for (int a = 0; a < 3; ++a) b.lo[a] = lo[a], b.hi[a] = hi[a];
        return b;
    }

private:
    __m128 lo_ = _mm_set1_ps(kInf), hi_ = _mm_set1_ps(-kInf);
#else
    void add(const FaceTree::Box& box) {
        for (int a = 0; a < 3; ++a) {
            b_.lo[a] = std::min(b_.lo[a], box.lo[a]);
            b_.hi[a] = std::max(b_.hi[a], box.hi[a]);
        }
    }
    FaceTree::Box box() const { return b_; }

private:
    FaceTree::Box b_{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
#endif
};

}  // namespace

double FaceTree::build(const mesh::TriMesh& mesh, const std::uint8_t* flagged_faces) {
    clear_for_build();
    // One pass over the faces: their boxes, the box of their centres and the longest edge; then
    // each box's Morton code in that box, the sort, the gather into the leaves and the levels
    // above. The scratch arrays are written before they are read: no zero-filling.
    const std::size_t capacity = mesh.n_faces();
    // Each live face's box in face order (a face's number is its position while every face is
    // live; scan.faces_of holds them from the first deleted face on). From the ordinary heap,
    // advised for huge pages: its first touch takes 12 faults instead of 6,000 on the 1M foot
    // (1.6 us each on this VM: 10 ms of a 70 ms build), and once freed it stays in the heap for
    // the stamps' and the inserts' reserves that follow, as 4 KiB pages do (a HugePageAllocator
    // block is unmapped: those reserves then page-faulted, 2 ms more in the build and in the idle
    // steps).
    auto unsorted = std::make_unique_for_overwrite<Box[]>(capacity);
    advise_huge_pages(unsorted.get(), capacity * sizeof(Box));
    const bool any_flagged = flagged_faces != nullptr && any_nonzero(flagged_faces, capacity);
    const FaceScan scan = any_flagged ? scan_faces<true>(mesh, flagged_faces, unsorted.get())
                                      : scan_faces<false>(mesh, nullptr, unsorted.get());
    const double longest_edge_sq = scan_met_every_edge(mesh, scan) ? scan.longest_sq : -1.0;
    max_abs_ = scan.max_abs;
    const std::size_t count = scan.count;
    if (count == 0) return longest_edge_sq;
    quantise_codes(scan.centre_lo, scan.centre_hi);
    // The sort's two key arrays, 12 bytes a face each, in one scratch block (advised for huge
    // pages as `unsorted` is): the scratch keys in its first half, the sorted keys in its second.
    static_assert(sizeof(Keyed) == 12);
    auto keys = std::make_unique_for_overwrite<unsigned char[]>(2 * sizeof(Keyed) * count);
    advise_huge_pages(keys.get(), 2 * sizeof(Keyed) * count);
    Keyed* const scratch = reinterpret_cast<Keyed*>(keys.get());
    Keyed* const keyed = reinterpret_cast<Keyed*>(keys.get() + sizeof(Keyed) * count);
    write_codes(unsorted.get(), count, scratch);
    if (const Keyed* sorted = radix_sort(scratch, keyed, count); sorted != keyed)
        std::memmove(keyed, sorted, count * sizeof(Keyed));  // an even number of passes ran
    const int depth = size_levels(count);
    gather_leaves(unsorted.get(), keys.get() + sizeof(Keyed) * count, count,
                  scan.every_face_live ? nullptr : scan.faces_of.data());
    keys.reset();
    unsorted.reset();
    for (std::uint32_t j = 0; j < leaves_; j += kCoarseStride)
        coarse_codes_.push_back(leaf_codes_[j]);
    fill_upper_levels(depth);
    extra_head_.assign(leaves_, -1);
    return longest_edge_sq;
}

void FaceTree::clear_for_build() {
    margin_m_ = 0.0;
    leaf_faces_.clear();
    leaf_groups_.clear();
    groups_.clear();
    level_first_.clear();
    max_abs_ = 0.0;
    leaf_codes_.clear();
    coarse_codes_.clear();
    extra_head_.clear();
    extra_.clear();
    pending_.clear();
    leaves_ = padded_leaves_ = 0;
    last_leaf_ = 0;
}

void FaceTree::quantise_codes(const double* centre_lo, const double* centre_hi) {
    const Vec3 lo(centre_lo[0], centre_lo[1], centre_lo[2]);
    const Vec3 hi(centre_hi[0], centre_hi[1], centre_hi[2]);
    const Vec3 ext = hi - lo;
    for (int a = 0; a < 3; ++a) code_lo_[a] = lo[a];
    code_scale_ = 2097151.0 / std::max({ext[0], ext[1], ext[2], 1e-300});
}

int FaceTree::size_levels(std::size_t count) {
    leaves_ = static_cast<std::uint32_t>((count + kLeafItems - 1) / kLeafItems);
    padded_leaves_ = 1;
    int depth = 0;  // of the leaves in the binary tree
    while (padded_leaves_ < leaves_) padded_leaves_ *= 2, ++depth;
    // Stored levels: depth % 3, then every third level down to the leaves.
    std::size_t total = 0;
    for (int d = depth % kLevelStep; d <= depth; d += kLevelStep) {
        level_first_.push_back(total);
        total += std::max<std::size_t>(1, (std::size_t{1} << d) / kLanes);
    }
    Group empty{};  // no lane live
    groups_.assign(total, empty);
    leaf_groups_.resize(leaves_);
    leaf_faces_.resize(std::size_t{leaves_} * kLeafItems);
    leaf_codes_.resize(leaves_);
    return depth;
}

void FaceTree::gather_leaves(const Box* unsorted, const unsigned char* sorted_keys,
                             std::size_t count, const std::int32_t* faces_of) {
    const auto key_at = [sorted_keys](std::size_t k) {
        Keyed key;
        std::memcpy(&key, sorted_keys + 12 * k, sizeof key);
        return key;
    };
    const int leaves_level = last_level();
    // A gather from across the unsorted boxes, each one fetched a few ahead, leaf by leaf: the
    // leaf's faces and boxes, its group quantised from the boxes, its own box folded from them
    // (LeafBox) and quantised with its group's other leaves.
    constexpr std::size_t kAhead = 16;
    Box leaf_boxes[kLanes];
    for (std::uint32_t leaf = 0; leaf < leaves_; ++leaf) {
        const std::size_t first = leaf * std::size_t{kLeafItems};
        const std::size_t end = std::min<std::size_t>(count, first + kLeafItems);
        leaf_codes_[leaf] = key_at(first).code;
        Box boxes[kLeafItems];
        LeafBox b;
        for (std::size_t k = first; k < end; ++k) {
            if (k + kAhead < count) __builtin_prefetch(&unsorted[key_at(k + kAhead).index]);
            const std::uint32_t at = key_at(k).index;
            leaf_faces_[k] = faces_of == nullptr ? static_cast<std::int32_t>(at) : faces_of[at];
            boxes[k - first] = unsorted[at];
            b.add(unsorted[at]);
        }
        for (std::size_t k = end; k < first + kLeafItems; ++k) leaf_faces_[k] = -1;
        leaf_boxes[leaf % kLanes] = b.box();
        quantise_leaf(leaf_groups_[leaf], boxes, static_cast<std::uint32_t>(end - first),
                      leaf_boxes[leaf % kLanes]);
        if (leaf % kLanes == kLanes - 1 || leaf + 1 == leaves_)
            quantise(group_of(leaves_level, leaf), leaf_boxes, (2u << (leaf % kLanes)) - 1);
    }
}

void FaceTree::fill_upper_levels(int depth) {
    // Each stored node holds the kLanes nodes of the level below that form its group.
    // Each lane holds the box of the group below it, quantised with the group's other lanes.
    for (int level = last_level(); level-- > 0;) {
        const std::size_t nodes = std::size_t{1} << (depth % kLevelStep + kLevelStep * level);
        Box boxes[kLanes];
        std::uint32_t live = 0;
        for (std::size_t k = 0; k < nodes; ++k) {
            const Group& below = groups_[level_first_[static_cast<std::size_t>(level) + 1] + k];
            const auto lane = static_cast<std::uint32_t>(k % kLanes);
            if (below.live != 0) boxes[lane] = group_box(below), live |= 1u << lane;
            if (lane == kLanes - 1 || k + 1 == nodes) {
                quantise(group_of(level, static_cast<std::uint32_t>(k)), boxes, live);
                live = 0;
            }
        }
    }
}

void FaceTree::reserve(std::size_t faces) {
    const std::size_t n = extra_.size(), p = pending_.size();
    if (extra_.capacity() < n + p + faces) extra_.reserve(n + p + faces);
    if (pending_.capacity() < kPendingFaces) pending_.reserve(kPendingFaces);
}

void FaceTree::make_resident() {
    const std::size_t n = extra_.size(), p = pending_.size();
    extra_.resize(extra_.capacity());  // value-initialised: every page written
    extra_.resize(n);
    pending_.resize(pending_.capacity());
    pending_.resize(p);
}

void FaceTree::drop_inserts(std::size_t pending, std::size_t hung) noexcept {
    if (pending < pending_.size()) pending_.resize(pending);
    for (std::size_t k = hung; k < extra_.size(); ++k)
        for (int a = 0; a < 3; ++a)
            extra_[k].item.box.lo[a] = std::numeric_limits<float>::infinity(),
            extra_[k].item.box.hi[a] = -std::numeric_limits<float>::infinity();
}

void FaceTree::flush_pending(std::size_t max_faces) {
    const std::size_t n = std::min(max_faces, pending_.size());
    for (std::size_t k = 0; k < n; ++k) hang(pending_[k]);
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
}

void FaceTree::hang(const Item& item) {
    // The leaf whose Morton range holds the face's centre: near it, so its boxes grow little.
    const std::uint64_t code = code_of(centre_of(item.box).data());
    // A cut inserts its faces along the loop, so the leaf of the last insert often holds this
    // code too: the last leaf whose first code is not above it, as the search finds it.
    std::uint32_t leaf = last_leaf_;
    const bool same_leaf = leaf < leaves_ && leaf_codes_[leaf] <= code &&
                           (leaf + 1 == leaves_ || code < leaf_codes_[leaf + 1]);
    if (!same_leaf) {
        // Two steps: the coarse table (small enough to stay in cache), then one stride of leaves.
        const auto c = std::upper_bound(coarse_codes_.begin(), coarse_codes_.end(), code);
        const std::size_t block = c == coarse_codes_.begin() ? 0 : c - coarse_codes_.begin() - 1;
        const auto lo = leaf_codes_.begin() + static_cast<std::ptrdiff_t>(block * kCoarseStride);
        const auto hi = leaf_codes_.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(
                                                  leaf_codes_.size(), (block + 1) * kCoarseStride));
        const auto it = std::upper_bound(lo, hi, code);
        leaf = static_cast<std::uint32_t>(it == leaf_codes_.begin() ? 0
                                                                    : it - leaf_codes_.begin() - 1);
        last_leaf_ = leaf;
    }
    extra_.push_back(Extra{item, extra_head_[leaf]});
    extra_head_[leaf] = static_cast<std::int32_t>(extra_.size() - 1);
    max_abs_ = std::max(max_abs_, max_abs_of(item.box));
    // Up the stored levels while the box grows (a node holds its descendants' boxes).
    std::uint32_t node = leaf;
    Box box = item.box;
    for (int level = last_level(); level >= 0; --level, node /= kLanes)
        if (!enlarge(group_of(level, node), node % kLanes, box)) break;
}

std::size_t FaceTree::memory_bytes() const noexcept {
    return leaf_faces_.capacity() * sizeof(std::int32_t) +
           (leaf_groups_.capacity() + groups_.capacity()) * sizeof(Group) +
           level_first_.capacity() * sizeof(std::size_t) +
           (leaf_codes_.capacity() + coarse_codes_.capacity()) * sizeof(std::uint64_t) +
           extra_head_.capacity() * sizeof(std::int32_t) + extra_.capacity() * sizeof(Extra) +
           pending_.capacity() * sizeof(Item);
}

}  // namespace kerf::cut::detail
