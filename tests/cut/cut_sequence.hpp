// A recorded sequence of cuts, replayed on one mesh as a training session would cut it: the
// regression tests that need the earlier cuts of a random sequence to reach the failing one
// (the slab_*_regression_test and merged_split_regression_test files) list them as hex floats.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include "display/cut/components.hpp"
#include "display/cut/context_state.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "tests/cut/chevron_checks.hpp"
#include "tests/cut/cut_test_util.hpp"
#include "tests/cut/slice_sweep.hpp"

namespace kerf::cut::testing {

/// One cut of a recorded sequence: kind 0-2 localised, 3 a chevron's second limb (localised,
/// no capacity growth before it), 4 full, 5 slab; each but a full cut seeded on the face the
/// recording's seed search found (the hint), as the display passes the triangle the blade hit, so
/// that a replay does not depend on how the library searches a seed without a face.
struct SeededCut {
    int kind;
    Vec3 point;   ///< plane point, m
    Vec3 normal;  ///< normalised by Plane::make
    Vec3 seed;    ///< m
    int hint;     ///< seed face index, -1 for none
};

/// The seed a recorded cut gives the library.
inline Seed seed_of(const SeededCut& c) {
    return Seed{c.seed, c.hint >= 0 ? mesh::FaceHandle(c.hint) : mesh::FaceHandle(), -1.0};
}

/// Applies `cuts` in order to `ctx` as sequential_cut_test made them (capacity grown before each
/// but a chevron's second limb; slabs `kerf_m` wide); the index of the first that ended in
/// kInternalError, or cuts.size() when none did. Refusals are allowed: they leave the mesh
/// unchanged (checked by the caller where it matters). The sequences were recorded before slices
/// put chords into the earlier caps they cross (cap_chords.hpp), and their face hints index the
/// mesh those cuts made: unless `cap_chords`, the replay cuts without chords (the context's
/// setting is restored after it).
inline std::size_t replay_cuts(CutContext& ctx, std::span<const SeededCut> cuts, double kerf_m,
                               bool cap_chords = false) {
    CrossSection cs;
    SlabCut slab;
    struct Restore {
        CutContext& ctx;
        bool was;
        ~Restore() { ctx.state().cap_chords = was; }
    } restore{ctx, ctx.state().cap_chords};
    ctx.state().cap_chords = cap_chords;
    for (std::size_t i = 0; i < cuts.size(); ++i) {
        const SeededCut& c = cuts[i];
        if (c.kind != 3) ctx.grow_capacity();
        const Plane plane = *Plane::make(c.point, c.normal);
        const Seed seed = seed_of(c);
        const CutResult r = c.kind < 4    ? slice_by_plane(ctx, plane, seed, cs)
                            : c.kind == 4 ? slice_by_plane(ctx, plane, cs)
                                          : subtract_slab(ctx, plane, kerf_m, seed, slab);
        if (r.status == CutStatus::kInternalError) return i;
    }
    return cuts.size();
}

// Flux of max(s - c, 0) n through the faces of `m` in `faces` (s: signed distance to `lower`, n
// its normal): clipped to s >= c, fanned, each piece's vector area times its mean of s - c.
inline double positive_part_flux(const mesh::TriMesh& m, const std::vector<mesh::FaceHandle>& faces,
                                 const Plane& lower, double c) {
    double sum = 0;
    for (mesh::FaceHandle f : faces) {
        Vec3 poly[4];
        double val[4];
        int k = 0;
        Vec3 p[3];
        double v[3];
        int i = 0;
        for (auto vh : m.fv_range(f))
            p[i] = m.point(vh), v[i] = lower.signed_distance(p[i]) - c, ++i;
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3;
            if (v[a] >= 0) poly[k] = p[a], val[k++] = v[a];
            if ((v[a] >= 0) != (v[b] >= 0)) {
                const double t = v[a] / (v[a] - v[b]);
                poly[k] = p[a] + (p[b] - p[a]) * t, val[k++] = 0;
            }
        }
        for (int j = 1; j + 1 < k; ++j) {
            const Vec3 area = OpenMesh::cross(poly[j] - poly[0], poly[j + 1] - poly[0]) * 0.5;
            sum += OpenMesh::dot(area, lower.normal()) * (val[0] + val[j] + val[j + 1]) / 3;
        }
    }
    return sum;
}

/// The index of the body of `m` (`bodies`, find_components) with the face centroid nearest `point`.
inline std::size_t nearest_body(const mesh::TriMesh& m, const std::vector<Body>& bodies,
                                const Vec3& point) {
    double nearest = 1e300;
    std::size_t best = 0;
    for (std::size_t k = 0; k < bodies.size(); ++k)
        for (mesh::FaceHandle f : bodies[k].faces) {
            const double d = (face_centroid(m, f) - point).norm();
            if (d < nearest) nearest = d, best = k;
        }
    return best;
}

/// A random cut of `m`: a plane through the centroid of a random live face (normal drawn in
/// [-1, 1]^3, +z when shorter than 0.1) and that centroid as the seed, with no triangle hint;
/// the face in `face` when given.
inline std::pair<Plane, Seed> random_face_cut(const mesh::TriMesh& m, std::mt19937_64& rng,
                                              mesh::FaceHandle* face = nullptr) {
    std::uniform_real_distribution<double> u(-1, 1);
    mesh::FaceHandle f;
    do {
        f = mesh::FaceHandle(
            std::uniform_int_distribution<int>(0, static_cast<int>(m.n_faces()) - 1)(rng));
    } while (m.status(f).deleted());
    const Vec3 p = face_centroid(m, f);
    Vec3 n(u(rng), u(rng), u(rng));
    if (n.norm() < 0.1) n = Vec3(0, 0, 1);
    if (face != nullptr) *face = f;
    return {*Plane::make(p, n), Seed{p, mesh::FaceHandle(), -1.0}};
}

/// The volume a slab cut of `plane` kerf_m wide should have removed from `before` (the mesh just
/// before it; `after` with `slab` the result): the material of the seed's body between the
/// planes, found independently of any cut as the flux of clamp(s, 0, kerf) n through the body's
/// surface before the cut (s the signed distance to the lower plane: the divergence is 1 inside
/// the slab, 0 outside). The body is the one nearest a point of the remaining lower cap.
inline double seed_body_band_volume(const mesh::TriMesh& before, const mesh::TriMesh& after,
                                    const SlabCut& slab, const Plane& plane, double kerf_m) {
    if (slab.lower.negative.cap_faces.empty()) return 0.0;
    const Vec3 on_lower_cap = face_centroid(after, slab.lower.negative.cap_faces.front());
    const std::vector<Body> bodies = find_components(before);
    const std::size_t seed_body = nearest_body(before, bodies, on_lower_cap);
    const Plane lower = plane.offset(-0.5 * kerf_m);
    const std::vector<mesh::FaceHandle>& faces = bodies[seed_body].faces;
    return positive_part_flux(before, faces, lower, 0.0) -
           positive_part_flux(before, faces, lower, kerf_m);
}

/// What a slab cut of `before` on `plane`, `kerf_m` wide, from a seed at `seed_point` must
/// remove, found independently of subtract_slab: the body of `before` nearest the seed, as a mesh
/// of its own, sliced by full planes on both walls, and the piece between them that holds the
/// seed, m^3 (-1 when a reference slice fails). Slicing the body alone keeps the rest of a long
/// sequence's mesh, where a full plane can meet a refusal, out of the reference.
inline double seed_body_slab_reference(const mesh::TriMesh& before, const Plane& plane,
                                       double kerf_m, const Vec3& seed_point) {
    const std::vector<Body> bodies = find_components(before);
    const std::size_t seed_body = nearest_body(before, bodies, seed_point);
    const std::vector<mesh::FaceHandle>& faces = bodies[seed_body].faces;
    const mesh::TriMesh body = extract_faces(before, [&](mesh::FaceHandle f) {
        return std::binary_search(faces.begin(), faces.end(), f);
    });
    return slab_reference_removed_volume(body, plane, kerf_m, seed_point);
}

/// What a slab cut of `before` on `plane`, `kerf_m` wide, from a seed at `seed_point` on face
/// `seed_face` must remove, found independently of subtract_slab: the body of `before` that holds
/// the face, as a mesh of its own, sliced by full planes on both walls, and the piece between them
/// that holds the seed on that face (the face nearest it among those facing as the seed's face
/// does), m^3 (-1 when a reference slice fails). The face says which material the blade touches:
/// a seed on an earlier cut's cap lies on that cut's other cap too, the pieces on either side
/// both hold it, and nearest_body or a nearest centroid may name either. `merges` (optional)
/// gets the reference slices' vertex merges.
inline double seed_face_slab_reference(const mesh::TriMesh& before, const Plane& plane,
                                       double kerf_m, const Vec3& seed_point,
                                       mesh::FaceHandle seed_face,
                                       std::uint32_t* merges = nullptr) {
    const std::vector<Body> bodies = find_components(before);
    std::size_t seed_body = 0;
    while (seed_body < bodies.size() &&
           !std::binary_search(bodies[seed_body].faces.begin(), bodies[seed_body].faces.end(),
                               seed_face))
        ++seed_body;
    if (seed_body == bodies.size()) return -1.0;
    const std::vector<mesh::FaceHandle>& faces = bodies[seed_body].faces;
    const mesh::TriMesh body = extract_faces(before, [&](mesh::FaceHandle f) {
        return std::binary_search(faces.begin(), faces.end(), f);
    });
    const Vec3 facing = before.calc_face_normal(seed_face);
    return slab_reference_removed_volume(body, plane, kerf_m, seed_point, &facing, merges);
}

/// Expects `after` to be `before` element for element: the array sizes, every vertex's point,
/// outgoing halfedge and deleted flag, every halfedge's vertex, next, previous and face, every
/// face's halfedge and deleted flag (a refusal leaves the mesh unchanged, not just its hash).
inline void expect_same_mesh(const mesh::TriMesh& before, const mesh::TriMesh& after) {
    ASSERT_EQ(before.n_vertices(), after.n_vertices());
    ASSERT_EQ(before.n_edges(), after.n_edges());
    ASSERT_EQ(before.n_faces(), after.n_faces());
    int differ = 0;
    for (int i = 0; i < static_cast<int>(before.n_vertices()); ++i) {
        const mesh::VertexHandle v(i);
        differ += before.point(v) != after.point(v) ||
                  before.halfedge_handle(v) != after.halfedge_handle(v) ||
                  before.status(v).deleted() != after.status(v).deleted();
    }
    for (int i = 0; i < static_cast<int>(before.n_halfedges()); ++i) {
        const mesh::HalfedgeHandle h(i);
        differ += before.to_vertex_handle(h) != after.to_vertex_handle(h) ||
                  before.next_halfedge_handle(h) != after.next_halfedge_handle(h) ||
                  before.prev_halfedge_handle(h) != after.prev_halfedge_handle(h) ||
                  before.face_handle(h) != after.face_handle(h);
    }
    for (int i = 0; i < static_cast<int>(before.n_faces()); ++i) {
        const mesh::FaceHandle f(i);
        differ += before.halfedge_handle(f) != after.halfedge_handle(f) ||
                  before.status(f).deleted() != after.status(f).deleted();
    }
    EXPECT_EQ(differ, 0) << "elements changed";
}

}  // namespace kerf::cut::testing
