// The demo's scripted surgeon: a kerf-hapsim hand script (CSV, tools/hapsim/README.md) that cuts
// a V osteotomy of the first metatarsal through kerf-rt, generated from the scene's geometry and
// kerf-rt's device -> world mapping (world = device origin + device position: scale 1, no
// rotation; the origin is above the centre of the scene's bounding box, 20 mm over its top).
//
// The blade without a sensed orientation takes the planned cut's pose (edge along +x, the blade
// rising along +y, normal +z) and tilts 5 degrees about its edge per press of button 1 (button 2
// back). Each limb: approach above the entry, tilt, saw on (button 0 held), feed along the tilted
// blade's -v through dorsal cortex, canal and plantar cortex at a surgeon's feed speed until the
// edge has left the bone (kerf-rt: CutEnd completed), saw off, withdraw up the kerf, untilt.
// The two limbs meet just plantar of the bone, so the bone falls into three pieces: the proximal
// shaft, the dorsal wedge between the limbs, and the freed head. Units: m, s, degrees.
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
    mesh::Point apex_world_m;         ///< where the two limbs meet (just plantar of the bone)
    std::vector<double> tilt_deg;     ///< each limb's blade tilt about its edge
    double feed_speed_m_s = 0;        ///< feed speed through bone
    std::vector<double> cut_start_s;  ///< when each limb's feed starts (script time)
};

/// Settings of the generator.
struct DemoScriptParams {
    double limb_tilt_deg = 30;       ///< each limb this far either side of the transverse plane
    double step_deg = 5;             ///< kerf-rt's tilt step per button press
    double feed_speed_m_s = 0.004;   ///< 4 mm/s: an oscillating saw through a metatarsal
    double apex_fraction = 0.7;      ///< apex along the first metatarsal's axis from its base
    double blade_length_m = 0.025;   ///< the force profile's blade_length_m
    double workspace_half_m = 0.08;  ///< the simulated device's workspace, +- each axis
};

/// The script for the first metatarsal `m1` (its neighbour `m2` says which side is lateral),
/// with the device origin at `device_origin_world_m`. Fails when the cut lies outside the
/// device's workspace.
Result<DemoScript, std::string> make_demo_script(const mesh::BoneInfo& m1, const mesh::BoneInfo& m2,
                                                 const mesh::Point& device_origin_world_m,
                                                 const DemoScriptParams& params = {});

}  // namespace kerf::cli
