// Shared helpers for the ipc tests: unique segment names, a scratch journal directory, and
// records filled deterministically from their index (so any process can re-derive and check them).
#pragma once

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "rt_core/ipc/records.hpp"

namespace kerf::ipc::test {

/// Heartbeat limit for consumers attaching to a test producer that does not tick every
/// millisecond: on a loaded 2-core CI machine the test can be descheduled for longer than the
/// 40 ms default between the producer's beat and the consumer's attach, which then refuses a live
/// producer as stale. The staleness check itself is tested with the default limit
/// (segment_test.cpp, multiprocess_test.cpp).
inline constexpr std::uint64_t kLoadedMachineStaleAfter_ns = 10'000'000'000;

/// "kerf.test-<pid>-<n>": unique per process and call.
inline std::string unique_segment_name(const char* what = "t") {
    static std::atomic<int> counter{0};
    return std::string("kerf.test-") + what + "-" + std::to_string(getpid()) + "-" +
           std::to_string(counter.fetch_add(1));
}

/// A fresh directory under /tmp, removed when the object dies.
struct ScratchDir {
    ScratchDir() {
        char tmpl[] = "/tmp/kerf-ipc-XXXXXX";
        path = mkdtemp(tmpl);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string path;
};

/// Event number `i` of a deterministic stream: types cycle, payload derived from i.
inline EventRecord make_event(std::uint64_t i) {
    EventRecord r{};
    switch (i % 5) {
        case 0:
        case 1:
        case 2: {
            r.header.type = i % 5 == 0   ? EventType::kCutBegin
                            : i % 5 == 1 ? EventType::kCutProgress
                                         : EventType::kCutEnd;
            CutPayload& c = r.cut;
            c.cut_id = std::uint32_t(i / 5);
            c.body_id = std::uint32_t(i % 7);
            c.plane_point_m[0] = 0.01f * float(i % 100);
            c.plane_normal[2] = 1.0f;
            c.plane_u[0] = 1.0f;
            c.seed_point_m[1] = 0.002f;
            c.triangle_hint = std::uint32_t(i);
            c.blade_length_m = 0.03f;
            c.blade_depth_m = 0.01f;
            c.kerf_width_m = 0.0004f;
            c.swept_u_max_m = 0.001f * float(i % 10);
            c.swept_v_max_m = 0.002f;
            c.feed_depth_m = 0.0001f * float(i % 50);
            c.end_reason = i % 5 == 2 ? CutEndReason::kCompleted : CutEndReason::kNone;
            break;
        }
        case 3:
            r.header.type = EventType::kBodyMoved;
            r.body_moved.body_id = std::uint32_t(i);
            r.body_moved.position_m[0] = double(i) * 1e-6;
            r.body_moved.orientation_wxyz[0] = 1.0;
            break;
        default:
            r.header.type = EventType::kParametersChanged;
            r.parameters.parameter_id = std::uint32_t(i);
            r.parameters.value = double(i);
            std::snprintf(r.parameters.name, sizeof r.parameters.name, "stiffness_n_per_m");
            break;
    }
    r.header.time_ns = 1000 + i;
    return r;
}

/// Telemetry sample for tick `i`.
inline TelemetrySample make_sample(std::uint64_t i) {
    TelemetrySample s{};
    s.header.type = EventType::kTelemetry;
    s.header.time_ns = 1000 + i;
    s.tool_position_m[0] = double(i) * 1e-6;
    s.tool_orientation_wxyz[0] = 1.0f;
    s.force_n[2] = float(i % 1000) * 0.01f;
    s.period_ns = 1'000'000;
    return s;
}

}  // namespace kerf::ipc::test
