#include "display/mesh/coincidence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace kerf::mesh {
namespace {

constexpr std::size_t kMaxSamples = 8;

/// A cell of the spatial hash: integer coordinates, packed 21 bits an axis.
std::uint64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) noexcept {
    constexpr std::uint64_t mask = (1u << 21) - 1;
    return (std::uint64_t(x) & mask) | ((std::uint64_t(y) & mask) << 21) |
           ((std::uint64_t(z) & mask) << 42);
}

struct TriangleKeyHash {
    std::size_t operator()(const Triangle& t) const noexcept {
        std::uint64_t h = 0xcbf29ce484222325ull;
        for (std::uint32_t v : t) h = (h ^ v) * 0x100000001b3ull;
        return std::size_t(h);
    }
};

void find_repeated_triangles(const IndexedMesh& mesh, CoincidenceReport& out) {
    std::unordered_map<Triangle, std::size_t, TriangleKeyHash> first_with;
    first_with.reserve(mesh.triangles.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        Triangle key = mesh.triangles[i];
        std::sort(key.begin(), key.end());
        const auto [it, inserted] = first_with.try_emplace(key, i);
        if (inserted) continue;
        ++out.repeated_triangles;
        if (out.triangle_samples.size() < kMaxSamples)
            out.triangle_samples.push_back(std::array<std::size_t, 2>{{i, it->second}});
    }
}

}  // namespace

CoincidenceReport find_coincidences(const IndexedMesh& mesh, double relative_tolerance) {
    CoincidenceReport out;
    find_repeated_triangles(mesh, out);

    std::vector<std::uint32_t> used;  // referenced vertices, ascending
    {
        std::vector<bool> referenced(mesh.positions_m.size(), false);
        for (const Triangle& t : mesh.triangles) {
            for (std::uint32_t v : t) referenced[v] = true;
        }
        for (std::uint32_t v = 0; v < referenced.size(); ++v) {
            if (referenced[v]) used.push_back(v);
        }
    }
    if (used.size() < 2) return out;
    Point lo = mesh.positions_m[used[0]], hi = lo;
    for (std::uint32_t v : used) {
        lo.minimize(mesh.positions_m[v]);
        hi.maximize(mesh.positions_m[v]);
    }
    const double diagonal = (hi - lo).norm();
    out.tolerance_m = diagonal * relative_tolerance;
    if (!(out.tolerance_m > 0) || !std::isfinite(out.tolerance_m)) return out;

    // Cells one tolerance wide: coincident vertices lie in the same or a neighbouring cell.
    // (hi - lo) / tolerance <= 1 / relative_tolerance cells an axis; at the default that fits
    // 21 bits, and a coarser cell (never a finer one) keeps it so for any tolerance.
    const double cell = std::max(out.tolerance_m, diagonal / double((1u << 20) - 2));
    auto coordinate = [&](double value, double origin) {
        return std::int64_t(std::floor((value - origin) / cell));
    };
    std::unordered_multimap<std::uint64_t, std::uint32_t> grid;
    grid.reserve(used.size());
    for (std::uint32_t v : used) {
        const Point& p = mesh.positions_m[v];
        grid.emplace(
            cell_key(coordinate(p[0], lo[0]), coordinate(p[1], lo[1]), coordinate(p[2], lo[2])), v);
    }
    std::uint64_t comparisons = 0;
    for (std::uint32_t v : used) {
        const Point& p = mesh.positions_m[v];
        const std::int64_t cx = coordinate(p[0], lo[0]), cy = coordinate(p[1], lo[1]),
                           cz = coordinate(p[2], lo[2]);
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
            for (std::int64_t dy = -1; dy <= 1; ++dy) {
                for (std::int64_t dz = -1; dz <= 1; ++dz) {
                    if (cx + dx < 0 || cy + dy < 0 || cz + dz < 0) continue;
                    const auto [first, last] =
                        grid.equal_range(cell_key(cx + dx, cy + dy, cz + dz));
                    for (auto it = first; it != last; ++it) {
                        const std::uint32_t w = it->second;
                        if (w <= v) continue;  // each pair once
                        if (++comparisons > kMaxComparisons) {
                            out.complete = false;
                            return out;
                        }
                        const double d = (mesh.positions_m[w] - p).norm();
                        if (d >= out.tolerance_m) continue;
                        ++out.coincident_vertex_pairs;
                        if (out.vertex_samples.size() < kMaxSamples)
                            out.vertex_samples.push_back({v, w, p, mesh.positions_m[w], d});
                    }
                }
            }
        }
    }
    return out;
}

}  // namespace kerf::mesh
