// kerf::cut::FaceTree — a bounding-volume hierarchy over the faces of a mesh: built once per mesh
// (O(n), faces in Morton order of their centroids), updated incrementally as cuts add faces
// (a pending list during the cut, hung on the leaves from idle time),
// queried for the faces near a point or near a patch of a plane. Library-internal (used by
// CutContext); queries may report a face more than once, may report deleted faces and may report
// faces a little beyond the query (a leaf's boxes are quantised outwards): callers dedupe, skip
// and test the faces themselves.
//
// Why a tree and not a uniform grid: a query costs what lies near the point or the plane, however
// the triangles are shaped. A grid's cells are sized on the faces' extents, so long thin
// triangles put thousands of faces in every cell the plane crosses, and a localised cut of a
// 4M-triangle tube of such triangles cost 36x the same cut at 100k (issue 10, item 7).
//
// Storage: an implicit complete binary tree over leaves of kLeafItems faces each, in Morton order
// of the faces' centroids, of which only every third level is stored (the leaves, their ancestors
// 3, 6, ... levels up, and a top level of 1, 2 or 4 nodes): each stored node's kLanes
// descendants three levels down lie together as one Group, their boxes quantised to 8 bits
// against the group's own frame (64 bytes, one cache line), so a query descends three levels per
// cache line and tests the eight boxes at once. A leaf's own faces are a Group too (their boxes
// quantised the same way) beside their eight face numbers (32 bytes): a leaf costs a query one
// and a half cache lines, not the three and a half its faces' exact float boxes took (28 bytes a
// face), which on a 4M-triangle tube were most of the cut's cache misses (issue 10, item 7).
// Queries go level by level over the nodes still near (in order, in chunks), prefetching the
// next nodes' groups, so the cache misses of the many paths a plane query follows (128 columns
// of long thin faces on a 4M-triangle tube) overlap instead of following one another. A face
// inserted by a cut hangs on the leaf its centroid's Morton code falls in (one flat node pool,
// exact boxes) and enlarges the boxes on its path. About 15 bytes per face.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "display/cut/huge_page_allocator.hpp"
#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

/// A float not above x / not below x (rounding must never shrink a box or a query).
float round_down_float(double x);
float round_up_float(double x);

class FaceTree {
public:
    /// An axis-aligned box in float, rounded outwards from the double geometry it bounds, m.
    struct Box {
        float lo[3], hi[3];
    };

    /// Indexes every non-deleted face of `mesh` (O(n)). The same pass over the faces measures the
    /// longest edge that no flagged face borders (`flagged_faces`: one byte per face, non-zero =
    /// flagged, e.g. the cap tags; null = none) and returns its squared length, m², or -1 when
    /// that pass cannot tell (a deleted face or edge, an edge with no face): then measure it
    /// over the edges.
    double build(const mesh::TriMesh& mesh, const std::uint8_t* flagged_faces = nullptr);

    /// Makes room for `faces` more inserted faces (and the pending list's), so inserts during a
    /// cut do not reallocate.
    void reserve(std::size_t faces);

    /// Writes the room reserve() made once, so inserts during a cut do not page-fault either.
    void make_resident();

    /// reserve(faces), then make_resident().
    void reserve_resident(std::size_t faces) {
        reserve(faces);
        make_resident();
    }

    /// Inserted faces the reserved room still takes without reallocating.
    std::size_t spare_inserts() const noexcept {
        return extra_.capacity() - extra_.size() - pending_.size();
    }

    /// Faces the pending list holds (its room is reserved once: about 0.5 MB).
    static constexpr std::size_t kPendingFaces = std::size_t{1} << 14;

    /// Adds face `f` (a face created by a cut): its box goes on the pending list, O(1), which
    /// every query scans after the tree, until flush_pending() hangs it on its leaf; when the list
    /// is full, the face is hung on its leaf at once (O(tree depth)).
    void insert(const mesh::TriMesh& mesh, mesh::FaceHandle f) {
        if (leaves_ == 0) return;
        if (pending_.size() < pending_.capacity())
            pending_.push_back(item_of(mesh, f));
        else
            hang(item_of(mesh, f));
    }

    /// Faces inserted since the last flush.
    std::size_t pending() const noexcept { return pending_.size(); }

    /// Faces hung on leaves since the build (flushed, or inserted when the pending list was full).
    std::size_t hung() const noexcept { return extra_.size(); }

    /// Forgets the inserts made since pending() was `pending` and hung() was `hung`, with no
    /// flush in between (an undone edit: their faces no longer exist). Pending ones are dropped;
    /// ones hung since stay on their leaves with an empty box, so no query reports them.
    void drop_inserts(std::size_t pending, std::size_t hung) noexcept;

    /// For idle time: hangs up to `max_faces` pending faces on the leaves their centres' Morton
    /// codes fall in, enlarging the boxes on their paths. O(faces x tree depth).
    void flush_pending(std::size_t max_faces);

    /// Extra distance every query adds (vertices moved since indexing), m.
    void widen(double margin_m) noexcept { margin_m_ += margin_m; }

    /// Calls `visit(face_index)` for every face whose bounding box comes within `radius_m` of `p`
    /// (and for some a little farther: see the file comment).
    template <class Visit>
    void for_each_near_point(const Vec3& p, double radius_m, Visit&& visit) const;

    /// Calls `visit(face_index)` for every face whose bounding box comes within `slack_m` of the
    /// plane and of the box around the patch of `plane` whose frame coordinates lie in [lo, hi]
    /// (and for some a little farther: see the file comment).
    template <class Visit>
    void for_each_near_plane(const Plane& plane, const Vec2& lo, const Vec2& hi, double slack_m,
                             Visit&& visit) const;

    /// Bytes held (capacity of every array).
    std::size_t memory_bytes() const noexcept;

    /// Whether plane queries test eight lanes at once (AVX2, where the CPU has it: the default)
    /// or four (SSE); returns the previous setting. Both report the same faces: for tests, which
    /// check each way.
    static bool set_wide_group_tests(bool on) noexcept;

private:
    static constexpr std::uint32_t kLeafItems = 8;
    static constexpr std::uint32_t kCoarseStride = 64;
    /// Stored nodes three binary levels apart: a node's kLanes descendants there form a Group.
    static constexpr std::uint32_t kLanes = 8;
    static_assert(kLeafItems == kLanes);  // a leaf's faces are one Group's lanes
    static constexpr int kLevelStep = 3;
    /// Nodes a query holds per level before it descends (a chunk on the stack, 1 KiB).
    static constexpr std::size_t kChunk = 256;
    /// How many nodes ahead a query prefetches the groups (or leaf items) it will test.
    static constexpr std::size_t kPrefetchAhead = 16;
    struct Item {
        std::int32_t face;
        Box box;
    };
    struct Extra {
        Item item;
        std::int32_t next;
    };
    /// kLanes boxes, m, each bound quantised to 8 bits against the group's frame: on axis a,
    /// lane k spans [bound(a, qlo[a][k]), bound(a, qhi[a][k])], bound(a, q) = origin[a] + q x
    /// 2^step_exp[a] in float (the product exact, the sum rounded once, as the group tests
    /// compute it), and quantise() picks every q so that its bound lies outside the box it
    /// stands for: a quantised box never shrinks. Lanes whose bit in `live` is clear hold no box
    /// and pass no test. An "open" group (a box with a NaN or an infinite coordinate) has a NaN
    /// origin: every bound is NaN, and every live lane passes every test.
    struct alignas(64) Group {
        float origin[3];
        std::int8_t step_exp[3];
        std::uint8_t live;
        std::uint8_t qlo[3][kLanes];
        std::uint8_t qhi[3][kLanes];
    };
    static_assert(sizeof(Group) == 64);
    /// A plane query as a group test takes it, in float, rounded so that it never rejects a box
    /// the double test near() of for_each_near_plane would keep.
    struct PlaneLanes {
        float lo[3], hi[3];  ///< the patch's box, thickened
        float n[3], abs_n[3];
        float twice_c0;     ///< 2 n . point
        float twice_slack;  ///< 2 x slack, plus the bound on float rounding
    };
    /// A point query as a group test takes it (squared radius enlarged by the float rounding).
    struct PointLanes {
        float p[3];
        float r2;
    };
    // Which lanes of g pass a plane query: plane_mask_wide (8 lanes at once, AVX2) where the CPU
    // has it and set_wide_group_tests has not turned it off, else plane_mask_narrow (4 at once,
    // SSE; one at a time elsewhere). Both give the same masks.
    static std::uint32_t plane_mask(const Group& g, const PlaneLanes& q) noexcept;
    static std::uint32_t plane_mask_narrow(const Group& g, const PlaneLanes& q) noexcept;
    static std::uint32_t plane_mask_wide(const Group& g, const PlaneLanes& q) noexcept;
    static std::uint32_t point_mask(const Group& g, const PointLanes& q) noexcept;
    /// A bound on the float rounding of a group test's sums over coordinates of magnitude up to
    /// max_abs_, m.
    double float_error_m(double query_abs) const noexcept;

    static Item item_of(const mesh::TriMesh& mesh, mesh::FaceHandle f);
    // The item of face `face` with corners p0, p1, p2.
    static Item item_from(std::int32_t face, const Vec3& p0, const Vec3& p1, const Vec3& p2);
    // Hangs `item` on its leaf and enlarges the boxes up its path.
    void hang(const Item& item);
    // Grows b to hold `by`; whether it grew.
    static bool enlarge(Box& b, const Box& by) noexcept;
    // Grows lane `lane` of g to hold `by` (requantising the whole group when `by` leaves its
    // frame); whether it grew. When it grew, `by` becomes the box the parent's lane must now
    // hold: the lane's new box, or every lane's when the group was requantised.
    bool enlarge(Group& g, std::uint32_t lane, Box& by) noexcept;
    // Sets g to hold boxes[k] in lane k for every bit k of `live`, rounded outwards, and widens
    // max_abs_ to the quantised bounds.
    void quantise(Group& g, const Box* boxes, std::uint32_t live) noexcept;
    // quantise() for a leaf's faces, lanes [0, count) live, whose boxes together span `box`:
    // the same frames, the bounds found on four lanes at a time (a build quantises every leaf;
    // quantise() one lane at a time took 50 ms of a 1M-face build). Each bound still lies
    // outside the box it stands for, though not always at the nearest step.
    void quantise_leaf(Group& g, const Box* boxes, std::uint32_t count, const Box& box) noexcept;
    // The box lane k of g stands for (live lanes only).
    static Box lane_box(const Group& g, std::uint32_t k) noexcept;
    // The box holding every live lane of g (empty: lo = +inf, hi = -inf, when none is live).
    static Box group_box(const Group& g) noexcept;
    // Morton code of a point in the quantisation of the last build.
    std::uint64_t code_of(const float* point) const noexcept;
    // Writes {code_of(centre of boxes[i]), i} for each of the n boxes into keys (the sort's
    // 12-byte keys, face_tree.cpp).
    void write_codes(const Box* boxes, std::size_t n, void* keys) const noexcept;

    // The steps of build(), in order. Empties every array.
    void clear_for_build();
    // The Morton quantisation of the box [centre_lo, centre_hi] of the items' centres.
    void quantise_codes(const double* centre_lo, const double* centre_hi);
    // Sizes the leaves and the stored levels for `count` faces (groups empty, leaf codes
    // unwritten); the depth of the leaves in the binary tree.
    int size_levels(std::size_t count);
    // Writes the leaves' faces and their groups (sorted_keys' order: `count` 12-byte keys
    // {code, index} at 12k, the index into `unsorted`, whose face is faces_of[index], or the
    // index itself when faces_of is null), the leaves' codes and the leaves' boxes.
    void gather_leaves(const Box* unsorted, const unsigned char* sorted_keys, std::size_t count,
                       const std::int32_t* faces_of);
    // Each stored level above the leaves from the one below.
    void fill_upper_levels(int depth);

    std::uint32_t leaf_count() const noexcept { return leaves_; }
    // The group holding node k of stored level `level` (level 0 is the top).
    const Group& group_of(int level, std::uint32_t k) const noexcept {
        return groups_[level_first_[static_cast<std::size_t>(level)] + k / kLanes];
    }
    Group& group_of(int level, std::uint32_t k) noexcept {
        return groups_[level_first_[static_cast<std::size_t>(level)] + k / kLanes];
    }
    int last_level() const noexcept { return static_cast<int>(level_first_.size()) - 1; }

    // Tests the children groups of nodes[0, count) of stored level `level` with
    // `mask(group)`, in order, and descends into the children near; at the leaves, the faces
    // whose lanes pass `mask` are visited, then the hung extras passing `accept(item)`.
    template <class Mask, class Accept, class Visit>
    void descend(int level, const std::uint32_t* nodes, std::size_t count, const Mask& mask,
                 const Accept& accept, Visit& visit) const;
    // Visits, in leaf order (so in the same order whatever the stored levels), the faces passing
    // `mask` (built) or `accept` (hung) in the leaves whose boxes pass `mask`, then the pending
    // items passing `accept`.
    template <class Mask, class Accept, class Visit>
    void walk(const Mask& mask, const Accept& accept, Visit& visit) const;

    double margin_m_ = 0.0;
    double code_lo_[3] = {0, 0, 0};  // quantisation of centroids for Morton codes
    double code_scale_ = 0.0;
    double max_abs_ = 0.0;             // largest finite |coordinate| of any box, m
    std::uint32_t leaves_ = 0;         // leaves holding built items
    std::uint32_t padded_leaves_ = 0;  // power of two >= leaves_
    std::uint32_t last_leaf_ = 0;      // leaf of the last insert
    // Leaf j's faces (Morton order): their numbers at [j*kLeafItems, ...) (-1 past the last
    // face), their boxes as the lanes of leaf_groups_[j].
    std::vector<std::int32_t, HugePageAllocator<std::int32_t>> leaf_faces_;
    std::vector<Group, HugePageAllocator<Group>> leaf_groups_;
    std::vector<Group, HugePageAllocator<Group>> groups_;  // every stored level, top first
    std::vector<std::size_t> level_first_;                 // first group of each stored level
    std::vector<std::uint64_t> leaf_codes_;                // Morton code of each leaf's first item
    std::vector<std::uint64_t> coarse_codes_;  // every kCoarseStride-th of leaf_codes_ (cache-
                                               // resident first step of an insert's search)
    std::vector<std::int32_t> extra_head_;     // per leaf, -1 = none
    std::vector<Extra> extra_;
    std::vector<Item> pending_;  // inserted, not yet hung on a leaf (scanned by every query)
};

template <class Mask, class Accept, class Visit>
void FaceTree::descend(int level, const std::uint32_t* nodes, std::size_t count, const Mask& mask,
                       const Accept& accept, Visit& visit) const {
    if (level == last_level()) {
        // nodes are leaves: their faces' group and numbers, prefetched a few leaves ahead.
        for (std::size_t i = 0; i < count; ++i) {
            if (i + kPrefetchAhead < count) {
                const std::uint32_t ahead = nodes[i + kPrefetchAhead];
                if (ahead < leaves_) {
                    __builtin_prefetch(&leaf_groups_[ahead]);
                    __builtin_prefetch(&leaf_faces_[ahead * std::size_t{kLeafItems}]);
                    __builtin_prefetch(&extra_head_[ahead]);
                }
            }
            const std::uint32_t leaf = nodes[i];
            if (leaf >= leaves_) continue;
            const std::int32_t* const faces = &leaf_faces_[leaf * std::size_t{kLeafItems}];
            for (std::uint32_t m = mask(leaf_groups_[leaf]); m != 0; m &= m - 1)
                visit(faces[std::countr_zero(m)]);
            for (std::int32_t n = extra_head_[leaf]; n >= 0; n = extra_[n].next)
                if (accept(extra_[n].item)) visit(extra_[n].item.face);
        }
        return;
    }
    std::uint32_t children[kChunk];
    std::size_t n = 0;
    for (std::size_t i = 0; i < count; ++i) {
        if (i + kPrefetchAhead < count) {
            const char* p = reinterpret_cast<const char*>(
                &group_of(level + 1, nodes[i + kPrefetchAhead] * kLanes));
            for (std::size_t b = 0; b < sizeof(Group); b += 64) __builtin_prefetch(p + b);
        }
        for (std::uint32_t m = mask(group_of(level + 1, nodes[i] * kLanes)); m != 0; m &= m - 1)
            children[n++] = nodes[i] * kLanes + static_cast<std::uint32_t>(std::countr_zero(m));
        if (n + kLanes > kChunk) {
            descend(level + 1, children, n, mask, accept, visit);
            n = 0;
        }
    }
    if (n > 0) descend(level + 1, children, n, mask, accept, visit);
}

template <class Mask, class Accept, class Visit>
void FaceTree::walk(const Mask& mask, const Accept& accept, Visit& visit) const {
    if (!groups_.empty()) {
        // Only live lanes pass a group test. The top group's lanes past its 1, 2 or 4 nodes,
        // whose children do not exist, are never live, and masked off here as well; lower
        // levels are complete (their empty lanes have children, empty too) and leaves past the
        // built ones are skipped.
        const std::uint32_t top_nodes = padded_leaves_ >> (kLevelStep * last_level());
        std::uint32_t top[kLanes];
        std::size_t n = 0;
        for (std::uint32_t m = mask(groups_[0]) & ((1u << top_nodes) - 1); m != 0; m &= m - 1)
            top[n++] = static_cast<std::uint32_t>(std::countr_zero(m));
        descend(0, top, n, mask, accept, visit);
    }
    for (const Item& e : pending_)
        if (accept(e)) visit(e.face);
}

template <class Visit>
void FaceTree::for_each_near_point(const Vec3& p, double radius_m, Visit&& visit) const {
    const double r = radius_m + margin_m_;
    auto near = [&](const Box& b) {
        double d2 = 0.0;
        for (int a = 0; a < 3; ++a) {
            const double below = b.lo[a] - p[a], above = p[a] - b.hi[a];
            const double d = below > 0 ? below : (above > 0 ? above : 0.0);
            d2 += d * d;
        }
        return d2 <= r * r;
    };
    PointLanes q;
    for (int a = 0; a < 3; ++a) q.p[a] = static_cast<float>(p[a]);
    const double padded =
        r + float_error_m(std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}));
    q.r2 = static_cast<float>(padded * padded * (1.0 + 1e-6));
    auto mask = [&](const Group& g) { return point_mask(g, q); };
    auto accept = [&](const Item& e) { return near(e.box); };
    walk(mask, accept, visit);
}

template <class Visit>
void FaceTree::for_each_near_plane(const Plane& plane, const Vec2& lo2, const Vec2& hi2,
                                   double slack_m, Visit&& visit) const {
    const double s = slack_m + margin_m_;
    const Vec3& n = plane.normal();
    const double c0 = OpenMesh::dot(n, plane.point());
    // The patch's 3-D box, thickened by the slack.
    Vec3 bl(1e300, 1e300, 1e300), bh(-1e300, -1e300, -1e300);
    for (int c = 0; c < 4; ++c) {
        const Vec3 q = plane.to_3d(Vec2((c & 1) ? hi2[0] : lo2[0], (c & 2) ? hi2[1] : lo2[1]));
        bl.minimize(q);
        bh.maximize(q);
    }
    bl -= Vec3(s, s, s);
    bh += Vec3(s, s, s);
    auto near = [&](const Box& b) {
        double centre = 0.0, extent = 0.0;
        for (int a = 0; a < 3; ++a) {
            if (b.lo[a] > bh[a] || b.hi[a] < bl[a]) return false;
            centre += n[a] * 0.5 * (double(b.lo[a]) + b.hi[a]);
            extent += std::abs(n[a]) * 0.5 * (double(b.hi[a]) - b.lo[a]);
        }
        return std::abs(centre - c0) <= extent + s;
    };
    PlaneLanes q;
    for (int a = 0; a < 3; ++a) {
        q.lo[a] = round_down_float(bl[a]);
        q.hi[a] = round_up_float(bh[a]);
        q.n[a] = static_cast<float>(n[a]);
        q.abs_n[a] = std::abs(q.n[a]);
    }
    q.twice_c0 = static_cast<float>(2.0 * c0);
    q.twice_slack = static_cast<float>(2.0 * (s + float_error_m(std::abs(c0))) * (1.0 + 1e-6));
    auto mask = [&](const Group& g) { return plane_mask(g, q); };
    auto accept = [&](const Item& e) { return near(e.box); };
    walk(mask, accept, visit);
}

}  // namespace kerf::cut::detail
