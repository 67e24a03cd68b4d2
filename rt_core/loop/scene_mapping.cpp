#include "rt_core/loop/scene_mapping.hpp"

#include <cmath>
#include <cstdio>

#include "rt_core/loop/collision_mesh_builder.hpp"

namespace kerf::rt {

physics::Mat3 rotation_from_quaternion(const std::array<double, 4>& q) noexcept {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    physics::Mat3 r;
    r.m[0][0] = 1 - 2 * (y * y + z * z), r.m[0][1] = 2 * (x * y - w * z);
    r.m[0][2] = 2 * (x * z + w * y);
    r.m[1][0] = 2 * (x * y + w * z), r.m[1][1] = 1 - 2 * (x * x + z * z);
    r.m[1][2] = 2 * (y * z - w * x);
    r.m[2][0] = 2 * (x * z - w * y), r.m[2][1] = 2 * (y * z + w * x);
    r.m[2][2] = 1 - 2 * (x * x + y * y);
    return r;
}

physics::Mat3 blade_axes_of(const config::PlannedCut& cut) noexcept {
    const physics::Vec3 n{cut.normal[0], cut.normal[1], cut.normal[2]};
    const physics::Vec3 u{cut.edge[0], cut.edge[1], cut.edge[2]};
    const physics::Vec3 v = physics::cross(n, u);
    physics::Mat3 r;
    const physics::Vec3 cols[3] = {u, v, n};
    for (int c = 0; c < 3; ++c) {
        r.m[0][c] = cols[c].x, r.m[1][c] = cols[c].y, r.m[2][c] = cols[c].z;
    }
    return r;
}

void apply_scene_mapping(const config::Scene& scene, const ipc::CollisionMesh& mesh,
                         LoopSettings& settings) {
    const config::DeviceMapping& m = scene.device_mapping;
    settings.device_origin_in_world_m =
        m.origin_given ? physics::Vec3{m.origin_m[0], m.origin_m[1], m.origin_m[2]}
                       : device_origin_above(mesh);
    settings.motion_scale = m.scale;
    settings.blade.world_from_device = rotation_from_quaternion(m.rotation_wxyz);
    if (scene.has_planned_cut) settings.blade.planned = blade_axes_of(scene.planned_cut);
}

std::string describe_mapping(const config::Scene& scene, const LoopSettings& s) {
    const auto& o = s.device_origin_in_world_m;
    const auto& q = scene.device_mapping.rotation_wxyz;
    char buf[512];
    int n = std::snprintf(buf, sizeof buf,
                          "device mapping: origin (%.4f, %.4f, %.4f) m%s, scale %.3g, rotation "
                          "wxyz (%.4f, %.4f, %.4f, %.4f)",
                          o.x, o.y, o.z,
                          scene.device_mapping.origin_given ? "" : " (20 mm above the scene)",
                          s.motion_scale, q[0], q[1], q[2], q[3]);
    if (scene.has_planned_cut && n > 0 && std::size_t(n) < sizeof buf) {
        const auto& c = scene.planned_cut;
        std::snprintf(buf + n, sizeof buf - std::size_t(n),
                      "; planned cut through (%.4f, %.4f, %.4f) m, normal (%.3f, %.3f, %.3f)",
                      c.point_m[0], c.point_m[1], c.point_m[2], c.normal[0], c.normal[1],
                      c.normal[2]);
    }
    return buf;
}

}  // namespace kerf::rt
