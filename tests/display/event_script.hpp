// The recorded event stream the display tests replay (as ipc records, as kerf-rt publishes them).
#pragma once

#include <cmath>
#include <vector>

#include "display/app/session_events_ipc.hpp"
#include "tests/display/session_scenes.hpp"

namespace kerf::display::test {

using cut::test::kOuterRadius;
using cut::test::kSecondX;

/// The recorded stream: cut 1 through tube 0 (begin, 12 progress steps, completed), the severed
/// end moved away, cut 2 into tube 1 (begin, 5 steps, withdrawn). Progress records carry the
/// feed depth kerf-rt would report (the swept front's advance): 12.0 mm at the end of cut 1,
/// 4.8 mm at the end of cut 2 (the display's HUD shows it; the session does not use it).
inline std::vector<ipc::EventRecord> script() {
    std::vector<ipc::EventRecord> out;
    cut::CutBegin first = cut::test::begin_across(1);
    first.blade = cut::test::blade_across(0.4);
    out.push_back(make_record(first));
    for (int i = 0; i <= 12; ++i) {
        const double front = -kOuterRadius + 2 * kOuterRadius * i / 12.0;
        out.push_back(
            make_record(cut::CutProgress{1, first.blade, {-0.02, front, -0.02, 0.02}}, first));
        out.back().cut.feed_depth_m = float(front + kOuterRadius);  // as kerf-rt reports it
    }
    out.push_back(make_record(cut::CutEnd{1, cut::CutEndKind::kCompleted}, first));
    out.back().cut.feed_depth_m = float(2 * kOuterRadius);
    const double a = 0.1;
    out.push_back(make_record(cut::BodyMoved{
        2, cut::RigidPose{cut::Vec3(0, 0, 0.01), {std::cos(a), 0, 0, std::sin(a)}}}));
    cut::CutBegin second = cut::test::begin_across(2);
    second.body_id = 1;
    second.blade = cut::test::blade_across(-0.3, kSecondX);
    second.blade.point_m[2] = 0.0302;
    second.seed_m = cut::Vec3(kSecondX + kOuterRadius, 0, 0.0302);
    out.push_back(make_record(second));
    for (int i = 0; i < 5; ++i) {
        const double front = -kOuterRadius + kOuterRadius * i / 5.0;
        out.push_back(
            make_record(cut::CutProgress{2, second.blade, {-0.02, front, -0.02, 0.02}}, second));
        out.back().cut.feed_depth_m = float(front + kOuterRadius);
    }
    out.push_back(make_record(cut::CutEnd{2, cut::CutEndKind::kWithdrawn}, second));
    out.back().cut.feed_depth_m = out[out.size() - 2].cut.feed_depth_m;
    return out;
}

}  // namespace kerf::display::test
