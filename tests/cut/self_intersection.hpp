// Pairs of faces of a mesh that cross each other: an edge of one passes through the inside of the
// other, strictly (by more than `eps_m` from its plane at both ends and from its edges). Faces
// that only touch — a shared vertex or edge, coincident caps of a cut not yet opened, a vertex on
// another face — do not count. For tests: a uniform grid over the faces' boxes, O(faces + pairs
// per cell).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::testing {

/// Two faces that cross, by index.
struct CrossingPair {
    int a = -1, b = -1;
};

namespace detail {

using Tri = std::array<mesh::TriMesh::Point, 3>;

/// Whether segment pq passes through the inside of triangle t, strictly by eps_m.
inline bool segment_crosses(const mesh::TriMesh::Point& p, const mesh::TriMesh::Point& q,
                            const Tri& t, double eps_m) {
    mesh::TriMesh::Point n = OpenMesh::cross(t[1] - t[0], t[2] - t[0]);
    const double len = n.norm();
    if (!(len > 0)) return false;
    n /= len;
    const double dp = OpenMesh::dot(p - t[0], n), dq = OpenMesh::dot(q - t[0], n);
    if (!((dp > eps_m && dq < -eps_m) || (dp < -eps_m && dq > eps_m))) return false;
    const mesh::TriMesh::Point x = p + (q - p) * (dp / (dp - dq));
    for (int i = 0; i < 3; ++i) {
        const mesh::TriMesh::Point& a = t[i];
        const mesh::TriMesh::Point& b = t[(i + 1) % 3];
        const double edge = (b - a).norm();
        if (!(edge > 0)) return false;
        if (OpenMesh::dot(OpenMesh::cross(b - a, x - a), n) / edge <= eps_m) return false;
    }
    return true;
}

inline bool triangles_cross(const Tri& s, const Tri& t, double eps_m) {
    for (int i = 0; i < 3; ++i) {
        if (segment_crosses(s[i], s[(i + 1) % 3], t, eps_m)) return true;
        if (segment_crosses(t[i], t[(i + 1) % 3], s, eps_m)) return true;
    }
    return false;
}

}  // namespace detail

/// The crossing pairs among the live faces `keep` accepts (all when empty), each pair once.
/// `cell_m`: grid cell size (a few typical edge lengths).
inline std::vector<CrossingPair> crossing_face_pairs(
    const mesh::TriMesh& m, double cell_m, double eps_m,
    const std::function<bool(mesh::FaceHandle)>& keep = {}) {
    struct Face {
        int idx;
        std::array<int, 3> v;
        detail::Tri p;
        mesh::TriMesh::Point lo, hi;
    };
    std::vector<Face> faces;
    for (const auto f : m.faces()) {
        if (keep && !keep(f)) continue;
        Face face{f.idx(),
                  {},
                  {},
                  mesh::TriMesh::Point(1e300, 1e300, 1e300),
                  mesh::TriMesh::Point(-1e300, -1e300, -1e300)};
        int k = 0;
        for (const auto v : m.fv_range(f)) {
            face.v[k] = v.idx();
            face.p[k] = m.point(v);
            face.lo.minimize(face.p[k]);
            face.hi.maximize(face.p[k]);
            ++k;
        }
        faces.push_back(face);
    }
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    const auto cell_of = [cell_m](double x) {
        return static_cast<std::int64_t>(std::floor(x / cell_m));
    };
    const auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
        return (static_cast<std::uint64_t>(x & 0x1FFFFF) << 42) |
               (static_cast<std::uint64_t>(y & 0x1FFFFF) << 21) |
               static_cast<std::uint64_t>(z & 0x1FFFFF);
    };
    // A face goes into the cells its plane passes through (not every cell of its box: a long
    // tilted cap triangle's box holds thousands), and each pair sharing a cell is tested once.
    for (std::uint32_t i = 0; i < faces.size(); ++i) {
        const Face& f = faces[i];
        mesh::TriMesh::Point n = OpenMesh::cross(f.p[1] - f.p[0], f.p[2] - f.p[0]);
        const double len = n.norm();
        if (len > 0) n /= len;
        const double reach = 0.5 * cell_m * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
        for (auto x = cell_of(f.lo[0]); x <= cell_of(f.hi[0]); ++x)
            for (auto y = cell_of(f.lo[1]); y <= cell_of(f.hi[1]); ++y)
                for (auto z = cell_of(f.lo[2]); z <= cell_of(f.hi[2]); ++z) {
                    const mesh::TriMesh::Point centre((x + 0.5) * cell_m, (y + 0.5) * cell_m,
                                                      (z + 0.5) * cell_m);
                    if (len > 0 && std::abs(OpenMesh::dot(centre - f.p[0], n)) > reach * 1.001)
                        continue;
                    grid[key(x, y, z)].push_back(i);
                }
    }
    std::vector<std::uint64_t> candidates;
    for (const auto& [cell, items] : grid) {
        for (std::size_t i = 0; i < items.size(); ++i) {
            for (std::size_t j = i + 1; j < items.size(); ++j) {
                const Face& a = faces[items[i]];
                const Face& b = faces[items[j]];
                mesh::TriMesh::Point lo = a.lo, hi = a.hi;
                lo.maximize(b.lo);
                hi.minimize(b.hi);
                if (lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]) continue;
                const auto [u, w] = std::minmax(items[i], items[j]);
                candidates.push_back((std::uint64_t{u} << 32) | w);
            }
        }
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    std::vector<CrossingPair> out;
    for (const std::uint64_t c : candidates) {
        const Face& a = faces[c >> 32];
        const Face& b = faces[c & 0xFFFFFFFFu];
        int shared = 0;
        for (const int va : a.v) shared += static_cast<int>(std::count(b.v.begin(), b.v.end(), va));
        if (shared >= 2) continue;  // neighbours across an edge
        if (detail::triangles_cross(a.p, b.p, eps_m)) out.push_back({a.idx, b.idx});
    }
    std::sort(out.begin(), out.end(), [](const CrossingPair& x, const CrossingPair& y) {
        return std::pair(x.a, x.b) < std::pair(y.a, y.b);
    });
    return out;
}

}  // namespace kerf::cut::testing
