#include "config/force_profile.hpp"

#include <cmath>

#include "config/toml_reader.hpp"

namespace kerf::config {
namespace {

using detail::closed;
using detail::non_negative;
using detail::positive;
using detail::Range;

/// One numeric field: where it lives in the TOML, what it accepts, where it goes in the struct.
struct FieldSpec {
    std::string_view table;  ///< dotted path of its table
    std::string_view key;
    Range range;
    double& (*ref)(ForceProfile&);
};

// The single list of numeric fields: the parser reads it, the validator checks it.
const FieldSpec kFields[] = {
    {"contact", "stiffness_n_per_m", positive(1e5, "N/m"),
     [](ForceProfile& p) -> double& { return p.contact.stiffness_n_per_m; }},
    {"contact", "damping_n_s_per_m", non_negative(1e3, "N·s/m"),
     [](ForceProfile& p) -> double& { return p.contact.damping_n_s_per_m; }},
    {"contact", "static_friction_n", non_negative(50, "N"),
     [](ForceProfile& p) -> double& { return p.contact.static_friction_n; }},
    {"contact", "dynamic_friction_n", non_negative(50, "N"),
     [](ForceProfile& p) -> double& { return p.contact.dynamic_friction_n; }},
    {"limits", "max_force_n", positive(100, "N"),
     [](ForceProfile& p) -> double& { return p.limits.max_force_n; }},
    {"limits", "slew_rate_n_per_s", positive(1e6, "N/s"),
     [](ForceProfile& p) -> double& { return p.limits.slew_rate_n_per_s; }},
    {"limits", "ramp_in_s", non_negative(10, "s"),
     [](ForceProfile& p) -> double& { return p.limits.ramp_in_s; }},
    {"limits", "engage_threshold_n", non_negative(100, "N"),
     [](ForceProfile& p) -> double& { return p.limits.engage_threshold_n; }},
    {"cutting.cortical", "feed_resistance_n_s_per_m", non_negative(1e5, "N·s/m"),
     [](ForceProfile& p) -> double& { return p.cortical.feed_resistance_n_s_per_m; }},
    {"cutting.cortical", "plane_lock_stiffness_n_per_m", positive(1e5, "N/m"),
     [](ForceProfile& p) -> double& { return p.cortical.plane_lock_stiffness_n_per_m; }},
    {"cutting.cortical", "twist_damping_n_m_s_per_rad", non_negative(100, "N·m·s/rad"),
     [](ForceProfile& p) -> double& { return p.cortical.twist_damping_n_m_s_per_rad; }},
    {"cutting.cancellous", "feed_resistance_n_s_per_m", non_negative(1e5, "N·s/m"),
     [](ForceProfile& p) -> double& { return p.cancellous.feed_resistance_n_s_per_m; }},
    {"cutting.cancellous", "plane_lock_stiffness_n_per_m", positive(1e5, "N/m"),
     [](ForceProfile& p) -> double& { return p.cancellous.plane_lock_stiffness_n_per_m; }},
    {"cutting.cancellous", "twist_damping_n_m_s_per_rad", non_negative(100, "N·m·s/rad"),
     [](ForceProfile& p) -> double& { return p.cancellous.twist_damping_n_m_s_per_rad; }},
    {"saw", "blade_length_m", positive(0.2, "m"),
     [](ForceProfile& p) -> double& { return p.saw.blade_length_m; }},
    {"saw", "blade_depth_m", positive(0.1, "m"),
     [](ForceProfile& p) -> double& { return p.saw.blade_depth_m; }},
    {"saw", "kerf_width_m", positive(0.005, "m"),
     [](ForceProfile& p) -> double& { return p.saw.kerf_width_m; }},
    {"saw", "speed_rpm", non_negative(60000, "rpm"),
     [](ForceProfile& p) -> double& { return p.saw.speed_rpm; }},
};

constexpr std::int64_t kMaxQuietTicks = 10'000;

std::string full_key(const FieldSpec& f) { return std::string(f.table) + "." + std::string(f.key); }

std::string number_text(double v) { return detail::format_number(v); }

ConfigError problem(ConfigErrc kind, std::string key, double value, std::string expected) {
    ConfigError e;
    e.code = kind;
    e.key = std::move(key);
    e.value = number_text(value);
    e.expected = std::move(expected);
    return described(e);
}

/// Rules that relate two fields; each names the field to change.
void check_cross_fields(const ForceProfile& p, std::vector<ConfigError>& out) {
    if (p.contact.dynamic_friction_n > p.contact.static_friction_n) {
        out.push_back(problem(
            ConfigErrc::kOutOfRange, "contact.dynamic_friction_n", p.contact.dynamic_friction_n,
            "<= contact.static_friction_n (" + number_text(p.contact.static_friction_n) + " N)"));
    }
    if (p.limits.engage_threshold_n > p.limits.max_force_n) {
        out.push_back(problem(
            ConfigErrc::kOutOfRange, "limits.engage_threshold_n", p.limits.engage_threshold_n,
            "<= limits.max_force_n (" + number_text(p.limits.max_force_n) + " N)"));
    }
    if (p.saw.kerf_width_m >= p.saw.blade_depth_m) {
        out.push_back(problem(ConfigErrc::kOutOfRange, "saw.kerf_width_m", p.saw.kerf_width_m,
                              "< saw.blade_depth_m (" + number_text(p.saw.blade_depth_m) +
                                  " m): a blade is thinner than it is deep"));
    }
}

ForceProfile read_force_profile(detail::TableReader& root) {
    ForceProfile p;
    p.name = root.string("name");
    p.description = root.string_or("description", "");
    auto contact = root.table("contact");
    auto limits = root.table("limits");
    auto cutting = root.table("cutting");
    auto cortical = cutting.table("cortical");
    auto cancellous = cutting.table("cancellous");
    auto saw = root.table("saw");
    auto reader_for = [&](std::string_view table) -> detail::TableReader& {
        if (table == "contact") return contact;
        if (table == "limits") return limits;
        if (table == "cutting.cortical") return cortical;
        if (table == "cutting.cancellous") return cancellous;
        return saw;
    };
    for (const FieldSpec& f : kFields) f.ref(p) = reader_for(f.table).number(f.key, f.range);
    p.limits.engage_quiet_ticks =
        static_cast<std::uint32_t>(limits.integer("engage_quiet_ticks", 0, kMaxQuietTicks));
    if (root.problems().empty()) {
        std::vector<ConfigError> cross;
        check_cross_fields(p, cross);
        for (const ConfigError& e : cross) {
            toml::node_view<const toml::node> node = root.raw().at_path(e.key);
            root.problems().add(e.code, node ? node.node()->source() : root.raw().source(), e.key,
                                e.value, e.expected, e.note);
        }
    }
    return p;
}

}  // namespace

std::vector<ConfigError> validate_force_profile(const ForceProfile& profile) {
    std::vector<ConfigError> out;
    ForceProfile copy = profile;
    for (const FieldSpec& f : kFields) {
        double v = f.ref(copy);
        if (!std::isfinite(v)) {
            out.push_back(problem(ConfigErrc::kNonFinite, full_key(f), v,
                                  "a finite number, " + f.range.describe()));
        } else if (!f.range.contains(v)) {
            out.push_back(problem(ConfigErrc::kOutOfRange, full_key(f), v, f.range.describe()));
        }
    }
    if (profile.limits.engage_quiet_ticks > kMaxQuietTicks) {
        out.push_back(problem(ConfigErrc::kOutOfRange, "limits.engage_quiet_ticks",
                              profile.limits.engage_quiet_ticks,
                              "0 <= value <= " + std::to_string(kMaxQuietTicks)));
    }
    if (out.empty()) check_cross_fields(profile, out);
    return out;
}

Result<ForceProfile, ConfigError> parse_force_profile(std::string_view text,
                                                      std::string_view source_name) {
    return detail::parse_document<ForceProfile>(text, source_name, read_force_profile);
}

Result<ForceProfile, ConfigError> load_force_profile(const std::filesystem::path& path) {
    auto text = detail::read_text_file(path.string());
    if (!text) return Err{text.error()};
    return parse_force_profile(*text, path.string());
}

}  // namespace kerf::config
