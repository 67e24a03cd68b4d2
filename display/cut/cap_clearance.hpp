// Internal to separate.cpp: walls kept clear of a partly opened cap.
//
// Caps are built on rim points only, so where part of the rim is swept a cap rises as wedges:
// over a point it is where its triangle's corners' weights interpolate to, which can be far above
// the swept region's weight there (a triangle from a swept rim point across the section), and a
// wall that leans over the cap close to the plane (a vertex 9 um above it) would be left below it.
// So the vertices of such walls rise with the cap: at every corner of the overlay of a wall face's
// projection with a cap triangle (the wall is linear over its face, the cap over each triangle,
// so these points decide) the wall keeps at least half its gap. The clearances of a cap triangle
// are found when one of its corners first moves (a withdrawn cut moves a few), from a grid of the
// wall faces made once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "display/cut/cross_section.hpp"
#include "display/cut/plane.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut::detail {

inline constexpr std::uint32_t kNotInBand = 0xFFFFFFFFu;

/// A vertex the separation may move (see separate.hpp).
struct BandVertex {
    mesh::VertexHandle v;
    Vec3 origin;         ///< position at plan time, m
    Vec2 xy;             ///< (u, v) position, m
    double lift = 0.0;   ///< signed move at m = 1: side * kerf/2 * (1 - depth / D), m
    double base = 0.0;   ///< signed distance from the plane at plan time, m
    double m = 0.0;      ///< weight applied so far, 0..1: at least `swept`, more to clear the cap
    double swept = 0.0;  ///< m(x) of the swept region so far, 0..1
    bool rim = false;
    std::uint32_t slot = 0;   ///< index in the grid's item array while still live
    std::uint32_t stamp = 0;  ///< the sweep that last moved it
};

class CapClearances {
public:
    /// Indexes both sides' cap triangles and the band's faces within a kerf of the plane (the
    /// walls; earlier cuts' caps included). O(band faces + cap triangles).
    void build(const mesh::TriMesh& m, const CrossSection& cut, std::span<const BandVertex> band,
               double kerf);

    /// Whether moving this band vertex (a rim point) can raise a cap triangle.
    bool raises_cap(std::uint32_t index) const noexcept {
        return rim_start_[index] != rim_start_[index + 1];
    }

    /// Raises walls over the cap triangles of rim point `rim` where the cap came within half
    /// their gap: calls raise(index, weight) with a larger weight for band vertices of the wall
    /// faces (their rim points too, where that raises the wall more than the cap).
    template <class Raise>
    void clear(std::uint32_t rim, std::span<const BandVertex> band, Raise&& raise);

private:
    struct Triangle {  // a cap triangle
        std::uint32_t corner[3];
        Vec2 p[3];  // counter-clockwise
        Vec2 lo, hi;
        double sign;
        bool found = false;  // its clearances are in `clearances_`
        std::uint32_t first = 0, count = 0;
    };
    struct Wall {  // a face of a side with a corner in the band, not a cap triangle of this cut
        std::uint32_t corner[3];  // band vertices or kNotInBand
        Vec2 p[3];                // counter-clockwise
        double height[3];         // along the side's direction at plan time, m
        Vec2 lo, hi;
        double sign;
    };
    struct Clearance {
        std::uint32_t cap[3];   // the cap triangle's corners (rim band vertices)
        double a[3];            // the point's barycentric coordinates in it
        std::uint32_t wall[3];  // the wall face's corners (band vertices or kNotInBand)
        double b[3];            // the point's barycentric coordinates in the wall face
        double fixed = 0.0;     // height of the wall's unmoving corners at the point, m
        double min_gap = 0.0;   // the wall stays at least this far above the cap there, m
        double sign = 1.0;      // the side: +1 positive, -1 negative
    };

    void find(Triangle& t, std::span<const BandVertex> band);
    double height(const BandVertex& b, double sign) const noexcept {
        return sign * (b.base + b.lift * b.m);
    }

    double kerf_ = 0.0;
    std::vector<Triangle> triangles_;
    std::vector<std::uint32_t> rim_start_, rim_triangles_;  // per band vertex: its cap triangles
    std::vector<Wall> walls_;
    // Coarse grid (at most 16 x 16 cells) of the walls over their boxes.
    Vec2 origin_{0.0, 0.0};
    double step_ = 1.0;
    std::uint32_t cells_ = 1;
    std::vector<std::uint32_t> cell_start_, cell_walls_;
    std::vector<std::uint32_t> wall_seen_;  // per wall: the triangle last tested against it, + 1
    std::vector<Clearance> clearances_;
    std::vector<Vec2> clip_, scratch_;
    std::uint32_t cell_coord(double x, double origin) const noexcept;
};

template <class Raise>
void CapClearances::clear(std::uint32_t rim, std::span<const BandVertex> band, Raise&& raise) {
    for (std::uint32_t k = rim_start_[rim]; k < rim_start_[rim + 1]; ++k) {
        Triangle& t = triangles_[rim_triangles_[k]];
        if (!t.found) find(t, band);
        for (std::uint32_t i = t.first; i < t.first + t.count; ++i) {
            const Clearance& c = clearances_[i];
            double wall = c.fixed, below = 0.0;
            for (int q = 0; q < 3; ++q) {
                below += c.a[q] * height(band[c.cap[q]], c.sign);
                if (c.wall[q] != kNotInBand) wall += c.b[q] * height(band[c.wall[q]], c.sign);
            }
            const double deficit = c.min_gap - (wall - below);
            if (!(deficit > 1e-9 * kerf_)) continue;
            // How much the gap grows per unit of weight of each wall corner.
            double rate[3] = {0, 0, 0}, total = 0.0;
            for (int q = 0; q < 3; ++q) {
                if (c.wall[q] == kNotInBand) continue;
                const BandVertex& b = band[c.wall[q]];
                if (b.m >= 1.0 || b.lift * c.sign <= 0) continue;
                double r = c.b[q];
                for (int j = 0; j < 3; ++j)
                    if (c.cap[j] == c.wall[q]) r -= c.a[j];
                rate[q] = r > 0 ? r * (b.lift * c.sign) : 0.0;
                total += rate[q];
            }
            if (!(total > 0)) continue;
            for (int q = 0; q < 3; ++q) {
                if (rate[q] > 0)
                    raise(c.wall[q], std::min(1.0, band[c.wall[q]].m + deficit / total));
            }
        }
    }
}

}  // namespace kerf::cut::detail
