#include "display/mesh/foot_generator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "display/mesh/detail/revolve.hpp"
#include "display/mesh/indexed_mesh.hpp"

namespace kerf::mesh {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kJointGapM = 0.0015;

// Dimensions of one ray (metres): x of its axis, z of the metatarsal base, then per bone
// length and mid-shaft radius. Ray 1 (the hallux) has no middle phalanx.
struct RayTemplate {
    double x, z0;
    double length[4];
    double radius[4];
};

constexpr RayTemplate kRays[5] = {
    {+0.030, 0.010, {0.064, 0.030, 0.000, 0.024}, {0.0060, 0.0048, 0.0, 0.0042}},
    {+0.010, 0.000, {0.074, 0.026, 0.012, 0.010}, {0.0040, 0.0030, 0.0024, 0.0022}},
    {-0.006, 0.002, {0.068, 0.023, 0.010, 0.009}, {0.0037, 0.0028, 0.0024, 0.0022}},
    {-0.021, 0.006, {0.064, 0.021, 0.009, 0.009}, {0.0036, 0.0027, 0.0023, 0.0021}},
    {-0.035, 0.012, {0.060, 0.019, 0.008, 0.008}, {0.0038, 0.0026, 0.0022, 0.0020}},
};

// Flare of the base and the head relative to the shaft, per bone kind.
constexpr double kBaseFlare[4] = {1.70, 1.45, 1.40, 1.35};
constexpr double kHeadFlare[4] = {1.45, 1.30, 1.30, 1.25};
constexpr double kCanalRatio = 0.5;  // canal radius / shaft radius

// splitmix64: the same numbers on every compiler and standard library.
class Variation {
public:
    explicit Variation(std::uint64_t seed) : state_(seed) {}
    double symmetric() {  // uniform in [-1, 1)
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return static_cast<double>(z >> 11) * (2.0 / 9007199254740992.0) - 1.0;
    }

private:
    std::uint64_t state_;
};

struct BoneShape {
    BoneInfo info;
    detail::AxisFrame frame;  // u and w scaled by the ellipse's half-axis factors
    double base_flare, head_flare;
};

double end_envelope(double s, double cap) {
    const double d = std::min(s, 1.0 - s);
    if (d >= cap) return 1.0;
    const double t = 1.0 - d / cap;
    return std::sqrt(std::max(0.0, 1.0 - t * t));
}

double outer_radius(const BoneShape& b, double s) {
    const double g0 = std::exp(-12.0 * s * s), g1 = std::exp(-12.0 * (1.0 - s) * (1.0 - s));
    const double r =
        b.info.shaft_radius_m * (1.0 + (b.base_flare - 1.0) * g0 + (b.head_flare - 1.0) * g1);
    const double cap = std::min(0.2, 0.8 * b.info.max_radius_m / b.info.length_m);
    return r * end_envelope(s, cap);
}

// Cosine-spaced stations (denser at the poles) along [a0, a1] with radius `radius(s)`.
template <class Radius>
std::vector<detail::ProfileSample> profile(double a0, double a1, int rings, Radius radius) {
    std::vector<detail::ProfileSample> out;
    for (int k = 0; k <= rings; ++k) {
        const double s = k == rings ? 1.0 : 0.5 * (1.0 - std::cos(kPi * k / rings));
        const bool pole = k == 0 || k == rings;
        out.push_back({a0 + s * (a1 - a0), pole ? 0.0 : radius(s)});
    }
    return out;
}

struct Resolution {
    int outer_segments, outer_rings, canal_segments, canal_rings;
    std::size_t triangles() const {
        return 2u * static_cast<std::size_t>(outer_segments) *
                   static_cast<std::size_t>(outer_rings - 1) +
               2u * static_cast<std::size_t>(canal_segments) *
                   static_cast<std::size_t>(canal_rings - 1);
    }
};

// Rings and segments for a target edge length `h_m`.
Resolution resolution(const BoneInfo& b, double h_m) {
    auto count = [](double v, int min) { return std::max(min, static_cast<int>(std::ceil(v))); };
    const double canal_length = b.canal_end_m - b.canal_start_m;
    return {count(2.0 * kPi * 1.15 * b.shaft_radius_m / h_m, 8),
            count(0.5 * kPi * b.length_m / h_m, 6), count(2.0 * kPi * b.canal_radius_m / h_m, 6),
            count(0.5 * kPi * canal_length / h_m, 4)};
}

std::size_t total_triangles(const std::vector<BoneShape>& bones, double h_m) {
    std::size_t t = 0;
    for (const BoneShape& b : bones) t += resolution(b.info, h_m).triangles();
    return t;
}

// The edge length whose triangle count is nearest the target (bisection on a step function).
double edge_length_for(const std::vector<BoneShape>& bones, std::size_t target) {
    double lo = 1e-5, hi = 0.05, best = hi;  // lo gives too many triangles, hi too few
    auto miss = [&](double h) {
        const double t = static_cast<double>(total_triangles(bones, h));
        return std::abs(t - static_cast<double>(target));
    };
    for (int i = 0; i < 80; ++i) {
        const double mid = std::sqrt(lo * hi);
        if (miss(mid) < miss(best)) best = mid;
        (total_triangles(bones, mid) > target ? lo : hi) = mid;
    }
    return best;
}

detail::AxisFrame ray_frame(const Point& origin, double yaw, double pitch) {
    Point axis{std::sin(yaw), std::sin(pitch), 1.0};
    axis.normalize();
    Point u = Point{0.0, 1.0, 0.0} % axis;
    u.normalize();
    return {origin, axis, u, axis % u};
}

std::vector<BoneShape> lay_out_bones(std::uint64_t seed) {
    Variation v(seed);
    std::vector<BoneShape> bones;
    for (int r = 0; r < 5; ++r) {
        const RayTemplate& t = kRays[r];
        const Point origin{t.x + 0.0003 * v.symmetric(), 0.0003 * v.symmetric(),
                           t.z0 + 0.001 * v.symmetric()};
        // Named, in this order: the order of a call's arguments is unspecified, and gcc -O2 and
        // -O1 (the sanitizer builds) drew these two the other way round (a different foot).
        const double pitch = 0.005 * v.symmetric();
        const double yaw = 0.005 * v.symmetric();
        detail::AxisFrame frame = ray_frame(origin, yaw, pitch);
        for (int k = 0; k < 4; ++k) {
            if (t.length[k] == 0.0) continue;
            BoneShape b;
            b.info.ray = r + 1;
            b.info.kind = static_cast<BoneKind>(k);
            b.info.length_m = t.length[k] * (1.0 + 0.04 * v.symmetric());
            b.info.shaft_radius_m = t.radius[k] * (1.0 + 0.04 * v.symmetric());
            const double ellipse = 1.0 + 0.06 * v.symmetric();
            b.base_flare = kBaseFlare[k];
            b.head_flare = kHeadFlare[k];
            b.info.max_radius_m = b.info.shaft_radius_m * std::max(b.base_flare, b.head_flare) *
                                  std::max(ellipse, 1.0 / ellipse);
            b.info.canal_radius_m = kCanalRatio * b.info.shaft_radius_m;
            const double margin = k == 0 ? 0.25 : 0.32;
            b.info.canal_start_m = margin * b.info.length_m;
            b.info.canal_end_m = (1.0 - margin) * b.info.length_m;
            b.info.base_m = frame.origin;
            b.info.head_m = frame.origin + frame.axis * b.info.length_m;
            b.frame = {frame.origin, frame.axis, frame.u * ellipse, frame.w / ellipse};
            bones.push_back(b);
            frame.origin = b.info.head_m + frame.axis * kJointGapM;
        }
    }
    return bones;
}

void add_bone(IndexedMesh& out, BoneShape& b, const Resolution& res) {
    b.info.first_triangle = out.triangles.size();
    const auto outer = profile(0.0, b.info.length_m, res.outer_rings,
                               [&](double s) { return outer_radius(b, s); });
    detail::add_closed_revolved(out, b.frame, outer, res.outer_segments, true, Material::kCortical);
    const auto canal =
        profile(b.info.canal_start_m, b.info.canal_end_m, res.canal_rings,
                [&](double s) { return b.info.canal_radius_m * end_envelope(s, 0.2); });
    detail::add_closed_revolved(out, b.frame, canal, res.canal_segments, false,
                                Material::kCancellous);
    b.info.triangle_count = out.triangles.size() - b.info.first_triangle;
}

void paint(TriMesh& mesh) {
    for (const VertexHandle v : mesh.vertices()) {
        const bool cortical = mesh.data(v).material() == Material::kCortical;
        mesh.set_color(v, cortical ? TriMesh::Color{0.89f, 0.86f, 0.79f}
                                   : TriMesh::Color{0.78f, 0.50f, 0.42f});
        const Point p = mesh.point(v);  // planar (x, z) texture coordinates, 1 unit = 0.1 m
        mesh.set_texcoord2D(v, TriMesh::TexCoord2D{static_cast<float>(p[0] * 10.0),
                                                   static_cast<float>(p[2] * 10.0)});
    }
}

}  // namespace

std::string_view to_string(BoneKind kind) noexcept {
    switch (kind) {
        case BoneKind::kMetatarsal:
            return "metatarsal";
        case BoneKind::kProximalPhalanx:
            return "proximal_phalanx";
        case BoneKind::kMiddlePhalanx:
            return "middle_phalanx";
        case BoneKind::kDistalPhalanx:
            return "distal_phalanx";
    }
    return "unknown";
}

Result<Foot, std::string> generate_foot(const FootParams& params) {
    if (params.target_triangles < kFootMinTriangles ||
        params.target_triangles > kFootMaxTriangles) {
        return Err{"target_triangles " + std::to_string(params.target_triangles) + " is outside [" +
                   std::to_string(kFootMinTriangles) + ", " + std::to_string(kFootMaxTriangles) +
                   "]"};
    }
    std::vector<BoneShape> bones = lay_out_bones(params.seed);
    const double h = edge_length_for(bones, params.target_triangles);
    IndexedMesh out;
    for (BoneShape& b : bones) add_bone(out, b, resolution(b.info, h));
    Foot foot{build_tri_mesh(out).mesh, {}};
    paint(foot.mesh);
    for (const BoneShape& b : bones) foot.bones.push_back(b.info);
    return foot;
}

}  // namespace kerf::mesh
