#include "display/cut/face_tree.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace kerf::cut::detail {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The float next to finite f towards -inf / +inf: std::nextafter's value without its library
// call (an insert rounds six coordinates; the call was a tenth of an insert).
float next_down(float f) {
    if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>(f > 0.0f ? bits - 1 : bits + 1);
}
float next_up(float f) {
    if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>(f > 0.0f ? bits + 1 : bits - 1);
}

// A float not above x / not below x (float rounding must never shrink a box). Only a finite
// float is stepped (NaN and infinities stay as std::nextafter leaves them).
float round_down(double x) {
    const auto f = static_cast<float>(x);
    if (!(static_cast<double>(f) > x)) return f;
    return std::isfinite(f) ? next_down(f) : std::nextafter(f, -kInf);
}
float round_up(double x) {
    const auto f = static_cast<float>(x);
    if (!(static_cast<double>(f) < x)) return f;
    return std::isfinite(f) ? next_up(f) : std::nextafter(f, kInf);
}

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

struct Keyed {
    std::uint64_t code;
    std::uint32_t index;
};

// Stable LSD radix sort by code (63 bits used), 16 bits per pass: O(n).
void radix_sort(std::vector<Keyed>& v) {
    std::vector<Keyed> tmp(v.size());
    std::vector<std::uint32_t> count(1u << 16);
    for (int pass = 0; pass < 4; ++pass) {
        const int shift = 16 * pass;
        std::fill(count.begin(), count.end(), 0u);
        for (const Keyed& k : v) ++count[(k.code >> shift) & 0xffff];
        if (count[v.empty() ? 0 : (v.front().code >> shift) & 0xffff] == v.size()) continue;
        std::uint32_t sum = 0;
        for (auto& c : count) {
            const std::uint32_t here = c;
            c = sum;
            sum += here;
        }
        for (const Keyed& k : v) tmp[count[(k.code >> shift) & 0xffff]++] = k;
        v.swap(tmp);
    }
}

FaceTree::Box empty_box() {
    FaceTree::Box b;
    for (int a = 0; a < 3; ++a) b.lo[a] = kInf, b.hi[a] = -kInf;
    return b;
}

}  // namespace

FaceTree::Item FaceTree::item_of(const mesh::TriMesh& mesh, mesh::FaceHandle f) {
    // The three corners straight from the halfedge arrays (a circulator costs several times more).
    const mesh::HalfedgeHandle h0 = mesh.halfedge_handle(f);
    const mesh::HalfedgeHandle h1 = mesh.next_halfedge_handle(h0);
    const mesh::HalfedgeHandle h2 = mesh.next_halfedge_handle(h1);
    const Vec3& p0 = mesh.point(mesh.to_vertex_handle(h0));
    const Vec3& p1 = mesh.point(mesh.to_vertex_handle(h1));
    const Vec3& p2 = mesh.point(mesh.to_vertex_handle(h2));
    Vec3 lo = p0, hi = p0;
    lo.minimize(p1);
    hi.maximize(p1);
    lo.minimize(p2);
    hi.maximize(p2);
    Item e;
    e.face = f.idx();
    for (int a = 0; a < 3; ++a) e.box.lo[a] = round_down(lo[a]), e.box.hi[a] = round_up(hi[a]);
    return e;
}

std::uint64_t FaceTree::code_of(const float* point) const noexcept {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const double x = (point[a] - code_lo_[a]) * code_scale_;
        const double q = x >= 0.0 ? std::min(x, 2097151.0) : 0.0;  // NaN -> 0
        code |= spread_bits(static_cast<std::uint64_t>(q)) << a;
    }
    return code;
}

namespace {

// The centre of an item's box.
std::array<float, 3> centre_of(const FaceTree::Box& b) {
    return {0.5f * (b.lo[0] + b.hi[0]), 0.5f * (b.lo[1] + b.hi[1]), 0.5f * (b.lo[2] + b.hi[2])};
}

}  // namespace

bool FaceTree::enlarge(Box& b, const Box& by) noexcept {
    bool grew = false;
    for (int a = 0; a < 3; ++a) {
        grew |= by.lo[a] < b.lo[a] || by.hi[a] > b.hi[a];
        b.lo[a] = std::min(b.lo[a], by.lo[a]);
        b.hi[a] = std::max(b.hi[a], by.hi[a]);
    }
    return grew;
}

void FaceTree::build(const mesh::TriMesh& mesh) {
    margin_m_ = 0.0;
    items_.clear();
    nodes_.clear();
    leaf_codes_.clear();
    coarse_codes_.clear();
    extra_head_.clear();
    extra_.clear();
    pending_.clear();
    leaves_ = padded_leaves_ = 0;
    last_leaf_ = 0;
    // Items, the box of their centres, and each item's Morton code in that box.
    std::vector<Item> unsorted;
    unsorted.reserve(mesh.n_faces());
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (auto f : mesh.faces()) {
        unsorted.push_back(item_of(mesh, f));
        const auto c = centre_of(unsorted.back().box);
        lo.minimize(Vec3(c[0], c[1], c[2]));
        hi.maximize(Vec3(c[0], c[1], c[2]));
    }
    if (unsorted.empty()) return;
    const Vec3 ext = hi - lo;
    for (int a = 0; a < 3; ++a) code_lo_[a] = lo[a];
    code_scale_ = 2097151.0 / std::max({ext[0], ext[1], ext[2], 1e-300});
    std::vector<Keyed> keyed(unsorted.size());
    for (std::size_t i = 0; i < unsorted.size(); ++i)
        keyed[i] = Keyed{code_of(centre_of(unsorted[i].box).data()), static_cast<std::uint32_t>(i)};
    radix_sort(keyed);
    items_.resize(unsorted.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) items_[i] = unsorted[keyed[i].index];
    std::vector<Item>().swap(unsorted);

    leaves_ = static_cast<std::uint32_t>((items_.size() + kLeafItems - 1) / kLeafItems);
    leaf_codes_.resize(leaves_);
    for (std::uint32_t j = 0; j < leaves_; ++j) leaf_codes_[j] = keyed[j * kLeafItems].code;
    for (std::uint32_t j = 0; j < leaves_; j += kCoarseStride)
        coarse_codes_.push_back(leaf_codes_[j]);
    padded_leaves_ = 1;
    while (padded_leaves_ < leaves_) padded_leaves_ *= 2;
    nodes_.assign(2 * std::size_t{padded_leaves_} - 1, empty_box());
    const std::uint32_t first = first_leaf_node();
    for (std::size_t k = 0; k < items_.size(); ++k)
        enlarge(nodes_[first + k / kLeafItems], items_[k].box);
    for (std::uint32_t i = first; i-- > 0;) {
        nodes_[i] = nodes_[2 * i + 1];
        enlarge(nodes_[i], nodes_[2 * i + 2]);
    }
    extra_head_.assign(leaves_, -1);
}

void FaceTree::reserve_resident(std::size_t faces) {
    const std::size_t n = extra_.size(), p = pending_.size();
    if (extra_.capacity() < n + p + faces) extra_.reserve(n + p + faces);
    extra_.resize(extra_.capacity());  // value-initialised: every page written
    extra_.resize(n);
    if (pending_.capacity() < kPendingFaces) {
        pending_.reserve(kPendingFaces);
        pending_.resize(pending_.capacity());
        pending_.resize(p);
    }
}

void FaceTree::insert(const mesh::TriMesh& mesh, mesh::FaceHandle f) {
    if (leaves_ == 0) return;
    if (pending_.size() < pending_.capacity())
        pending_.push_back(item_of(mesh, f));
    else
        hang(item_of(mesh, f));
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
    // Up the path while the box grows (a parent holds its child's box).
    for (std::uint32_t i = first_leaf_node() + leaf; enlarge(nodes_[i], item.box) && i > 0;)
        i = (i - 1) / 2;
}

std::size_t FaceTree::memory_bytes() const noexcept {
    return items_.capacity() * sizeof(Item) + nodes_.capacity() * sizeof(Box) +
           (leaf_codes_.capacity() + coarse_codes_.capacity()) * sizeof(std::uint64_t) +
           extra_head_.capacity() * sizeof(std::int32_t) + extra_.capacity() * sizeof(Extra) +
           pending_.capacity() * sizeof(Item);
}

}  // namespace kerf::cut::detail
