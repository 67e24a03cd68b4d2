// Checks and helpers for sequential cuts (chevrons: two localised planes meeting on a line, the
// second through the first one's cap), shared by the cut property test and the chevron
// regression test (issue 10, item 2).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "display/cut/components.hpp"
#include "display/cut/section_plan.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/mesh_io.hpp"
#include "display/mesh/validate.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/slice_sweep.hpp"

namespace kerf::cut::testing {

/// The chevron's second limb: the plane through `through` (on the first plane) turned `angle_rad`
/// from `first` about the first plane's v axis.
inline Plane chevron_second_limb(const Plane& first, const Vec3& through, double angle_rad) {
    const Vec3 n2 = first.normal() * std::cos(angle_rad) + first.u() * std::sin(angle_rad);
    return *Plane::make(through, n2);
}

/// Volume of the piece of `ref` (already sliced on both slab planes) between the planes that
/// holds the face nearest to `p`, m^3 (0 when none lies between them). A rim vertex may lie
/// kSnapTolerances tolerances outside its plane (snapped). Nearest: by face centroid; with
/// `facing`, by the distance to the face itself, among the faces whose normal has a positive
/// component along `facing` (a point on an earlier cut's cap is on its twin too, facing away).
inline double between_piece_volume(const kerf::mesh::TriMesh& ref, const Plane& lower,
                                   const Plane& upper, const Vec3& p, double tolerance_m,
                                   const Vec3* facing = nullptr) {
    const double tol = kSnapTolerances * tolerance_m;
    double best_d = 1e300, volume = 0;
    for (const Body& b : find_components(ref)) {
        bool between = true;
        for (auto v : b.vertices)
            between &= lower.signed_distance(ref.point(v)) > -tol &&
                       upper.signed_distance(ref.point(v)) < tol;
        if (!between) continue;
        for (kerf::mesh::FaceHandle f : b.faces) {
            if (facing != nullptr && !(OpenMesh::dot(ref.calc_face_normal(f), *facing) > 0))
                continue;
            const double d = facing != nullptr ? cut::detail::distance_to_face(ref, f, p)
                                               : (face_centroid(ref, f) - p).norm();
            if (d < best_d) best_d = d, volume = b.volume_m3;
        }
    }
    return volume;
}

/// What a slab cut of `shape` on `plane`, `kerf_m` wide, from a seed at `seed_point` must remove,
/// found independently: a copy sliced on both slab planes and the piece between them that holds
/// the seed, m^3; -1 when a reference slice fails. `merges` (optional) gets the vertex merges of
/// the two reference slices: each moved the reference's surface too (volume_change_bound).
inline double slab_reference_removed_volume(const kerf::mesh::TriMesh& shape, const Plane& plane,
                                            double kerf_m, const Vec3& seed_point,
                                            const Vec3* facing = nullptr,
                                            std::uint32_t* merges = nullptr) {
    kerf::mesh::TriMesh ref = shape;
    CutContext ctx(ref);
    CrossSection cs;
    const Plane lower = plane.offset(-0.5 * kerf_m), upper = plane.offset(0.5 * kerf_m);
    const CutResult low = slice_by_plane(ctx, lower, cs);
    if (!low.ok()) return -1.0;
    const CutResult up = slice_by_plane(ctx, upper, cs);
    if (up.status != CutStatus::kOk && up.status != CutStatus::kPlaneMissesMesh) return -1.0;
    if (merges != nullptr) *merges = low.stats.vertices_merged + up.stats.vertices_merged;
    return between_piece_volume(ref, lower, upper, seed_point, ctx.tolerance_m(), facing);
}

/// A mesh of the given faces of `m` (positions only), for writing one piece.
inline kerf::mesh::TriMesh piece_mesh(const kerf::mesh::TriMesh& m, const Body& b) {
    return extract_faces(m, [&](kerf::mesh::FaceHandle f) {
        return std::binary_search(b.faces.begin(), b.faces.end(), f);
    });
}

/// Writes every piece of `m` in `format`, reads it back and checks it strictly.
inline void expect_pieces_round_trip(const kerf::mesh::TriMesh& m, mesh::Format format,
                                     const std::string& what) {
    for (const Body& b : group_cavities(find_components(m))) {
        const kerf::mesh::TriMesh piece = piece_mesh(m, b);
        const std::string bytes = mesh::serialize_mesh(piece, format, LengthUnit::kMillimetre);
        auto back = mesh::parse_mesh(std::as_bytes(std::span(bytes.data(), bytes.size())), format,
                                     LengthUnit::kMillimetre);
        ASSERT_TRUE(back) << what << ": " << to_string(format) << " piece does not reload";
        const mesh::ValidationReport v = mesh::validate(back->indexed);
        EXPECT_TRUE(v.closed && v.oriented && v.non_manifold_vertices == 0 &&
                    v.degenerate_triangles == 0 && back->detached_triangles == 0)
            << what << ": " << to_string(format) << " piece of " << b.faces.size()
            << " faces reloads with " << v.boundary_edges << " boundary, " << v.non_manifold_edges
            << " non-manifold edges, " << v.non_manifold_vertices << " non-manifold vertices, "
            << v.degenerate_triangles << " degenerate, " << back->detached_triangles << " detached";
    }
}

/// How many vertices made by the cuts (index >= `first_new`) lie within `tol` of another vertex,
/// except at exactly the same position (the two copies of a rim vertex, one per side): a cut
/// should reuse the existing vertex instead (issue 10, item 2), and `nearest` gets the smallest
/// such distance. O(V log V).
inline int close_new_vertices(const kerf::mesh::TriMesh& m, int first_new, double tol,
                              double& nearest) {
    std::vector<std::pair<double, int>> by_x;
    for (auto v : m.vertices()) by_x.emplace_back(m.point(v)[0], v.idx());
    std::sort(by_x.begin(), by_x.end());
    int close = 0;
    for (auto v : m.vertices()) {
        if (v.idx() < first_new) continue;
        const auto& p = m.point(v);
        auto it = std::lower_bound(by_x.begin(), by_x.end(), std::make_pair(p[0] - tol, -1));
        for (; it != by_x.end() && it->first <= p[0] + tol; ++it) {
            if (it->second == v.idx()) continue;
            const double d = (m.point(mesh::VertexHandle(it->second)) - p).norm();
            if (d > 0 && d <= tol) ++close, nearest = std::min(nearest, d);
        }
    }
    return close;
}

/// A seed on the line where `a` and `b` meet, on the surface (a face crossing both near it).
inline Seed seed_on_both(const kerf::mesh::TriMesh& m, const Plane& a, const Plane& b) {
    kerf::mesh::FaceHandle best;
    double best_d = 1e300;
    for (auto f : m.faces()) {
        int pa = 0, na = 0;
        double db = 0;
        for (auto v : m.fv_range(f)) {
            const double d = a.signed_distance(m.point(v));
            pa += d > 0, na += d < 0;
            db += b.signed_distance(m.point(v)) / 3.0;
        }
        if (pa && na && std::abs(db) < best_d) best_d = std::abs(db), best = f;
    }
    if (!best.is_valid()) return Seed{Vec3(0, 0, 0), kerf::mesh::FaceHandle(), 0.0};
    return Seed{face_centroid(m, best), best, -1.0};
}

}  // namespace kerf::cut::testing
