// Gtest-free strict checks of a mesh after cuts: closed, consistently oriented 2-manifold, no
// non-finite or near-zero-area triangle, piece volumes. Used by mesh_checks.hpp (the gtest
// wrappers every cut test calls) and by the fuzz targets. See mesh_checks.hpp for the definitions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "display/mesh/tri_mesh.hpp"
#include "display/mesh/validate.hpp"

namespace kerf::cut::testing {

/// Smallest triangle area accepted, relative to the squared bounding-box diagonal: the project's
/// one degenerate threshold (validate.hpp; twice the area must exceed it).
inline constexpr double kMinRelativeArea = 0.5 * kerf::mesh::kDegenerateTwiceAreaRelative;

/// What the strict check measured; volumes in m^3, sorted descending.
struct MeshReport {
    std::size_t faces = 0;
    std::size_t vertices_used = 0;
    std::vector<double> piece_volumes_m3;
    double total_volume_m3 = 0.0;
    double min_area_m2 = 0.0;
    bool ok = false;
    int failures = 0;
    std::string failures_log;  ///< the first few failures, one per line
};

/// Signed volume of the non-deleted faces (divergence theorem), m^3.
inline double signed_volume(const kerf::mesh::TriMesh& mesh) {
    double v = 0.0;
    for (auto f : mesh.faces()) {
        auto it = mesh.cfv_iter(f);
        const auto a = mesh.point(*it++);
        const auto b = mesh.point(*it++);
        const auto c = mesh.point(*it);
        v += OpenMesh::dot(a, OpenMesh::cross(b, c)) / 6.0;
    }
    return v;
}

/// Total area of the non-deleted faces, m^2.
inline double surface_area(const kerf::mesh::TriMesh& mesh) {
    double a = 0.0;
    for (auto f : mesh.faces()) {
        auto it = mesh.cfv_iter(f);
        const auto p0 = mesh.point(*it++);
        const auto p1 = mesh.point(*it++);
        const auto p2 = mesh.point(*it);
        a += 0.5 * OpenMesh::cross(p1 - p0, p2 - p0).norm();
    }
    return a;
}

/// How much a cut may change the enclosed volume, m^3: rounding (1e-9 relative) plus, per cut
/// point merged into its loop neighbour (CutStats::vertices_merged), the volume a vertex moved
/// by at most `tolerance_m` can sweep: tolerance_m * (one-ring area) / 3 <= tolerance_m * area / 3.
inline double volume_change_bound(double volume_m3, std::uint32_t vertices_merged,
                                  double tolerance_m, double surface_area_m2) {
    return 1e-9 * std::abs(volume_m3) + vertices_merged * tolerance_m * surface_area_m2 / 3.0;
}

/// Bounding-box diagonal of the points used by non-deleted faces, m.
inline double used_bbox_diagonal(const kerf::mesh::TriMesh& mesh) {
    OpenMesh::Vec3d lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (auto f : mesh.faces()) {
        for (auto v : mesh.fv_range(f)) {
            lo.minimize(mesh.point(v));
            hi.maximize(mesh.point(v));
        }
    }
    return mesh.n_faces() == 0 ? 0.0 : (hi - lo).norm();
}

namespace detail {

inline std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t{a} << 32) | b; }

// Union-find over face indices, for pieces.
inline std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

}  // namespace detail

/// Runs every check above without gtest (the fuzz targets use it too): failures are counted
/// and the first few described in `failures_log`.
inline MeshReport check_closed_2_manifold(const kerf::mesh::TriMesh& mesh) {
    MeshReport r;
    int failures = 0;
    std::string log;
    auto fail = [&](const std::string& what) {
        if (++failures <= 8) log += what + "\n";
    };
    const double diag = used_bbox_diagonal(mesh);
    const double min_area = kMinRelativeArea * diag * diag;
    r.min_area_m2 = 1e300;
    std::vector<std::uint64_t> directed;
    directed.reserve(mesh.n_faces() * 3);
    std::vector<std::uint32_t> uses(mesh.n_vertices(), 0);
    for (auto f : mesh.faces()) {
        ++r.faces;
        std::uint32_t idx[3];
        OpenMesh::Vec3d p[3];
        int k = 0;
        for (auto h : mesh.fh_range(f)) {
            if (k == 3) break;
            const auto v = mesh.to_vertex_handle(h);
            if (mesh.status(v).deleted())
                fail("face " + std::to_string(f.idx()) + " uses a deleted vertex");
            if (mesh.is_boundary(mesh.opposite_halfedge_handle(h)))
                fail("face " + std::to_string(f.idx()) + " has an OpenMesh boundary edge");
            idx[k] = static_cast<std::uint32_t>(v.idx());
            p[k] = mesh.point(v);
            ++k;
        }
        if (k != 3) {
            fail("face " + std::to_string(f.idx()) + " is not a triangle");
            continue;
        }
        for (int i = 0; i < 3; ++i) {
            ++uses[idx[i]];
            directed.push_back(detail::key(idx[i], idx[(i + 1) % 3]));
        }
        const double area = 0.5 * OpenMesh::cross(p[1] - p[0], p[2] - p[0]).norm();
        if (!std::isfinite(area) ||
            !std::isfinite(p[0].sqrnorm() + p[1].sqrnorm() + p[2].sqrnorm()))
            fail("face " + std::to_string(f.idx()) + " is not finite");
        else if (!(area > min_area)) {
            char text[160];
            std::snprintf(text, sizeof text, "face %d has near-zero area %.3g m^2 (limit %.3g)",
                          f.idx(), area, min_area);
            fail(text);
        }
        r.min_area_m2 = std::min(r.min_area_m2, area);
    }
    std::sort(directed.begin(), directed.end());
    for (std::size_t i = 0; i < directed.size(); ++i) {
        const auto d = directed[i];
        if (i + 1 < directed.size() && directed[i + 1] == d)
            fail("directed edge " + std::to_string(d >> 32) + "->" +
                 std::to_string(d & 0xffffffffu) +
                 " used twice (inconsistent orientation or non-manifold edge)");
        const auto rev = detail::key(static_cast<std::uint32_t>(d & 0xffffffffu),
                                     static_cast<std::uint32_t>(d >> 32));
        if (!std::binary_search(directed.begin(), directed.end(), rev))
            fail("edge " + std::to_string(d >> 32) + "->" + std::to_string(d & 0xffffffffu) +
                 " has no opposite (open surface)");
    }
    for (auto v : mesh.vertices()) {
        if (uses[v.idx()] == 0) continue;
        ++r.vertices_used;
        std::uint32_t ring = 0;
        for (auto f : mesh.vf_range(v)) {
            (void)f;
            if (++ring > uses[v.idx()]) break;
        }
        if (ring != uses[v.idx()])
            fail("vertex " + std::to_string(v.idx()) + " one-ring sees " + std::to_string(ring) +
                 " of its " + std::to_string(uses[v.idx()]) + " faces (pinched or broken fan)");
    }
    // Pieces: faces joined across edges.
    std::vector<std::uint32_t> parent(mesh.n_faces());
    std::iota(parent.begin(), parent.end(), 0u);
    for (auto e : mesh.edges()) {
        if (mesh.status(e).deleted() || mesh.is_boundary(e)) continue;
        const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
        const auto f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
        const auto a = detail::find(parent, static_cast<std::uint32_t>(f0.idx()));
        const auto b = detail::find(parent, static_cast<std::uint32_t>(f1.idx()));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
    std::vector<double> vol(mesh.n_faces(), 0.0);
    std::vector<char> is_root(mesh.n_faces(), 0);
    for (auto f : mesh.faces()) {
        auto it = mesh.cfv_iter(f);
        const auto a = mesh.point(*it++);
        const auto b = mesh.point(*it++);
        const auto c = mesh.point(*it);
        const auto root = detail::find(parent, static_cast<std::uint32_t>(f.idx()));
        vol[root] += OpenMesh::dot(a, OpenMesh::cross(b, c)) / 6.0;
        is_root[root] = 1;
    }
    for (std::size_t i = 0; i < vol.size(); ++i) {
        if (!is_root[i]) continue;
        r.piece_volumes_m3.push_back(vol[i]);
        r.total_volume_m3 += vol[i];
    }
    std::sort(r.piece_volumes_m3.begin(), r.piece_volumes_m3.end(), std::greater<>());
    if (r.faces == 0) r.min_area_m2 = 0.0;
    r.ok = failures == 0;
    r.failures = failures;
    r.failures_log = std::move(log);
    return r;
}

}  // namespace kerf::cut::testing
