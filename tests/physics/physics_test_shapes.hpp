// Test meshes for kerf_physics, generated in code (icosphere, box, thin plate, wedge) or read from
// a binary STL by the tiny reader below (rt_core may not include OpenMesh), plus brute-force
// references (closest point over every triangle, generalized winding number for inside tests).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "rt_core/physics/collision_body.hpp"
#include "rt_core/physics/collision_mesh.hpp"
#include "rt_core/physics/triangle_geometry.hpp"

namespace kerf::physics::test {

/// A mesh owned by the test, viewable as a CollisionMeshView.
struct TestMesh {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::vector<Material> materials;
    RigidTransform pose;

    CollisionMeshView view() const { return {positions, indices, materials, pose}; }
    std::size_t triangles() const { return indices.size() / 3; }
    Vec3 vertex(std::uint32_t i) const {
        return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
    }
    std::uint32_t add_vertex(const Vec3& p) {
        positions.push_back(float(p.x)), positions.push_back(float(p.y)),
            positions.push_back(float(p.z));
        return std::uint32_t(positions.size() / 3 - 1);
    }
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c,
                      Material m = Material::kCortical) {
        indices.insert(indices.end(), {a, b, c});
        materials.push_back(m);
    }
};

/// An icosphere of `radius` around `centre`, subdivided `levels` times (20 * 4^levels triangles).
inline TestMesh make_sphere(const Vec3& centre, double radius, int levels) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                           {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                           {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::uint32_t> f = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                    1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                    3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                    4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
    for (Vec3& p : v) p = normalized(p);
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        const auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalized(v[a] + v[b]));
            return mid[key] = std::uint32_t(v.size() - 1);
        };
        std::vector<std::uint32_t> g;
        for (std::size_t i = 0; i < f.size(); i += 3) {
            const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f.swap(g);
    }
    TestMesh m;
    for (const Vec3& p : v) m.add_vertex(centre + p * radius);
    for (std::size_t i = 0; i < f.size(); i += 3) m.add_triangle(f[i], f[i + 1], f[i + 2]);
    return m;
}

/// A closed box [lo, hi] (a thin plate when one side is small), outward winding.
inline TestMesh make_box(const Vec3& lo, const Vec3& hi) {
    TestMesh m;
    for (int i = 0; i < 8; ++i) {
        m.add_vertex({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    }
    const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                   {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : q) {
        m.add_triangle(f[0], f[1], f[2]);
        m.add_triangle(f[0], f[2], f[3]);
    }
    return m;
}

/// Splits every triangle into 4 (midpoints), `levels` times: more triangles, same surface.
inline TestMesh refine(const TestMesh& in, int levels) {
    TestMesh m = in;
    for (int l = 0; l < levels; ++l) {
        TestMesh out;
        out.positions = m.positions;
        out.pose = m.pose;
        out.positions.reserve(m.positions.size() * 4);
        out.indices.reserve(m.indices.size() * 4);
        out.materials.reserve(m.materials.size() * 4);
        std::unordered_map<std::uint64_t, std::uint32_t> mid;
        mid.reserve(m.indices.size() * 2);
        const auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            auto [it, added] = mid.try_emplace(key, 0);
            if (added) it->second = out.add_vertex((m.vertex(a) + m.vertex(b)) * 0.5);
            return it->second;
        };
        for (std::size_t i = 0; i < m.indices.size(); i += 3) {
            const std::uint32_t a = m.indices[i], b = m.indices[i + 1], c = m.indices[i + 2];
            const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            const Material mat = m.materials[i / 3];
            out.add_triangle(a, ab, ca, mat), out.add_triangle(b, bc, ab, mat);
            out.add_triangle(c, ca, bc, mat), out.add_triangle(ab, bc, ca, mat);
        }
        m = std::move(out);
    }
    return m;
}

/// Reads a binary STL (welding bit-identical corners), scaling coordinates by `scale` (mm -> m:
/// 0.001). Empty mesh on any problem.
inline TestMesh read_binary_stl(const std::string& path, double scale) {
    TestMesh m;
    std::ifstream in(path, std::ios::binary);
    char header[80];
    std::uint32_t count = 0;
    if (!in.read(header, 80) || !in.read(reinterpret_cast<char*>(&count), 4)) return {};
    std::map<std::tuple<float, float, float>, std::uint32_t> welded;
    for (std::uint32_t t = 0; t < count; ++t) {
        char rec[50];
        if (!in.read(rec, 50)) return {};
        std::uint32_t corner[3];
        for (int k = 0; k < 3; ++k) {
            float p[3];
            std::memcpy(p, rec + 12 + 12 * k, 12);
            const auto key = std::make_tuple(p[0], p[1], p[2]);
            auto it = welded.find(key);
            corner[k] = it != welded.end()
                            ? it->second
                            : (welded[key] = m.add_vertex(Vec3{p[0], p[1], p[2]} * scale));
        }
        m.add_triangle(corner[0], corner[1], corner[2]);
    }
    return m;
}

/// Brute-force nearest surface distance from `p`.
inline double brute_distance(const TestMesh& m, const Vec3& p) {
    double best = 1e300;
    for (std::size_t i = 0; i < m.indices.size(); i += 3) {
        const Vec3 q = closest_point_on_triangle(
            p, m.vertex(m.indices[i]), m.vertex(m.indices[i + 1]), m.vertex(m.indices[i + 2]));
        best = std::min(best, norm(q - p));
    }
    return best;
}

/// Generalized winding number of `p` (about 1 inside a closed outward mesh, 0 outside).
inline double winding_number(const TestMesh& m, const Vec3& p) {
    double total = 0;
    for (std::size_t i = 0; i < m.indices.size(); i += 3) {
        const Vec3 a = m.vertex(m.indices[i]) - p, b = m.vertex(m.indices[i + 1]) - p,
                   c = m.vertex(m.indices[i + 2]) - p;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double num = dot(a, cross(b, c));
        const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
        total += 2 * std::atan2(num, den);
    }
    return total / (4 * M_PI);
}

/// A slow walk over the surface: `ticks` points circling the body's centre, each projected onto
/// the surface and offset along the surface normal by `offset_min_m..offset_max_m` (negative:
/// inside), varying slowly. About 5-30 mm/s along the surface: what a hand does.
inline std::vector<Vec3> surface_walk(const CollisionBody& body, int ticks, double offset_min_m,
                                      double offset_max_m) {
    Vec3 lo, hi;
    body.bounds(lo, hi);
    const Vec3 centre = (lo + hi) * 0.5;
    const double radius = 0.5 * norm(hi - lo);
    std::vector<Vec3> path;
    path.reserve(std::size_t(ticks));
    for (int i = 0; i < ticks; ++i) {
        const double a = 2 * M_PI * i / 40000.0, b = 0.7 * std::sin(2 * M_PI * i / 23000.0);
        const Vec3 far =
            centre +
            Vec3{std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)} * radius;
        const SurfaceHit hit = body.closest_point(far, 10 * radius);
        const double s = 0.5 + 0.5 * std::sin(2 * M_PI * i / 1700.0);
        path.push_back(hit.point + hit.normal * (offset_min_m + s * (offset_max_m - offset_min_m)));
    }
    return path;
}

}  // namespace kerf::physics::test
