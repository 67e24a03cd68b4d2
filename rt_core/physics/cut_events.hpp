// Cut events as the saw model emits them: plain structs, world frame, SI, double precision. The
// loop maps each field 1:1 onto rt_core/ipc/records.hpp CutPayload (EventType kCutBegin /
// kCutProgress / kCutEnd), narrowing to float:
//   cut_id, body_id, plane_point_m, plane_normal, plane_u, seed_point_m, triangle_hint,
//   blade.length_m -> blade_length_m, blade.depth_m -> blade_depth_m,
//   blade.kerf_width_m -> kerf_width_m, swept.{u,v}_{min,max}_m -> swept_{u,v}_{min,max}_m,
//   feed_depth_m, end_reason (same numeric values as ipc::CutEndReason).
// Every event of one cut carries the same plane, seed and blade (the display may start from any).
#pragma once

#include <cstdint>
#include <string_view>

#include "rt_core/physics/collision_body.hpp"

namespace kerf::physics {

enum class CutEventType : std::uint8_t { kBegin = 1, kProgress = 2, kEnd = 3 };
std::string_view to_string(CutEventType type) noexcept;

/// Why a cut ended; values equal ipc::CutEndReason.
enum class CutEndReason : std::uint32_t { kNone = 0, kCompleted = 1, kWithdrawn = 2, kAborted = 3 };
std::string_view to_string(CutEndReason reason) noexcept;

/// The blade as an oriented thin box: edge along u (length), from the edge towards the back along
/// v (depth), thickness along the normal (kerf width). m.
struct BladeGeometry {
    double length_m = 0.025;
    double depth_m = 0.010;
    double kerf_width_m = 0.0008;
};

/// A rectangle in the cut plane's (u, v) frame: origin plane_point_m, v = normal x u. m.
struct SweptRect {
    double u_min_m = 0, u_max_m = 0;
    double v_min_m = 0, v_max_m = 0;
};

/// One cut event (begin, progress or end).
struct CutEvent {
    CutEventType type = CutEventType::kBegin;
    std::uint32_t cut_id = 0;   ///< +1 per cut in the session (the first cut is 1)
    std::uint32_t body_id = 0;  ///< world slot of the body being cut
    Vec3 plane_point_m;         ///< blade edge centre at first contact (origin of (u, v)), m
    Vec3 plane_normal;          ///< locked plane normal (the blade's normal at first contact)
    Vec3 plane_u;               ///< blade length direction at first contact, in the plane
    Vec3 seed_point_m;          ///< surface point where the blade first touched the bone, m
    std::uint32_t triangle_hint = kNoTriangle;  ///< triangle first touched
    BladeGeometry blade;
    SweptRect swept;          ///< region the cutting edge has swept so far (u, v), m
    double feed_depth_m = 0;  ///< advance along -v since first contact, m
    CutEndReason end_reason = CutEndReason::kNone;  ///< kEnd only
};

}  // namespace kerf::physics
