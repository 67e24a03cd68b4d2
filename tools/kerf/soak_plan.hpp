// `kerf soak`'s plans: which faults a run injects (parsed from --faults), and one round's random
// cutting scenario — a kerf-hapsim hand script (CSV, tools/hapsim/README.md) of planes, chevrons
// and slabs through the scene's bones, generated from the scene's geometry and kerf-rt's device ->
// world mapping like the demo's (tools/kerf/demo_script.*): world = device origin + device
// position, the blade's edge along +x rising along +y, tilted 5 degrees about its edge per press
// of button 1 (button 2 back). Before each cut the hand presses the blade onto the bone with the
// saw off for 2.5 s. Faults are not in the script: the soak runner injects them while the tool
// pushes (soak_round.cpp). Deterministic for a seed. Units: m, s, degrees.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/result.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cli {

/// A fault the soak injects. Device faults go to kerf-hapsim (`fault <name> <value>` on its
/// command pipe); the others are done to the processes and the segment by the soak runner.
enum class SoakFault : std::uint8_t {
    kDrop,          ///< device replies dropped
    kDelay,         ///< device replies held back 50 ms
    kCorrupt,       ///< one byte of every device reply flipped
    kShort,         ///< device replies cut to half their length
    kUnplug,        ///< the device disconnects, then is plugged back in
    kEStop,         ///< the device's e-stop pressed, then released
    kStuckEncoder,  ///< the device's encoder freezes (the firmware flags it)
    kDisplayKill,   ///< kerf-display SIGKILLed (the supervisor restarts it)
    kDisplayStop,   ///< kerf-display SIGSTOPped for 2 s, then SIGCONT
    kScribble,      ///< random bytes over the segment's rings, records and mesh mailbox for 2 s
};
inline constexpr int kSoakFaultCount = 10;
/// The --faults name ("drop", "display-kill", ...).
std::string_view to_string(SoakFault fault) noexcept;
/// True for the faults kerf-hapsim injects.
bool is_device_fault(SoakFault fault) noexcept;
/// kerf-hapsim's `fault <name> <on>` for a device fault ("delay 50", "stuck_encoder on").
std::string hapsim_on_command(SoakFault fault);
/// ... and the command that clears it ("delay off", "unplug off").
std::string hapsim_off_command(SoakFault fault);

/// Parses --faults: "all", "none", or a comma-separated list of names. Fails naming the
/// unknown name and listing the known ones.
Result<std::vector<SoakFault>, std::string> parse_fault_list(const std::string& list);

/// Where a cut can go: a point over a bone and the bone's top and bottom there (world, m).
struct CutTarget {
    double x_m = 0, z_m = 0;  ///< the blade edge's centre over the bone
    double top_y_m = 0, bottom_y_m = 0;
};

/// One cut of a round, for the report.
struct PlannedCut {
    std::string kind;         ///< "plane", "chevron limb", "slab face"
    double tilt_deg = 0;      ///< blade tilt about its edge
    double feed_m_s = 0;      ///< feed speed through bone
    double feed_start_s = 0;  ///< script time the feed starts
    double feed_end_s = 0;    ///< ... and ends
};

/// One round's hand script.
struct RoundScript {
    std::string csv;
    double duration_s = 0;
    std::vector<PlannedCut> cuts;
};

/// Settings of the generator.
struct RoundScriptParams {
    double duration_s = 60;    ///< about this long (no scenario starts past the middle of its last)
    double step_deg = 5;       ///< kerf-rt's tilt step per button press
    double max_tilt_deg = 30;  ///< tilts drawn from -max..max in steps
    double feed_min_m_s = 0.003;  ///< feed speeds drawn from min..max
    double feed_max_m_s = 0.006;
    double blade_length_m = 0.025;   ///< the force profile's blade_length_m
    double workspace_half_m = 0.08;  ///< the simulated device's workspace, +- each axis
    double start_hold_s = 3;         ///< kerf-display attaches and publishes the scene first
};

/// A script of random planes, chevrons and slabs through `targets` (chosen at random) for a
/// device whose origin is at `device_origin_world_m`, about `params.duration_s` long (at least one
/// scenario).
/// Fails when there is no target or the device's workspace cannot reach one.
Result<RoundScript, std::string> make_round_script(const std::vector<CutTarget>& targets,
                                                   const mesh::Point& device_origin_world_m,
                                                   std::uint64_t seed,
                                                   const RoundScriptParams& params = {});

}  // namespace kerf::cli
