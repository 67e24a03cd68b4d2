#include "display/mesh/validate.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace kerf::mesh {
namespace {

class UnionFind {
public:
    explicit UnionFind(std::size_t n) : parent_(n) {
        std::iota(parent_.begin(), parent_.end(), 0u);
    }
    std::uint32_t find(std::uint32_t x) {
        while (parent_[x] != x) {
            parent_[x] = parent_[parent_[x]];
            x = parent_[x];
        }
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // deterministic roots
    }

private:
    std::vector<std::uint32_t> parent_;
};

// One use of an undirected edge by a triangle corner.
struct EdgeUse {
    std::uint64_t key;  // (min << 32) | max
    std::uint32_t face;
    std::uint8_t corner;  // the edge runs from corner to corner + 1
    bool forward;         // min -> max
    bool operator<(const EdgeUse& o) const { return key != o.key ? key < o.key : face < o.face; }
};

std::vector<EdgeUse> collect_edge_uses(const IndexedMesh& in) {
    std::vector<EdgeUse> uses;
    uses.reserve(in.triangles.size() * 3);
    for (std::uint32_t f = 0; f < in.triangles.size(); ++f) {
        const Triangle& t = in.triangles[f];
        for (std::uint8_t k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a == b) continue;
            const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
            uses.push_back({(lo << 32) | hi, f, k, a < b});
        }
    }
    std::sort(uses.begin(), uses.end());
    return uses;
}

double norm(const Point& p) { return std::sqrt(p | p); }

void measure_geometry(const IndexedMesh& in, ValidationReport& r) {
    if (in.positions_m.empty()) return;
    r.bbox_min_m = r.bbox_max_m = in.positions_m.front();
    for (const Point& p : in.positions_m) {
        r.bbox_min_m.minimize(p);
        r.bbox_max_m.maximize(p);
    }
}

// Corner index of the vertex `v` in face f: 3f + k.
std::uint32_t corner_of(const Triangle& t, std::uint32_t f, std::uint32_t v) {
    const std::uint32_t k = t[0] == v ? 0u : (t[1] == v ? 1u : 2u);
    return 3 * f + k;
}

// Walks the sorted edge uses: edge counts, orientation, and fans around vertices.
void measure_edges(const IndexedMesh& in, const std::vector<EdgeUse>& uses, UnionFind& fans,
                   ValidationReport& r, std::vector<std::uint8_t>& on_bad_edge) {
    for (std::size_t i = 0; i < uses.size();) {
        std::size_t j = i;
        while (j < uses.size() && uses[j].key == uses[i].key) ++j;
        const std::size_t n = j - i;
        const auto lo = static_cast<std::uint32_t>(uses[i].key >> 32);
        const auto hi = static_cast<std::uint32_t>(uses[i].key & 0xFFFFFFFFu);
        ++r.edges;
        if (n == 1) {
            ++r.boundary_edges;
            if (r.boundary_samples_m.size() < 16) {
                r.boundary_samples_m.push_back({in.positions_m[lo], in.positions_m[hi]});
            }
        } else if (n == 2 && uses[i].forward == uses[i + 1].forward) {
            ++r.misoriented_edges;
        } else if (n > 2) {
            ++r.non_manifold_edges;
            on_bad_edge[lo] = on_bad_edge[hi] = 1;
        }
        for (std::size_t k = i + 1; k < j; ++k) {
            const std::uint32_t f0 = uses[i].face, f1 = uses[k].face;
            fans.unite(corner_of(in.triangles[f0], f0, lo), corner_of(in.triangles[f1], f1, lo));
            fans.unite(corner_of(in.triangles[f0], f0, hi), corner_of(in.triangles[f1], f1, hi));
        }
        i = j;
    }
}

void measure_vertices(const IndexedMesh& in, UnionFind& fans,
                      const std::vector<std::uint8_t>& on_bad_edge, ValidationReport& r) {
    // First fan root seen per vertex; a second, different root makes it non-manifold.
    constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    std::vector<std::uint32_t> root(in.positions_m.size(), kNone);
    std::vector<std::uint8_t> bad(on_bad_edge);
    for (std::uint32_t f = 0; f < in.triangles.size(); ++f) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t v = in.triangles[f][k];
            const std::uint32_t c = fans.find(3 * f + k);
            if (root[v] == kNone) {
                root[v] = c;
            } else if (root[v] != c) {
                bad[v] = 1;
            }
        }
    }
    for (std::size_t v = 0; v < root.size(); ++v) {
        if (root[v] == kNone) ++r.unreferenced_vertices;
        if (bad[v] != 0) ++r.non_manifold_vertices;
    }
}

void measure_shells(const IndexedMesh& in, const std::vector<EdgeUse>& uses, ValidationReport& r) {
    UnionFind shells(in.positions_m.size());
    for (const Triangle& t : in.triangles) {
        shells.unite(t[0], t[1]);
        shells.unite(t[1], t[2]);
    }
    std::vector<std::uint32_t> slot(in.positions_m.size(), 0xFFFFFFFFu);  // root -> shell
    std::vector<ShellSummary> out;
    auto shell_of = [&](std::uint32_t v) -> ShellSummary& {
        std::uint32_t& s = slot[shells.find(v)];
        if (s == 0xFFFFFFFFu) {
            s = static_cast<std::uint32_t>(out.size());
            out.emplace_back();
        }
        return out[s];
    };
    const Point centre = (r.bbox_min_m + r.bbox_max_m) * 0.5;
    const double diag = norm(r.bbox_max_m - r.bbox_min_m);
    for (const Triangle& t : in.triangles) {
        ShellSummary& s = shell_of(t[0]);
        const Point a = in.positions_m[t[0]] - centre, b = in.positions_m[t[1]] - centre;
        const Point c = in.positions_m[t[2]] - centre;
        const double twice_area = norm((b - a) % (c - a));
        ++s.triangles;
        s.area_m2 += 0.5 * twice_area;
        s.volume_m3 += (a | (b % c)) / 6.0;
        const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        if (repeated || twice_area <= kDegenerateTwiceAreaRelative * diag * diag)
            ++r.degenerate_triangles;
    }
    std::vector<std::uint8_t> seen(in.positions_m.size(), 0);
    for (const Triangle& t : in.triangles) {
        for (std::uint32_t v : t) {
            if (seen[v] == 0) ++shell_of(v).vertices;
            seen[v] = 1;
        }
    }
    for (std::size_t i = 0; i < uses.size(); ++i) {
        const bool first = i == 0 || uses[i - 1].key != uses[i].key;
        const bool single = first && (i + 1 == uses.size() || uses[i + 1].key != uses[i].key);
        ShellSummary& s = shell_of(static_cast<std::uint32_t>(uses[i].key >> 32));
        if (first) ++s.edges;
        if (single) ++s.boundary_edges;
    }
    for (ShellSummary& s : out) {
        s.euler_characteristic = static_cast<long>(s.vertices) - static_cast<long>(s.edges) +
                                 static_cast<long>(s.triangles);
        s.closed = s.boundary_edges == 0;
        r.area_m2 += s.area_m2;
        r.volume_m3 += s.volume_m3;
    }
    std::stable_sort(out.begin(), out.end(), [](const ShellSummary& x, const ShellSummary& y) {
        return x.triangles > y.triangles;
    });
    r.shells = std::move(out);
}

}  // namespace

ValidationReport validate(const IndexedMesh& in) {
    ValidationReport r;
    r.vertices = in.positions_m.size();
    r.triangles = in.triangles.size();
    measure_geometry(in, r);
    const std::vector<EdgeUse> uses = collect_edge_uses(in);
    UnionFind fans(in.triangles.size() * 3);
    std::vector<std::uint8_t> on_bad_edge(in.positions_m.size(), 0);
    measure_edges(in, uses, fans, r, on_bad_edge);
    measure_vertices(in, fans, on_bad_edge, r);
    measure_shells(in, uses, r);
    r.closed = r.triangles > 0 && r.boundary_edges == 0 && r.non_manifold_edges == 0;
    r.oriented = r.misoriented_edges == 0 && r.non_manifold_edges == 0;
    return r;
}

ValidationReport validate(const TriMesh& mesh) { return validate(to_indexed(mesh)); }

}  // namespace kerf::mesh
