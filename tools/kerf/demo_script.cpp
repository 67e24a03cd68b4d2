#include "tools/kerf/demo_script.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tools/kerf/hand_script_writer.hpp"

namespace kerf::cli {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// One limb of the chevron as the hand cuts it.
struct Limb {
    int steps = 0;      ///< tilt button presses from the planned pose (negative: button 2)
    mesh::Point v;      ///< the tilted blade's edge -> back direction (the hand feeds along -v)
    mesh::Point start;  ///< edge centre clear of the bone on the limb's line, saw starting
    mesh::Point end;    ///< edge centre just past the apex
    mesh::Point aside;  ///< further out along the limb: where the blade is tilted
};

/// The limb on `side` (+1 dorsal, -1 plantar) of the bone's sagittal axis `a`.
Limb make_limb(const mesh::Point& apex, const mesh::Point& a, const mesh::Point& dorsal,
               double side, double clear_radius_m, const DemoScriptParams& p) {
    const double h = p.half_angle_deg * kPi / 180.0, step = p.step_deg * kPi / 180.0;
    const mesh::Point along = -a * std::cos(h) + dorsal * (side * std::sin(h));  // apex -> out
    Limb l;
    l.steps = static_cast<int>(std::lround(std::atan2(along[2], along[1]) / step));
    const double theta = l.steps * step;
    l.v = mesh::Point{0, std::cos(theta), std::sin(theta)};
    // Out along the limb until the edge's line is `clear_radius_m` from the axis.
    const double sin_to_axis = OpenMesh::cross(l.v, a).norm();
    l.start = apex + l.v * (clear_radius_m / sin_to_axis);
    l.end = apex - l.v * p.past_apex_m;
    l.aside = l.start + l.v * 0.015;
    return l;
}

/// Feeds one limb: tilt, saw on, touch and cut to just past the apex, hold, withdraw along the
/// kerf with the saw running (kerf-rt: CutEnd withdrawn), saw off, back out.
void cut_limb(HandScriptWriter& w, const Limb& l, int& steps_now, const DemoScriptParams& p,
              DemoScript& out) {
    if (l.steps > steps_now) w.press(1, l.steps - steps_now);
    if (l.steps < steps_now) w.press(2, steps_now - l.steps);
    steps_now = l.steps;
    w.move(l.start, 0.8);
    w.hold(0.2);
    w.button(0, true);  // saw on
    w.hold(0.3);
    out.cut_start_s.push_back(w.time());
    const double path_m = (l.start - l.end).norm();
    w.move(l.end, path_m / p.feed_speed_m_s);  // touch, lock, cortex, canal, past the apex
    // The hand lags its target by the feed resistance over its spring (~0.4 mm at 4 mm/s) and
    // settles with a time constant of a few tenths of a second: hold until the edge is there and
    // the last progress was reported.
    w.hold(1.0);
    w.move(l.start, path_m / p.withdraw_speed_m_s);  // back along the kerf, saw running
    w.button(0, false);                              // saw off, clear of the bone
    w.hold(0.2);
    w.move(l.aside, 0.8);
    out.tilt_deg.push_back(l.steps * p.step_deg);
}

}  // namespace

Result<DemoScript, std::string> make_demo_script(const mesh::BoneInfo& m1, const mesh::BoneInfo& m2,
                                                 const mesh::Point& device_origin_world_m,
                                                 const DemoScriptParams& p) {
    if (!(m1.length_m > 0) || !(m1.max_radius_m > 0))
        return Err{std::string("first metatarsal: no length or radius")};
    // The blade tilts about the world x axis only: the chevron lies in the (y, z) plane.
    mesh::Point a = m1.head_m - m1.base_m;
    a[0] = 0;
    if (!(a.norm() > 0.5 * m1.length_m))
        return Err{std::string("first metatarsal: its axis is not along the foot")};
    a.normalize();
    const mesh::Point up{0, 1, 0};
    const mesh::Point dorsal = (up - a * OpenMesh::dot(up, a)).normalized();
    const double medial = m1.head_m[0] >= m2.head_m[0] ? 1.0 : -1.0;
    // The edge's lateral end halfway between the first and second metatarsals; the edge runs on
    // medially across the whole first metatarsal.
    const double bone_lateral = m1.head_m[0] - medial * m1.max_radius_m;
    const double neighbour_medial = m2.head_m[0] + medial * m2.max_radius_m;
    const double lateral_end = 0.5 * (bone_lateral + neighbour_medial);
    if (medial * (bone_lateral - neighbour_medial) <= 0)
        return Err{std::string("first and second metatarsals overlap: no room for the blade")};
    if (medial * (lateral_end - m1.head_m[0]) + p.blade_length_m < m1.max_radius_m + 0.001)
        return Err{std::string("the blade is too short to span the first metatarsal")};
    const double edge_x = lateral_end + medial * p.blade_length_m / 2;
    const mesh::Point on_axis = m1.base_m + (m1.head_m - m1.base_m) * p.apex_fraction;
    const mesh::Point apex{edge_x, on_axis[1], on_axis[2]};
    const double clear_radius = m1.max_radius_m + 0.001;  // 1 mm clear of the widest flare
    const Limb dorsal_limb = make_limb(apex, a, dorsal, +1, clear_radius, p);
    const Limb plantar_limb = make_limb(apex, a, dorsal, -1, clear_radius, p);
    const mesh::Point round{medial * (p.blade_length_m + 0.01), 0, 0};  // edge clear, medially

    DemoScript out;
    out.apex_world_m = on_axis;
    out.feed_speed_m_s = p.feed_speed_m_s;
    out.half_angle_deg = std::asin(OpenMesh::cross(dorsal_limb.v, a).norm()) * 180.0 / kPi;
    HandScriptWriter w(device_origin_world_m);
    int steps = 0;
    w.hold(3.0);  // kerf-display attaches and publishes the scene's collision mesh
    // Approach over the dorsum, then the dorsal limb from above.
    w.move({dorsal_limb.aside[0], device_origin_world_m[1], dorsal_limb.aside[2]}, 1.0);
    w.move(dorsal_limb.aside, 1.0);
    cut_limb(w, dorsal_limb, steps, p, out);
    // Round the medial side of the bone to below it, then the plantar limb from below.
    w.move(dorsal_limb.aside + round, 1.0);
    w.move(plantar_limb.aside + round, 1.5);
    if (plantar_limb.steps < steps) w.press(2, steps - plantar_limb.steps);
    if (plantar_limb.steps > steps) w.press(1, plantar_limb.steps - steps);
    steps = plantar_limb.steps;
    w.move(plantar_limb.aside, 1.0);
    cut_limb(w, plantar_limb, steps, p, out);
    // The head is free: back round the medial side, blade to the planned pose, take hold of
    // the head just above its dorsal surface, shift it laterally, let go.
    w.move(plantar_limb.aside + round, 1.0);
    w.press(steps < 0 ? 1 : 2, std::abs(steps));
    const mesh::Point in_head =
        m1.base_m + (m1.head_m - m1.base_m) * (p.apex_fraction + 0.4 * (1 - p.apex_fraction));
    mesh::Point grab = in_head + dorsal * (m1.max_radius_m + 0.001);
    grab[0] = edge_x;
    const mesh::Point above = grab + up * 0.01;
    const mesh::Point shift{-medial * p.shift_m, 0, 0};
    w.move(above + round, 1.5);
    w.move(above, 1.0);
    w.move(grab, 0.8);
    w.hold(0.3);
    w.button(p.grab_button, true);  // kerf-rt takes the nearest body: the head
    w.hold(0.3);
    w.move(grab + shift, p.shift_m / 0.002);  // 2 mm/s
    w.hold(0.3);
    w.button(p.grab_button, false);
    w.hold(0.3);
    w.move(above + shift, 0.8);
    w.move(device_origin_world_m, 1.0);  // home
    w.hold(0.5);
    out.grab_world_m = grab;
    out.shift_m = shift;
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
