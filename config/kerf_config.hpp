// kerf::config::KerfConfig — the top-level settings in kerf.toml.
//
// Which device, force profile and scene to use (by name: `devices/<name>.toml`, ... next to
// kerf.toml), the display mode, the real-time loop's settings, the shared-memory session, the
// journal and logging. `load_config()` (config/load_config.hpp) also loads the named profiles.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/result.hpp"
#include "config/config_error.hpp"

namespace kerf::config {

/// How kerf-display presents frames.
enum class DisplayMode : std::uint8_t {
    kHeadless,  ///< EGL surfaceless/pbuffer: tests, CI, screenshots
    kWindow,    ///< a desktop window (development)
    kKms,       ///< GBM/KMS full screen, no X or Wayland (kiosk)
};
std::string_view to_string(DisplayMode mode) noexcept;

/// Scheduling policy requested for the 1 kHz thread.
enum class SchedPolicy : std::uint8_t { kFifo, kRoundRobin, kOther };
std::string_view to_string(SchedPolicy policy) noexcept;  ///< "fifo", "rr", "other"

/// Log verbosity (spdlog levels).
enum class LogLevel : std::uint8_t { kTrace, kDebug, kInfo, kWarn, kError, kOff };
std::string_view to_string(LogLevel level) noexcept;

/// Names of the profiles to load (file stems; [a-z0-9_-], no paths).
struct ProfileNames {
    std::string device;  ///< devices/<device>.toml
    std::string force;   ///< force/<force>.toml
    std::string scene;   ///< scenes/<scene>.toml
};

/// Display settings.
struct DisplaySettings {
    DisplayMode mode = DisplayMode::kHeadless;
    std::uint32_t width_px = 1280;
    std::uint32_t height_px = 720;
    bool vsync = true;
};

/// The real-time loop's settings. Each request is checked at start; without permission the loop
/// runs degraded and says so, unless `require_realtime` is set.
struct RealtimeSettings {
    std::int64_t period_ns = 1'000'000;  ///< loop period (absolute deadlines)
    SchedPolicy policy = SchedPolicy::kFifo;
    std::int32_t priority = 80;                          ///< 1..99 for fifo/rr; 0 for other
    std::vector<std::uint32_t> cpu_affinity;             ///< CPUs to pin to; empty: no pinning
    std::uint32_t consecutive_misses_to_safe_state = 3;  ///< overruns in a row -> zero force
    bool mlockall = true;                                ///< lock current and future pages
    bool require_realtime = false;  ///< refuse to start when a request is denied
};

/// The shared-memory session (rt_core/ipc).
struct ShmSettings {
    std::string session_name = "kerf";  ///< names the segment (shm_open("/" + name)); [A-Za-z0-9_-]
    std::string group;                  ///< empty: owner-only (0600); else 0660 with this group
    std::uint32_t event_ring_capacity = 4096;      ///< records per consumer; power of two
    std::uint32_t telemetry_ring_capacity = 8192;  ///< samples per consumer; power of two
    std::uint32_t consumer_slots = 4;              ///< display, tuning, soak, spare
    std::uint32_t heartbeat_timeout_ms = 100;      ///< producer declared dead after this
};

/// The session event journal.
struct JournalSettings {
    std::string dir;                    ///< as written; `${config}`/`${shared}`/`${tmp}` expand
    std::uint32_t flush_ms = 100;       ///< flush period
    std::uint32_t max_files = 50;       ///< `kerf run` keeps at most this many journals
    std::uint32_t max_total_mb = 1024;  ///< ... taking at most this many MiB (oldest go first)
};

/// Everything in kerf.toml.
struct KerfConfig {
    ProfileNames profiles;
    std::string shared_dir;  ///< `[paths] shared`, as written; relative to the config folder
    DisplaySettings display;
    RealtimeSettings realtime;
    ShmSettings shm;
    JournalSettings journal;
    LogLevel log_level = LogLevel::kInfo;
};

/// Parses kerf.toml text (profile names are checked for form, not existence).
Result<KerfConfig, ConfigError> parse_kerf_config(std::string_view text,
                                                  std::string_view source_name);

/// Reads and parses a kerf.toml file.
Result<KerfConfig, ConfigError> load_kerf_config(const std::filesystem::path& path);

}  // namespace kerf::config
