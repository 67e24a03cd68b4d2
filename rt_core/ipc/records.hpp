// The records kerf-rt publishes: events (journalled, never lost) and per-tick telemetry samples
// (best effort), plus the latest-value state behind the seqlock. Every type here lives in shared
// memory or in the journal file: trivially copyable, fixed-width fields, little-endian x86-64/
// aarch64 layout pinned by static_asserts below and by tests/ipc/layout_test.cpp. If a pin fails,
// bump kLayoutVersion in layout.hpp. Units are SI and written in each field's comment.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace kerf::ipc {

/// Type tag of a record; values are part of the layout (never renumber, only append).
enum class EventType : std::uint16_t {
    kCutBegin = 1,            ///< blade entered bone: a cut plane is locked
    kCutProgress = 2,         ///< the locked cut advanced (swept region grew)
    kCutEnd = 3,              ///< blade left the cut (see CutEndReason)
    kBodyMoved = 4,           ///< a rigid body's pose changed (after separation, drag)
    kParametersChanged = 5,   ///< a tuning parameter changed value
    kDeviceStateChanged = 6,  ///< haptic device connected, faulted, recovered ...
    kSessionReset = 7,        ///< scene reloaded: consumers drop derived state
    kTelemetry = 100,         ///< a per-tick TelemetrySample (telemetry rings only)
};
std::string_view to_string(EventType type) noexcept;

enum class CutEndReason : std::uint32_t { kNone = 0, kCompleted = 1, kWithdrawn = 2, kAborted = 3 };
enum class DeviceState : std::uint32_t {
    kDisconnected = 0,
    kConnecting = 1,
    kReady = 2,
    kFault = 3,
    kSafeStop = 4
};
std::string_view to_string(DeviceState state) noexcept;

/// First 24 bytes of every record.
struct RecordHeader {
    std::uint64_t
        sequence;  ///< events: session-wide, starts at 0, +1 per event; telemetry: per tick
    std::uint64_t time_ns;   ///< CLOCK_MONOTONIC when the producer stamped it, ns
    EventType type;          ///< what the payload holds
    std::uint16_t flags;     ///< reserved, 0
    std::uint32_t checksum;  ///< record_checksum() of the whole record with this field as 0
};

/// Cut begin / progress / end. The plane frame: origin plane_point_m, axes plane_u (the blade's
/// length direction, unit) and v = normal x u; swept region is a rectangle in that (u, v) frame.
struct CutPayload {
    std::uint32_t cut_id;         ///< increments per cut in the session
    std::uint32_t body_id;        ///< body the blade is cutting (collision mesh body index)
    float plane_point_m[3];       ///< a point on the cut plane, world frame, m
    float plane_normal[3];        ///< cut plane normal, world frame, unit length
    float seed_point_m[3];        ///< where the blade first touched the bone, world frame, m
    std::uint32_t triangle_hint;  ///< triangle of body_id hit first, or kNoTriangle
    float blade_length_m;         ///< blade edge length, m
    float blade_depth_m;          ///< blade height from edge to back, m
    float kerf_width_m;           ///< blade thickness (material removed), m
    float swept_u_min_m;          ///< swept region in plane coordinates, m
    float swept_u_max_m;
    float swept_v_min_m;
    float swept_v_max_m;
    float feed_depth_m;         ///< how far the blade has advanced along -v since begin, m
    CutEndReason end_reason;    ///< kNone unless type == kCutEnd
    float plane_u[3];           ///< blade length direction in the plane, world frame, unit
    std::uint32_t reserved[2];  ///< 0
};
inline constexpr std::uint32_t kNoTriangle = 0xFFFFFFFFu;

struct BodyMovedPayload {
    std::uint32_t body_id;       ///< collision mesh body index
    std::uint32_t reserved;      ///< 0
    double position_m[3];        ///< body origin in the world frame, m
    double orientation_wxyz[4];  ///< body rotation, unit quaternion (w, x, y, z)
};

struct ParametersChangedPayload {
    std::uint32_t parameter_id;  ///< stable id of the parameter (config module's table)
    std::uint32_t reserved;      ///< 0
    double value;                ///< new value, SI unit named by `name`'s suffix
    double previous_value;       ///< value before the change, same unit
    char name[32];               ///< NUL-terminated printable ASCII, e.g. "stiffness_n_per_m"
};

struct DeviceStateChangedPayload {
    DeviceState state;           ///< new state
    DeviceState previous;        ///< state before
    std::uint32_t fault_flags;   ///< device-specific fault bits, 0 when none
    std::uint32_t device_index;  ///< which device (0 for the single-device rig)
};

struct SessionResetPayload {
    std::uint64_t scene_id;  ///< id of the scene now loaded
    std::uint32_t reason;    ///< 0 operator, 1 scene loaded, 2 fault recovery
    std::uint32_t reserved;  ///< 0
};

/// One event: header + payload selected by header.type. 128 bytes.
struct EventRecord {
    RecordHeader header;
    union {
        CutPayload cut;
        BodyMovedPayload body_moved;
        ParametersChangedPayload parameters;
        DeviceStateChangedPayload device;
        SessionResetPayload reset;
        std::uint8_t raw[104];
    };
};

/// One 1 kHz tick as measured by the loop. 128 bytes.
struct TelemetrySample {
    RecordHeader header;             ///< type kTelemetry; sequence = tick
    double tool_position_m[3];       ///< tool tip, world frame, m
    float tool_orientation_wxyz[4];  ///< tool rotation, unit quaternion
    float force_n[3];                ///< force commanded to the device, world frame, N
    std::uint32_t contact_flags;     ///< bit 0 touching bone, bit 1 cut locked, bit 2 safety limit
    float penetration_m;             ///< tool depth into the surface, m (0 without contact)
    std::uint32_t period_ns;         ///< time since the previous tick started, ns
    std::uint32_t compute_ns;        ///< time this tick's work took, ns
    std::int32_t jitter_ns;          ///< period_ns minus the nominal period, ns
    std::uint32_t overrun_count;     ///< ticks so far whose work exceeded the period
    float passivity_power_w;         ///< power the passivity observer dissipated this tick, W
    std::uint32_t safety_reasons;    ///< firmware_host SafetyReason bits of this tick
    std::uint32_t loop_flags;        ///< kLoopFlag* bits (safe state, degraded real time, ...)
    std::uint8_t reserved[16];       ///< 0
};
inline constexpr std::uint32_t kLoopFlagSafeState = 1u << 0;    ///< forced zero force (timing)
inline constexpr std::uint32_t kLoopFlagDegradedRt = 1u << 1;   ///< running without SCHED_FIFO
inline constexpr std::uint32_t kLoopFlagDeviceFault = 1u << 2;  ///< device read failed or fault
inline constexpr std::uint32_t kLoopFlagFixedBlade = 1u << 3;   ///< blade from the planned cut
inline constexpr std::uint32_t kLoopFlagCheckFailed = 1u
                                                      << 4;  ///< a KERF_RT_CHECK failed: zero force

/// Latest value behind the seqlock (readers want "now", not history). 128 bytes.
struct LatestState {
    std::uint64_t tick;               ///< loop tick number
    std::uint64_t time_ns;            ///< CLOCK_MONOTONIC of the tick, ns
    double tool_position_m[3];        ///< tool tip, world frame, m
    double tool_orientation_wxyz[4];  ///< tool rotation, unit quaternion
    double force_n[3];                ///< force commanded, N
    double penetration_m;             ///< m
    std::uint32_t contact_flags;      ///< as TelemetrySample::contact_flags
    std::uint32_t overrun_count;      ///< ticks over budget so far
    std::uint32_t period_ns_max;      ///< longest period in the last second, ns
    std::uint32_t compute_ns_max;     ///< longest tick work in the last second, ns
    std::uint64_t reserved;           ///< 0
};

static_assert(sizeof(RecordHeader) == 24 && offsetof(RecordHeader, checksum) == 20);
static_assert(sizeof(CutPayload) == 104 && sizeof(BodyMovedPayload) == 64);
static_assert(sizeof(ParametersChangedPayload) == 56 && sizeof(DeviceStateChangedPayload) == 16);
static_assert(sizeof(SessionResetPayload) == 16);
static_assert(sizeof(EventRecord) == 128 && offsetof(EventRecord, cut) == 24);
static_assert(sizeof(TelemetrySample) == 128 && sizeof(LatestState) == 128);
static_assert(std::is_trivially_copyable_v<EventRecord> &&
              std::is_trivially_copyable_v<TelemetrySample> &&
              std::is_trivially_copyable_v<LatestState>);

}  // namespace kerf::ipc
