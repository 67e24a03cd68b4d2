#include "config/kerf_config.hpp"

#include <grp.h>

#include <algorithm>
#include <climits>
#include <vector>

#include "config/expand_path.hpp"
#include "config/shm_slots.hpp"
#include "config/toml_reader.hpp"

namespace kerf::config {
namespace {

using detail::TableReader;

/// True when the system knows a group of that name (getgrnam_r; a lookup error counts as no).
bool group_exists(const std::string& name) {
    std::vector<char> buffer(16384);
    ::group entry{};
    ::group* found = nullptr;
    return getgrnam_r(name.c_str(), &entry, buffer.data(), buffer.size(), &found) == 0 &&
           found != nullptr;
}

const std::vector<std::string_view> kModeNames = {"headless", "window", "kms"};
const std::vector<std::string_view> kPolicyNames = {"fifo", "rr", "other"};
const std::vector<std::string_view> kLevelNames = {"trace", "debug", "info",
                                                   "warn",  "error", "off"};

constexpr std::int64_t kMinRing = 16;
constexpr std::int64_t kMaxRing = 1 << 20;

std::string profile_name(TableReader& t, std::string_view key) {
    std::string name = t.string(key);
    if (t.has(key) && t.raw().get(key)->is_string() && !detail::is_plain_name(name)) {
        t.fail(key, ConfigErrc::kBadValue,
               "a profile name: 1-64 letters, digits, '_' or '-' (no paths, no extension)");
    }
    return name;
}

/// A path with only known ${...} variables.
std::string path_template(TableReader& t, std::string_view key, std::string fallback) {
    std::string raw = t.string_or(key, std::move(fallback));
    std::string bad;
    if (raw.empty() && t.has(key)) {
        t.fail(key, ConfigErrc::kBadValue, "a non-empty path");
    } else if (!check_path_template(raw, &bad)) {
        t.fail(key, ConfigErrc::kBadReference,
               "a path; variables ${config}, ${shared}, ${tmp}, ${runtime}",
               "cannot expand " + bad);
    }
    return raw;
}

void read_display(TableReader t, DisplaySettings& d) {
    d.mode = static_cast<DisplayMode>(t.choice_or("mode", 0, kModeNames));
    d.width_px = static_cast<std::uint32_t>(t.integer_or("width_px", d.width_px, 64, 8192));
    d.height_px = static_cast<std::uint32_t>(t.integer_or("height_px", d.height_px, 64, 8192));
    d.vsync = t.boolean_or("vsync", d.vsync);
}

void read_realtime(TableReader t, RealtimeSettings& r) {
    r.period_ns = t.integer_or("period_ns", r.period_ns, 100'000, 100'000'000);
    r.policy = static_cast<SchedPolicy>(t.choice_or("policy", 0, kPolicyNames));
    r.priority = static_cast<std::int32_t>(t.integer_or("priority", r.priority, 0, 99));
    bool realtime_policy = r.policy != SchedPolicy::kOther;
    if (!t.has("priority") && !realtime_policy) r.priority = 0;
    if (t.has("priority") && realtime_policy == (r.priority == 0)) {
        t.fail("priority", ConfigErrc::kOutOfRange,
               realtime_policy ? "1..99 for policy \"fifo\" or \"rr\"" : "0 for policy \"other\"");
    }
    for (auto cpu : t.integer_list_or("cpu_affinity", 0, 1023, 64))
        r.cpu_affinity.push_back(static_cast<std::uint32_t>(cpu));
    auto sorted = r.cpu_affinity;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        t.fail("cpu_affinity", ConfigErrc::kBadValue, "distinct CPU numbers");
    r.consecutive_misses_to_safe_state = static_cast<std::uint32_t>(t.integer_or(
        "consecutive_misses_to_safe_state", r.consecutive_misses_to_safe_state, 1, 1000));
    r.mlockall = t.boolean_or("mlockall", r.mlockall);
    r.require_realtime = t.boolean_or("require_realtime", r.require_realtime);
}

std::uint32_t ring_capacity(TableReader& t, std::string_view key, std::uint32_t fallback) {
    auto v = t.integer_or(key, fallback, kMinRing, kMaxRing);
    if ((v & (v - 1)) != 0) {
        t.fail(key, ConfigErrc::kOutOfRange,
               "a power of two, " + std::to_string(kMinRing) + ".." + std::to_string(kMaxRing));
        return fallback;
    }
    return static_cast<std::uint32_t>(v);
}

void read_shm(TableReader t, ShmSettings& s) {
    s.session_name = t.string_or("session_name", s.session_name);
    if (!detail::is_plain_name(s.session_name))
        t.fail("session_name", ConfigErrc::kBadValue, "1-64 letters, digits, '_' or '-'");
    s.group = t.string_or("group", s.group);
    if (!s.group.empty() && (!detail::is_plain_name(s.group) || s.group.size() > 32)) {
        t.fail("group", ConfigErrc::kBadValue, "empty (owner-only) or a group name");
    } else if (!s.group.empty() && !group_exists(s.group)) {
        t.fail("group", ConfigErrc::kBadValue, "empty (owner-only) or an existing group",
               "no group '" + s.group + "' on this system (see getent group)");
    }
    s.event_ring_capacity = ring_capacity(t, "event_ring_capacity", s.event_ring_capacity);
    s.telemetry_ring_capacity =
        ring_capacity(t, "telemetry_ring_capacity", s.telemetry_ring_capacity);
    // Slots 0 and 1 are the display's and the soak monitor's; a value that leaves no slot for
    // tools (or asks for more than the segment has) is refused, not clamped.
    const auto slots = t.integer_or("consumer_slots", s.consumer_slots, INT32_MIN, INT32_MAX);
    if (slots <= kReservedConsumerSlots || slots > kSegmentConsumerSlots) {
        t.fail("consumer_slots", ConfigErrc::kOutOfRange,
               std::to_string(kReservedConsumerSlots + 1) + ".." +
                   std::to_string(kSegmentConsumerSlots),
               "slot 0 is kerf-display's and slot 1 the soak monitor's, at least one must be "
               "left for tools (kerf shm tail), and a segment has " +
                   std::to_string(kSegmentConsumerSlots));
    } else {
        s.consumer_slots = static_cast<std::uint32_t>(slots);
    }
    s.heartbeat_timeout_ms = static_cast<std::uint32_t>(
        t.integer_or("heartbeat_timeout_ms", s.heartbeat_timeout_ms, 10, 10'000));
}

KerfConfig read_kerf_config(TableReader& root) {
    KerfConfig c;
    auto profiles = root.table("profiles");
    c.profiles.device = profile_name(profiles, "device");
    c.profiles.force = profile_name(profiles, "force");
    c.profiles.scene = profile_name(profiles, "scene");
    auto paths = root.table("paths", false);
    c.shared_dir = path_template(paths, "shared", "../../shared");
    read_display(root.table("display", false), c.display);
    read_realtime(root.table("realtime", false), c.realtime);
    read_shm(root.table("shm", false), c.shm);
    auto journal = root.table("journal", false);
    c.journal.dir = path_template(journal, "dir", "${tmp}/kerf-journal");
    c.journal.flush_ms = static_cast<std::uint32_t>(journal.integer_or("flush_ms", 100, 1, 10'000));
    c.journal.max_files =
        static_cast<std::uint32_t>(journal.integer_or("max_files", 50, 1, 1'000'000));
    c.journal.max_total_mb =
        static_cast<std::uint32_t>(journal.integer_or("max_total_mb", 1024, 1, 10'000'000));
    auto log = root.table("log", false);
    c.log_level = static_cast<LogLevel>(log.choice_or("level", 2, kLevelNames));
    return c;
}

}  // namespace

std::string_view to_string(DisplayMode mode) noexcept {
    switch (mode) {
        case DisplayMode::kHeadless:
            return "headless";
        case DisplayMode::kWindow:
            return "window";
        case DisplayMode::kKms:
            return "kms";
    }
    return "unknown";
}

std::string_view to_string(SchedPolicy policy) noexcept {
    switch (policy) {
        case SchedPolicy::kFifo:
            return "fifo";
        case SchedPolicy::kRoundRobin:
            return "rr";
        case SchedPolicy::kOther:
            return "other";
    }
    return "unknown";
}

std::string_view to_string(LogLevel level) noexcept {
    switch (level) {
        case LogLevel::kTrace:
            return "trace";
        case LogLevel::kDebug:
            return "debug";
        case LogLevel::kInfo:
            return "info";
        case LogLevel::kWarn:
            return "warn";
        case LogLevel::kError:
            return "error";
        case LogLevel::kOff:
            return "off";
    }
    return "unknown";
}

Result<KerfConfig, ConfigError> parse_kerf_config(std::string_view text,
                                                  std::string_view source_name) {
    return detail::parse_document<KerfConfig>(text, source_name, read_kerf_config);
}

Result<KerfConfig, ConfigError> load_kerf_config(const std::filesystem::path& path) {
    auto text = detail::read_text_file(path.string());
    if (!text) return Err{text.error()};
    return parse_kerf_config(*text, path.string());
}

}  // namespace kerf::config
