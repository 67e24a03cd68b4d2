// kerf::cut::FaceTree — a bounding-volume hierarchy over the faces of a mesh: built once per mesh
// (O(n), faces in Morton order of their centroids), updated incrementally as cuts add faces
// (a pending list during the cut, hung on the leaves from idle time),
// queried for the faces near a point or near a patch of a plane. Library-internal (used by
// CutContext); queries may report a face more than once and may report deleted faces: callers
// dedupe and skip.
//
// Why a tree and not a uniform grid: a query costs what lies near the point or the plane, however
// the triangles are shaped. A grid's cells are sized on the faces' extents, so long thin
// triangles put thousands of faces in every cell the plane crosses, and a localised cut of a
// 4M-triangle tube of such triangles cost 36x the same cut at 100k (issue 10, item 7).
//
// Storage: the faces as items {face, float bounding box} in Morton order of their centroids,
// kLeafItems per leaf; an implicit complete binary tree of boxes over the leaves (node i has
// children 2i+1, 2i+2); a face inserted by a cut hangs on the leaf its centroid's Morton code
// falls in (one flat node pool) and enlarges the boxes on its path. About 36 bytes per face.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

class FaceTree {
public:
    /// An axis-aligned box in float, rounded outwards from the double geometry it bounds, m.
    struct Box {
        float lo[3], hi[3];
    };

    /// Indexes every non-deleted face of `mesh` (O(n)).
    void build(const mesh::TriMesh& mesh);

    /// Makes room for `faces` more inserted faces and writes it once, so inserts during a cut
    /// neither reallocate nor page-fault.
    void reserve_resident(std::size_t faces);

    /// Inserted faces the reserved room still takes without reallocating.
    std::size_t spare_inserts() const noexcept {
        return extra_.capacity() - extra_.size() - pending_.size();
    }

    /// Faces the pending list holds (its room is reserved once: about 0.5 MB).
    static constexpr std::size_t kPendingFaces = std::size_t{1} << 14;

    /// Adds face `f` (a face created by a cut): its box goes on the pending list, O(1), which
    /// every query scans after the tree, until flush_pending() hangs it on its leaf; when the list
    /// is full, the face is hung on its leaf at once (O(tree depth)).
    void insert(const mesh::TriMesh& mesh, mesh::FaceHandle f);

    /// Faces inserted since the last flush.
    std::size_t pending() const noexcept { return pending_.size(); }

    /// For idle time: hangs up to `max_faces` pending faces on the leaves their centres' Morton
    /// codes fall in, enlarging the boxes on their paths. O(faces x tree depth).
    void flush_pending(std::size_t max_faces);

    /// Extra distance every query adds (vertices moved since indexing), m.
    void widen(double margin_m) noexcept { margin_m_ += margin_m; }

    /// Calls `visit(face_index)` for faces whose bounding box comes within `radius_m` of `p`.
    template <class Visit>
    void for_each_near_point(const Vec3& p, double radius_m, Visit&& visit) const;

    /// Calls `visit(face_index)` for faces whose bounding box comes within `slack_m` of the plane
    /// and of the box around the patch of `plane` whose frame coordinates lie in [lo, hi].
    template <class Visit>
    void for_each_near_plane(const Plane& plane, const Vec2& lo, const Vec2& hi, double slack_m,
                             Visit&& visit) const;

    /// Bytes held (capacity of every array).
    std::size_t memory_bytes() const noexcept;

private:
    static constexpr std::uint32_t kLeafItems = 8;
    static constexpr std::uint32_t kCoarseStride = 64;
    struct Item {
        std::int32_t face;
        Box box;
    };
    struct Extra {
        Item item;
        std::int32_t next;
    };
    static Item item_of(const mesh::TriMesh& mesh, mesh::FaceHandle f);
    // Hangs `item` on its leaf and enlarges the boxes up its path.
    void hang(const Item& item);
    // Grows b to hold `by`; whether it grew.
    static bool enlarge(Box& b, const Box& by) noexcept;
    // Morton code of a point in the quantisation of the last build.
    std::uint64_t code_of(const float* point) const noexcept;

    std::uint32_t leaf_count() const noexcept { return leaves_; }
    std::uint32_t first_leaf_node() const noexcept { return padded_leaves_ - 1; }

    // Visits the subtree nodes whose box passes `near(box)`; at each leaf, every item passing
    // `accept(item)`.
    template <class Near, class Accept, class Visit>
    void walk(const Near& near, const Accept& accept, Visit& visit) const;

    double margin_m_ = 0.0;
    double code_lo_[3] = {0, 0, 0};  // quantisation of centroids for Morton codes
    double code_scale_ = 0.0;
    std::uint32_t leaves_ = 0;                 // leaves holding built items
    std::uint32_t padded_leaves_ = 0;          // power of two >= leaves_
    std::uint32_t last_leaf_ = 0;              // leaf of the last insert
    std::vector<Item> items_;                  // Morton order; leaf j holds [j*kLeafItems, ...)
    std::vector<Box> nodes_;                   // 2 * padded_leaves_ - 1, empty boxes where no faces
    std::vector<std::uint64_t> leaf_codes_;    // Morton code of each leaf's first item
    std::vector<std::uint64_t> coarse_codes_;  // every kCoarseStride-th of leaf_codes_ (cache-
                                               // resident first step of an insert's search)
    std::vector<std::int32_t> extra_head_;     // per leaf, -1 = none
    std::vector<Extra> extra_;
    std::vector<Item> pending_;  // inserted, not yet hung on a leaf (scanned by every query)
};

template <class Near, class Accept, class Visit>
void FaceTree::walk(const Near& near, const Accept& accept, Visit& visit) const {
    if (nodes_.empty()) return;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    const std::uint32_t first_leaf = first_leaf_node();
    while (top > 0) {
        const std::uint32_t i = stack[--top];
        if (!near(nodes_[i])) continue;
        if (i < first_leaf) {
            stack[top++] = 2 * i + 2;
            stack[top++] = 2 * i + 1;
            continue;
        }
        const std::uint32_t leaf = i - first_leaf;
        if (leaf >= leaves_) continue;
        const std::size_t end = std::min<std::size_t>(items_.size(), (leaf + 1) * kLeafItems);
        for (std::size_t k = leaf * std::size_t{kLeafItems}; k < end; ++k)
            if (accept(items_[k])) visit(items_[k].face);
        for (std::int32_t n = extra_head_[leaf]; n >= 0; n = extra_[n].next)
            if (accept(extra_[n].item)) visit(extra_[n].item.face);
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
    auto accept = [&](const Item& e) { return near(e.box); };
    walk(near, accept, visit);
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
    auto accept = [&](const Item& e) { return near(e.box); };
    walk(near, accept, visit);
}

}  // namespace kerf::cut::detail
