#include "rt_core/ipc/record_check.hpp"

#include <cmath>
#include <cstring>

namespace kerf::ipc {
namespace {

bool finite(const float* v, int n) noexcept {
    for (int i = 0; i < n; ++i) {
        if (!std::isfinite(v[i])) return false;
    }
    return true;
}

bool finite(const double* v, int n) noexcept {
    for (int i = 0; i < n; ++i) {
        if (!std::isfinite(v[i])) return false;
    }
    return true;
}

template <class T>
bool unit_length(const T* v, int n, double tolerance) noexcept {
    double sq = 0.0;
    for (int i = 0; i < n; ++i) sq += double(v[i]) * double(v[i]);
    return std::fabs(std::sqrt(sq) - 1.0) <= tolerance;
}

bool printable_name(const char* name, std::size_t size) noexcept {
    for (std::size_t i = 0; i < size; ++i) {
        if (name[i] == '\0') return i > 0;
        if (name[i] < 0x20 || name[i] > 0x7e) return false;
    }
    return false;  // no terminator
}

RecordFault validate_cut(const CutPayload& c, EventType type) noexcept {
    const float scalars[] = {c.blade_length_m, c.blade_depth_m, c.kerf_width_m,  c.swept_u_min_m,
                             c.swept_u_max_m,  c.swept_v_min_m, c.swept_v_max_m, c.feed_depth_m};
    if (!finite(c.plane_point_m, 3) || !finite(c.plane_normal, 3) || !finite(c.seed_point_m, 3) ||
        !finite(c.plane_u, 3) || !finite(scalars, 8)) {
        return RecordFault::kNotFinite;
    }
    if (!unit_length(c.plane_normal, 3, 1e-3) || !unit_length(c.plane_u, 3, 1e-3)) {
        return RecordFault::kOutOfRange;
    }
    if (c.blade_length_m <= 0.f || c.blade_depth_m <= 0.f || c.kerf_width_m <= 0.f ||
        c.swept_u_min_m > c.swept_u_max_m || c.swept_v_min_m > c.swept_v_max_m) {
        return RecordFault::kOutOfRange;
    }
    const auto reason = static_cast<std::uint32_t>(c.end_reason);
    const bool is_end = type == EventType::kCutEnd;
    if (reason > 3 || (is_end != (reason != 0))) return RecordFault::kOutOfRange;
    return RecordFault::kNone;
}

RecordFault validate_payload(const EventRecord& r) noexcept {
    switch (r.header.type) {
        case EventType::kCutBegin:
        case EventType::kCutProgress:
        case EventType::kCutEnd:
            return validate_cut(r.cut, r.header.type);
        case EventType::kBodyMoved:
            if (!finite(r.body_moved.position_m, 3) || !finite(r.body_moved.orientation_wxyz, 4)) {
                return RecordFault::kNotFinite;
            }
            return unit_length(r.body_moved.orientation_wxyz, 4, 1e-6) ? RecordFault::kNone
                                                                       : RecordFault::kOutOfRange;
        case EventType::kParametersChanged:
            if (!std::isfinite(r.parameters.value) || !std::isfinite(r.parameters.previous_value)) {
                return RecordFault::kNotFinite;
            }
            return printable_name(r.parameters.name, sizeof r.parameters.name)
                       ? RecordFault::kNone
                       : RecordFault::kOutOfRange;
        case EventType::kDeviceStateChanged:
            return static_cast<std::uint32_t>(r.device.state) <= 4 &&
                           static_cast<std::uint32_t>(r.device.previous) <= 4
                       ? RecordFault::kNone
                       : RecordFault::kOutOfRange;
        case EventType::kSessionReset:
            return r.reset.reason <= 2 ? RecordFault::kNone : RecordFault::kOutOfRange;
        case EventType::kTelemetry:
            break;
    }
    return RecordFault::kBadType;
}

}  // namespace

std::string_view to_string(RecordFault fault) noexcept {
    switch (fault) {
        case RecordFault::kNone:
            return "none";
        case RecordFault::kBadType:
            return "bad_type";
        case RecordFault::kBadChecksum:
            return "bad_checksum";
        case RecordFault::kNotFinite:
            return "not_finite";
        case RecordFault::kOutOfRange:
            return "out_of_range";
    }
    return "unknown";
}

std::string_view to_string(EventType type) noexcept {
    switch (type) {
        case EventType::kCutBegin:
            return "cut_begin";
        case EventType::kCutProgress:
            return "cut_progress";
        case EventType::kCutEnd:
            return "cut_end";
        case EventType::kBodyMoved:
            return "body_moved";
        case EventType::kParametersChanged:
            return "parameters_changed";
        case EventType::kDeviceStateChanged:
            return "device_state_changed";
        case EventType::kSessionReset:
            return "session_reset";
        case EventType::kTelemetry:
            return "telemetry";
    }
    return "unknown";
}

std::string_view to_string(DeviceState state) noexcept {
    switch (state) {
        case DeviceState::kDisconnected:
            return "disconnected";
        case DeviceState::kConnecting:
            return "connecting";
        case DeviceState::kReady:
            return "ready";
        case DeviceState::kFault:
            return "fault";
        case DeviceState::kSafeStop:
            return "safe_stop";
    }
    return "unknown";
}

std::uint32_t record_checksum(const void* record_128_bytes) noexcept {
    std::uint64_t words[16];
    std::memcpy(words, record_128_bytes, sizeof words);
    words[2] &= 0x00000000FFFFFFFFull;  // bytes 20..23 are the checksum itself (little-endian)
    std::uint64_t h = 0x243F6A8885A308D3ull;
    for (std::uint64_t w : words) {
        h = (h ^ w) * 0x9E3779B97F4A7C15ull;
        h ^= h >> 31;
    }
    return static_cast<std::uint32_t>(h ^ (h >> 32));
}

void stamp_checksum(EventRecord& record) noexcept {
    record.header.checksum = record_checksum(&record);
}

void stamp_checksum(TelemetrySample& sample) noexcept {
    sample.header.checksum = record_checksum(&sample);
}

RecordFault validate_event(const EventRecord& record) noexcept {
    if (record_checksum(&record) != record.header.checksum) return RecordFault::kBadChecksum;
    return validate_payload(record);
}

RecordFault validate_telemetry(const TelemetrySample& s) noexcept {
    if (s.header.type != EventType::kTelemetry) return RecordFault::kBadType;
    if (record_checksum(&s) != s.header.checksum) return RecordFault::kBadChecksum;
    if (!finite(s.tool_position_m, 3) || !finite(s.tool_orientation_wxyz, 4) ||
        !finite(s.force_n, 3) || !std::isfinite(s.penetration_m)) {
        return RecordFault::kNotFinite;
    }
    return RecordFault::kNone;
}

RecordFault validate_state(const LatestState& s) noexcept {
    if (!finite(s.tool_position_m, 3) || !finite(s.tool_orientation_wxyz, 4) ||
        !finite(s.force_n, 3) || !std::isfinite(s.penetration_m)) {
        return RecordFault::kNotFinite;
    }
    return RecordFault::kNone;
}

}  // namespace kerf::ipc
