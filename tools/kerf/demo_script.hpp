// The demo's scripted surgeon: a kerf-hapsim hand script (CSV, tools/hapsim/README.md) that cuts
// a chevron osteotomy of the first metatarsal through kerf-rt and shifts the freed head,
// generated from the scene's geometry and kerf-rt's device -> world mapping (world = device
// origin + device position: scale 1, no rotation; the origin is above the centre of the scene's
// bounding box, 20 mm over its top).
//
// The chevron: a V in the sagittal plane whose apex lies on the bone's axis in the head, its two
// limbs running proximally at `half_angle_deg` either side of the axis (dorsal and plantar), each
// limb's plane containing the medial-lateral direction, so the head can slide laterally along
// both. The blade without a sensed orientation takes the planned cut's pose (edge along +x,
// medial-lateral; the blade rising along +y; normal +z) and tilts `step_deg` about its edge per
// press of button 1 (button 2 back). Each limb: approach beside the bone, tilt onto the limb,
// saw on (button 0 held), feed along the limb towards the apex at a surgeon's feed speed — touch
// (kerf-rt locks the plane: CutBegin), dorsal (or plantar) cortex, canal — until the edge is
// `past_apex_m` past the apex, hold while the last progress is reported, withdraw along the kerf
// with the saw running (kerf-rt: CutEnd withdrawn), saw off. The dorsal limb is cut from above,
// the plantar one from below (the hand goes round the medial side). The two withdrawn limbs meet
// inside the bone, so the head comes free (CutSession: one more body). Then the hand holds the
// head (button 3 near its dorsal surface: kerf-rt's grab, BodyMoved) and shifts it `shift_m`
// laterally, the correction a chevron bunionectomy makes, and lets go. Units: m, s, degrees.
#pragma once

#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "display/mesh/foot_generator.hpp"

namespace kerf::cli {

/// What the script does, for the report and the tests.
struct DemoScript {
    std::string csv;                  ///< the hapsim script
    double duration_s = 0;            ///< time the hand takes, s
    mesh::Point apex_world_m;         ///< where the two limbs meet (on the bone's axis)
    std::vector<double> tilt_deg;     ///< each limb's blade tilt about its edge
    double half_angle_deg = 0;        ///< each limb's angle to the bone's axis (quantised tilt)
    double feed_speed_m_s = 0;        ///< feed speed through bone
    std::vector<double> cut_start_s;  ///< when each limb's feed starts (script time)
    mesh::Point grab_world_m;         ///< where the hand takes hold of the head
    mesh::Point shift_m;              ///< how the hand moves the head (world frame)
};

/// Settings of the generator.
struct DemoScriptParams {
    double half_angle_deg = 30;         ///< each limb this far from the bone's axis
    double step_deg = 5;                ///< kerf-rt's tilt step per button press
    double feed_speed_m_s = 0.004;      ///< 4 mm/s: an oscillating saw through a metatarsal
    double withdraw_speed_m_s = 0.008;  ///< back out along the kerf, saw running
    double apex_fraction = 0.8;         ///< apex along the first metatarsal's axis from its base
    double past_apex_m = 0.0003;        ///< each limb's edge this far past the apex
    double shift_m = 0.004;             ///< lateral shift of the freed head
    double blade_length_m = 0.025;      ///< the force profile's blade_length_m
    double workspace_half_m = 0.08;     ///< the simulated device's workspace, +- each axis
    int grab_button = 3;                ///< kerf-rt's GrabPlan::button
};

/// The script for the first metatarsal `m1` (its neighbour, the second metatarsal `m2`, says
/// which side is lateral and how far the blade's edge may reach), with the device origin at
/// `device_origin_world_m`. Fails when the blade cannot span the bone between its neighbours or
/// the surgery lies outside the device's workspace.
Result<DemoScript, std::string> make_demo_script(const mesh::BoneInfo& m1, const mesh::BoneInfo& m2,
                                                 const mesh::Point& device_origin_world_m,
                                                 const DemoScriptParams& params = {});

}  // namespace kerf::cli
