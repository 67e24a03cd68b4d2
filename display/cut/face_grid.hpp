// kerf::cut::FaceGrid — a uniform grid over face bounding boxes: built once per mesh (O(n)),
// updated incrementally as cuts add faces, queried for the faces near a point or near a patch of
// a plane. Library-internal (used by CutContext); queries may report a face more than once and
// may report deleted faces: callers dedupe and skip.
//
// Storage: an immutable CSR of the faces indexed at build time plus, per cell, a linked list of
// faces inserted since (one flat node pool; no per-cell allocation, no hash map). Each entry
// carries the face's bounding sphere, so queries reject most faces without touching the mesh.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

class FaceGrid {
public:
    /// Indexes every non-deleted face of `mesh` (O(n)); cells of about 3 mean face sizes.
    void build(const mesh::TriMesh& mesh);

    /// Makes room for `faces` more inserted faces (about two cells each) and writes it once,
    /// so inserts during a cut neither reallocate nor page-fault.
    void reserve_resident(std::size_t faces);

    /// Adds face `f` (a face created by a cut) to the cells its bounding box overlaps.
    void insert(const mesh::TriMesh& mesh, mesh::FaceHandle f);

    /// Extra distance every query adds (vertices moved since indexing), m.
    void widen(double margin_m) noexcept { margin_m_ += margin_m; }

    /// Calls `visit(face_index)` for faces whose bounding sphere comes within `radius_m` of `p`.
    template <class Visit>
    void for_each_near_point(const Vec3& p, double radius_m, Visit&& visit) const;

    /// Calls `visit(face_index)` for faces whose bounding sphere comes within `slack_m` of the
    /// plane, registered in cells along the patch of `plane` whose frame coordinates lie in [lo,
    /// hi].
    template <class Visit>
    void for_each_near_plane(const Plane& plane, const Vec2& lo, const Vec2& hi, double slack_m,
                             Visit&& visit) const;

    /// Number of cells (0 before build).
    std::size_t cell_count() const noexcept { return offsets_.empty() ? 0 : offsets_.size() - 1; }

private:
    struct Entry {
        std::int32_t face;
        float centre[3];  // bounding sphere, m (radius padded for float rounding)
        float radius;
    };
    struct Node {
        Entry entry;
        std::int32_t next;
    };
    static Entry entry_of(const mesh::TriMesh& mesh, mesh::FaceHandle f);

    int clamp_cell(double x, int axis) const noexcept;
    std::size_t cell_id(int i, int j, int k) const noexcept {
        return (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i;
    }
    template <class Accept, class Visit>
    void visit_cell(std::size_t c, const Accept& accept, Visit& visit) const;

    Vec3 origin_{0, 0, 0};
    double cell_m_ = 1.0;
    double margin_m_ = 0.0;
    int dims_[3] = {0, 0, 0};
    std::vector<std::uint32_t> offsets_;  // CSR: cell c holds faces_[offsets_[c] .. offsets_[c+1])
    std::vector<Entry> faces_;
    std::vector<std::int32_t> extra_head_;  // per cell, -1 = none
    std::vector<Node> extra_;
};

template <class Accept, class Visit>
void FaceGrid::visit_cell(std::size_t c, const Accept& accept, Visit& visit) const {
    for (std::uint32_t i = offsets_[c]; i < offsets_[c + 1]; ++i)
        if (accept(faces_[i])) visit(faces_[i].face);
    for (std::int32_t n = extra_head_[c]; n >= 0; n = extra_[n].next)
        if (accept(extra_[n].entry)) visit(extra_[n].entry.face);
}

template <class Visit>
void FaceGrid::for_each_near_point(const Vec3& p, double radius_m, Visit&& visit) const {
    if (offsets_.empty()) return;
    const double r = radius_m + margin_m_;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = clamp_cell(p[a] - r, a);
        hi[a] = clamp_cell(p[a] + r, a);
    }
    auto accept = [&](const Entry& e) {
        const double dx = e.centre[0] - p[0], dy = e.centre[1] - p[1], dz = e.centre[2] - p[2];
        const double reach = e.radius + r;
        return dx * dx + dy * dy + dz * dz <= reach * reach;
    };
    for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i) visit_cell(cell_id(i, j, k), accept, visit);
}

template <class Visit>
void FaceGrid::for_each_near_plane(const Plane& plane, const Vec2& lo2, const Vec2& hi2,
                                   double slack_m, Visit&& visit) const {
    if (offsets_.empty()) return;
    const double s = slack_m + margin_m_;
    const Vec3& n = plane.normal();
    // Walk columns along the two axes least aligned with the normal; in each column only the
    // cells the (thickened) plane passes through.
    int w = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(n[a]) > std::abs(n[w])) w = a;
    const int a0 = (w + 1) % 3, a1 = (w + 2) % 3;
    Vec3 bl(1e300, 1e300, 1e300), bh(-1e300, -1e300, -1e300);
    for (int c = 0; c < 4; ++c) {
        const Vec3 q = plane.to_3d(Vec2((c & 1) ? hi2[0] : lo2[0], (c & 2) ? hi2[1] : lo2[1]));
        bl.minimize(q);
        bh.maximize(q);
    }
    const int i0 = clamp_cell(bl[a0] - s, a0), i1 = clamp_cell(bh[a0] + s, a0);
    const int j0 = clamp_cell(bl[a1] - s, a1), j1 = clamp_cell(bh[a1] + s, a1);
    const double nw = n[w];
    const double c0 = OpenMesh::dot(n, plane.point());
    const double pad = s / std::abs(nw) + cell_m_ * 1e-9;
    auto accept = [&](const Entry& e) {
        const double d = n[0] * e.centre[0] + n[1] * e.centre[1] + n[2] * e.centre[2] - c0;
        return std::abs(d) <= e.radius + s;
    };
    int cell[3];
    for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
            double wl = 1e300, wh = -1e300;
            for (int c = 0; c < 4; ++c) {
                const double x = origin_[a0] + (i + (c & 1)) * cell_m_;
                const double y = origin_[a1] + (j + ((c >> 1) & 1)) * cell_m_;
                const double z = (c0 - n[a0] * x - n[a1] * y) / nw;
                wl = std::min(wl, z);
                wh = std::max(wh, z);
            }
            wl = std::max(wl - pad, bl[w] - s);
            wh = std::min(wh + pad, bh[w] + s);
            if (wl > wh) continue;
            const int k0 = clamp_cell(wl, w), k1 = clamp_cell(wh, w);
            cell[a0] = i;
            cell[a1] = j;
            for (int k = k0; k <= k1; ++k) {
                cell[w] = k;
                visit_cell(cell_id(cell[0], cell[1], cell[2]), accept, visit);
            }
        }
    }
}

}  // namespace kerf::cut::detail
