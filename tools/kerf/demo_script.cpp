#include "tools/kerf/demo_script.hpp"

#include <cmath>
#include <cstdio>

#include "tools/kerf/hand_script_writer.hpp"

namespace kerf::cli {
namespace {

constexpr double kPi = 3.14159265358979323846;

using ScriptWriter = HandScriptWriter;

}  // namespace

Result<DemoScript, std::string> make_demo_script(const mesh::BoneInfo& m1, const mesh::BoneInfo& m2,
                                                 const mesh::Point& device_origin_world_m,
                                                 const DemoScriptParams& p) {
    if (!(m1.length_m > 0) || !(m1.shaft_radius_m > 0))
        return Err{std::string("first metatarsal: no length or radius")};
    const mesh::Point axis_point = m1.base_m + (m1.head_m - m1.base_m) * p.apex_fraction;
    const double medial = axis_point[0] >= m2.base_m[0] ? 1.0 : -1.0;
    const double r = 1.25 * m1.shaft_radius_m;  // the shaft's ellipse and flare, with margin
    // The edge reaches 1.5 mm lateral of the bone and runs on medially (away from the second ray).
    const double edge_x = axis_point[0] + medial * (p.blade_length_m / 2 - r - 0.0015);
    const mesh::Point apex{edge_x, axis_point[1] - r - 0.001, axis_point[2]};

    DemoScript out;
    out.apex_world_m = {axis_point[0], apex[1], apex[2]};
    out.feed_speed_m_s = p.feed_speed_m_s;
    ScriptWriter w(device_origin_world_m);
    w.hold(3.0);  // kerf-display attaches and publishes the scene's collision mesh
    const int steps = static_cast<int>(std::lround(p.limb_tilt_deg / p.step_deg));
    for (const int sign : {+1, -1}) {  // dorsal-proximal limb first, then the distal one
        const double theta = sign * steps * p.step_deg * kPi / 180.0;
        const mesh::Point v{0, std::cos(theta), std::sin(theta)};  // blade edge -> back
        const double above_bone = 2 * r + 0.001 + 0.005;           // 5 mm clear of the top
        const mesh::Point start = apex + v * (above_bone / std::cos(theta));
        // Through: the edge leaves the plantar cortex 4 mm past the apex (CutEnd completed).
        const mesh::Point end = apex - v * 0.004;
        const mesh::Point below = end - mesh::Point{0, 0.015, 0};
        const mesh::Point around = below + mesh::Point{medial * (p.blade_length_m + 0.01), 0, 0};
        const mesh::Point approach = start + mesh::Point{0, 0.015, 0};
        w.move(approach, 1.5);  // approach over the dorsum
        w.press(sign > 0 ? 1 : 2, steps);
        w.move(start, 0.8);  // down to just above the bone
        w.hold(0.2);
        w.button(0, true);  // saw on
        w.hold(0.3);
        out.cut_start_s.push_back(w.time());
        w.move(end, (start - end).norm() / p.feed_speed_m_s);  // touch, lock, cortex, canal
        w.button(0, false);  // saw off, the edge in the clear below the bone
        w.hold(3.0);         // the display opens the kerf and publishes the pieces
        w.move(below, 1.0);  // out plantarwards, medially round the bone and back up
        w.move(around, 1.0);
        w.move(around + mesh::Point{0, 4 * r + 0.03, 0}, 1.0);
        w.press(sign > 0 ? 2 : 1, steps);  // back to the planned pose
        out.tilt_deg.push_back(sign * steps * p.step_deg);
    }
    w.move(device_origin_world_m, 1.0);  // home
    w.hold(0.5);
    if (w.max_abs() > p.workspace_half_m - 0.005) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "the cut is %.1f mm from the device origin, beyond the workspace (+-%.0f mm)",
                      w.max_abs() * 1e3, p.workspace_half_m * 1e3);
        return Err{std::string(buf)};
    }
    out.csv = w.text();
    out.duration_s = w.time();
    return out;
}

}  // namespace kerf::cli
