#include "tools/kerf/demo_chevron.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace kerf::cli {
namespace {

/// Distance along the ray to triangle (a, b, c) (Moller-Trumbore), or infinity.
double ray_triangle(const cut::Vec3& o, const cut::Vec3& d, const cut::Vec3& a, const cut::Vec3& b,
                    const cut::Vec3& c) {
    const cut::Vec3 e1 = b - a;
    const cut::Vec3 e2 = c - a;
    const cut::Vec3 p = OpenMesh::cross(d, e2);
    const double det = OpenMesh::dot(e1, p);
    if (std::abs(det) < 1e-30) return std::numeric_limits<double>::infinity();
    const cut::Vec3 s = o - a;
    const double u = OpenMesh::dot(s, p) / det;
    const cut::Vec3 q = OpenMesh::cross(s, e1);
    const double v = OpenMesh::dot(d, q) / det;
    const double t = OpenMesh::dot(e2, q) / det;
    if (u < 0 || v < 0 || u + v > 1 || t <= 0) return std::numeric_limits<double>::infinity();
    return t;
}

/// The farthest hit of the ray on the bone's triangles (its outer surface, past the canal).
double farthest_hit(const mesh::TriMesh& m, const mesh::BoneInfo& bone, const cut::Vec3& o,
                    const cut::Vec3& d) {
    double best = -1.0;
    for (std::size_t i = bone.first_triangle; i < bone.first_triangle + bone.triangle_count; ++i) {
        auto it = m.cfv_iter(mesh::FaceHandle(static_cast<int>(i)));
        const auto a = m.point(*it++);
        const auto b = m.point(*it++);
        const double t = ray_triangle(o, d, a, b, m.point(*it));
        if (std::isfinite(t)) best = std::max(best, t);
    }
    return best;
}

}  // namespace

Result<CutJob, std::string> chevron_job(const mesh::Foot& foot, const mesh::BoneInfo& bone,
                                        double apex_fraction) {
    const cut::Vec3 axis = (bone.head_m - bone.base_m).normalized();
    // The generator spreads the rays along x: that is the mediolateral direction.
    cut::Vec3 lateral = cut::Vec3(1, 0, 0) - axis * axis[0];
    if (lateral.norm() < 1e-6) return Err{std::string("bone axis runs along x")};
    lateral.normalize();
    const cut::Vec3 dorsal = OpenMesh::cross(axis, lateral);
    const cut::Vec3 apex = bone.base_m + (bone.head_m - bone.base_m) * apex_fraction;
    const double t = farthest_hit(foot.mesh, bone, apex, lateral);
    if (t <= 0) return Err{std::string("no bone surface beside the apex")};
    CutJob job;
    const double half_angle = M_PI / 6.0;  // 30 degrees each side: a 60-degree V
    for (const double side : {1.0, -1.0}) {
        const cut::Vec3 limb =
            -axis * std::cos(half_angle) + dorsal * (side * std::sin(half_angle));
        job.planes.push_back({apex, OpenMesh::cross(lateral, limb).normalized()});
    }
    job.seeds_m.push_back(apex + lateral * t);
    job.mode = CutMode::kUniplanar;
    return job;
}

Result<ChevronReport, std::string> cut_chevron(mesh::Foot& foot) {
    const auto start = std::chrono::steady_clock::now();
    const mesh::BoneInfo bone = foot.first_metatarsal();
    auto job = chevron_job(foot, bone);
    if (!job) return Err{job.error()};
    ChevronReport r;
    r.job = *job;
    r.apex_m = job->planes[0].point_m;
    r.seed_m = job->seeds_m[0];
    const std::size_t faces_before = foot.mesh.n_faces();
    auto cuts = run_cut_job(foot.mesh, *job);
    if (!cuts) {
        return Err{"plane " + std::to_string(cuts.error().plane + 1) + ": " + cuts.error().why};
    }
    r.cuts = std::move(*cuts);
    // The bone's pieces: bodies holding one of its original faces or a face the cuts added.
    for (std::size_t k = 0; k < r.cuts.pieces.size(); ++k) {
        for (const auto f : r.cuts.pieces[k].faces) {
            const auto i = static_cast<std::size_t>(f.idx());
            if ((i >= bone.first_triangle && i < bone.first_triangle + bone.triangle_count) ||
                i >= faces_before) {
                r.fragments.push_back(k);
                break;
            }
        }
    }
    r.elapsed_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return r;
}

}  // namespace kerf::cli
