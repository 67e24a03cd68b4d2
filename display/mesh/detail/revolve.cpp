#include "display/mesh/detail/revolve.hpp"

#include <cmath>
#include <numbers>

namespace kerf::mesh::detail {
namespace {

void push(IndexedMesh& out, std::uint32_t a, std::uint32_t b, std::uint32_t c, bool keep) {
    out.triangles.push_back(keep ? Triangle{a, b, c} : Triangle{a, c, b});
}

}  // namespace

std::uint32_t add_ring(IndexedMesh& out, const AxisFrame& f, const ProfileSample& s, int segments,
                       Material material) {
    const auto first = static_cast<std::uint32_t>(out.positions_m.size());
    const int count = s.radius_m == 0.0 ? 1 : segments;
    for (int i = 0; i < count; ++i) {
        const double theta = 2.0 * std::numbers::pi * i / segments;
        const double c = s.radius_m * std::cos(theta);
        const double sn = s.radius_m * std::sin(theta);
        out.positions_m.push_back(f.origin + f.axis * s.axial_m + f.u * c + f.w * sn);
        out.materials.push_back(material);
    }
    return first;
}

void join_rings(IndexedMesh& out, std::uint32_t a, bool a_pole, std::uint32_t b, bool b_pole,
                int segments, bool outward) {
    const auto n = static_cast<std::uint32_t>(segments);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % n;
        if (a_pole) {
            push(out, a, b + j, b + i, outward);
        } else if (b_pole) {
            push(out, a + i, a + j, b, outward);
        } else {
            push(out, a + i, a + j, b + j, outward);
            push(out, a + i, b + j, b + i, outward);
        }
    }
}

void add_closed_revolved(IndexedMesh& out, const AxisFrame& f,
                         const std::vector<ProfileSample>& profile, int segments, bool outward,
                         Material material) {
    std::uint32_t previous = add_ring(out, f, profile.front(), segments, material);
    bool previous_pole = true;
    for (std::size_t k = 1; k < profile.size(); ++k) {
        const bool pole = k + 1 == profile.size();
        const ProfileSample s = pole ? ProfileSample{profile[k].axial_m, 0.0} : profile[k];
        const std::uint32_t ring = add_ring(out, f, s, segments, material);
        join_rings(out, previous, previous_pole, ring, pole, segments, outward);
        previous = ring;
        previous_pole = false;
    }
}

}  // namespace kerf::mesh::detail
