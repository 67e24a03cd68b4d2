// Helpers shared by the slice tests: the shared bone meshes, snapshots for "unchanged /
// bit-identical" checks, cap and loop areas, and a one-call strict check after a cut.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

#include "display/cut/cross_section.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/mesh/mesh_io.hpp"
#include "display/mesh/tri_mesh.hpp"
#include "tests/cut/mesh_checks.hpp"

namespace kerf::cut::testing {

/// The shared bone mesh `file` (KERF_SHARED_MESHES, ../shared/meshes) loaded in `unit`, or
/// nullopt when it is absent (the caller skips: `if (!m) GTEST_SKIP() << "real meshes absent";`)
/// or does not load (a failure naming the file and the error is recorded as well).
inline std::optional<kerf::mesh::TriMesh> load_shared_mesh(
    const char* file, kerf::LengthUnit unit = kerf::LengthUnit::kMillimetre) {
    const auto path = std::filesystem::path(KERF_SHARED_MESHES) / file;
    if (!std::filesystem::exists(path)) return std::nullopt;
    auto loaded = kerf::mesh::load_mesh(path, unit);
    if (!loaded) {
        ADD_FAILURE() << "cannot load " << path << ": " << loaded.error().message();
        return std::nullopt;
    }
    return std::move(*loaded);
}

/// Every non-deleted face's vertex positions, bit for bit, in face-index order.
struct FaceSnapshot {
    std::vector<int> face_ids;
    std::vector<double> coords;
    friend bool operator==(const FaceSnapshot&, const FaceSnapshot&) = default;
};

/// Snapshot of the faces whose index is in [first, last) (all when last < 0).
inline FaceSnapshot snapshot(const kerf::mesh::TriMesh& m, int first = 0, int last = -1) {
    FaceSnapshot s;
    for (auto f : m.faces()) {
        if (f.idx() < first || (last >= 0 && f.idx() >= last)) continue;
        s.face_ids.push_back(f.idx());
        for (auto v : m.fv_range(f))
            for (int i = 0; i < 3; ++i) s.coords.push_back(m.point(v)[i]);
    }
    return s;
}

/// A new mesh made of the faces of `m` for which `keep(face)` holds, with every vertex attribute
/// mesh_hash() reads (position, normal, texture coordinates, colour, material): a copy's hash is
/// then as deterministic as the original's.
template <class Keep>
kerf::mesh::TriMesh extract_faces(const kerf::mesh::TriMesh& m, Keep&& keep) {
    kerf::mesh::TriMesh out;
    std::vector<kerf::mesh::VertexHandle> map(m.n_vertices());
    for (auto f : m.faces()) {
        if (!keep(f)) continue;
        kerf::mesh::VertexHandle vs[3];
        int k = 0;
        for (auto v : m.fv_range(f)) {
            if (!map[v.idx()].is_valid()) {
                map[v.idx()] = out.add_vertex(m.point(v));
                // A slice of the copy interpolates them (valgrind: uninitialised otherwise).
                out.set_normal(map[v.idx()], m.normal(v));
                out.set_texcoord2D(map[v.idx()], m.texcoord2D(v));
                out.set_color(map[v.idx()], m.color(v));
                out.data(map[v.idx()]).set_material(m.data(v).material());
            }
            vs[k++] = map[v.idx()];
        }
        out.add_face(vs[0], vs[1], vs[2]);
    }
    return out;
}

/// Total area of some faces, m^2.
inline double area_of(const kerf::mesh::TriMesh& m,
                      const std::vector<kerf::mesh::FaceHandle>& faces) {
    double a = 0;
    for (auto f : faces) {
        auto it = m.cfv_iter(f);
        const auto p = m.point(*it++);
        const auto q = m.point(*it++);
        const auto r = m.point(*it);
        a += 0.5 * OpenMesh::cross(q - p, r - p).norm();
    }
    return a;
}

/// Total area of some faces projected onto the plane with unit normal `n`, m^2.
inline double projected_area_of(const kerf::mesh::TriMesh& m,
                                const std::vector<kerf::mesh::FaceHandle>& faces, const Vec3& n) {
    double a = 0;
    for (auto f : faces) {
        auto it = m.cfv_iter(f);
        const auto p = m.point(*it++);
        const auto q = m.point(*it++);
        const auto r = m.point(*it);
        a += 0.5 * std::abs(OpenMesh::dot(OpenMesh::cross(q - p, r - p), n));
    }
    return a;
}

/// Net polygon area of the cross-section (outer loops minus holes), from its 2-D loops, m^2.
inline double polygon_area(const CrossSection& cs) {
    double a = 0;
    for (const auto& loop : cs.loops_2d)
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const auto& p = loop[i];
            const auto& q = loop[(i + 1) % loop.size()];
            a += 0.5 * (p[0] * q[1] - p[1] * q[0]);
        }
    return a;
}

/// The checks every cut test runs on the cross-section it got: pairing, planarity of the rim,
/// cap areas equal to the polygon area on both sides, cap normals.
inline void expect_cross_section_consistent(const kerf::mesh::TriMesh& m, const CrossSection& cs,
                                            double tolerance_m,
                                            std::uint32_t vertices_snapped = 0) {
    ASSERT_EQ(cs.positive.loops.size(), cs.loops_2d.size());
    ASSERT_EQ(cs.negative.loops.size(), cs.loops_2d.size());
    std::uint32_t beyond_tolerance = 0;  // rim pairs a snapped vertex made
    for (std::size_t i = 0; i < cs.loops_2d.size(); ++i) {
        ASSERT_EQ(cs.positive.loops[i].size(), cs.loops_2d[i].size());
        for (std::size_t j = 0; j < cs.loops_2d[i].size(); ++j) {
            const auto p = cs.positive.loops[i][j];
            const auto n = cs.negative.loops[i][j];
            ASSERT_NE(p, n);
            EXPECT_EQ(std::memcmp(&m.point(p), &m.point(n), sizeof(m.point(p))), 0);
            const double d = std::abs(cs.plane.signed_distance(m.point(p)));
            beyond_tolerance += d > tolerance_m * 1.0001;
            EXPECT_LE(d, kSnapTolerances * tolerance_m * 1.0001);
        }
    }
    EXPECT_LE(beyond_tolerance, vertices_snapped) << "rim vertices beyond the tolerance";
    const double poly = polygon_area(cs);
    EXPECT_GT(poly, 0.0);
    // The caps tile the polygon: their area projected onto the plane is the polygon's. Unsnapped
    // rims lie within tol of the plane, so the caps are flat to 1e-9 as well; a snapped vertex
    // (up to kSnapTolerances tol off) tilts the cap triangles on its steep rim edges.
    for (const auto* side : {&cs.positive, &cs.negative}) {
        EXPECT_NEAR(projected_area_of(m, side->cap_faces, cs.plane.normal()), poly, 1e-9 * poly);
        if (vertices_snapped == 0) {
            EXPECT_NEAR(area_of(m, side->cap_faces), poly, 1e-9 * poly);
        }
    }
    for (auto f : cs.positive.cap_faces)
        EXPECT_LT(OpenMesh::dot(m.calc_face_normal(f), cs.plane.normal()), 0.0);
    for (auto f : cs.negative.cap_faces)
        EXPECT_GT(OpenMesh::dot(m.calc_face_normal(f), cs.plane.normal()), 0.0);
}

}  // namespace kerf::cut::testing
