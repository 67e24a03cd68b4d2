#include "config/device_profile.hpp"

#include <algorithm>
#include <system_error>

#include "config/expand_path.hpp"
#include "config/toml_reader.hpp"

namespace kerf::config {
namespace {

using detail::closed;
using detail::positive;
using detail::TableReader;

const std::vector<std::string_view> kKindNames = {"falcon", "kerf_hid", "simulated"};
const std::vector<std::string_view> kSpaceNames = {"joint", "cartesian"};
const std::vector<std::string_view> kModelNames = {"falcon_delta", "cartesian"};
const std::vector<std::string_view> kProtocolNames = {"falcon", "kerf_hid"};

constexpr double kMaxLink_m = 1.0;
constexpr double kMaxWorkspace_m = 2.0;

void read_ids(TableReader ids, DeviceIds& out) {
    out.vendor_id = static_cast<std::uint16_t>(ids.integer("vendor_id", 1, 0xFFFF));
    out.product_id = static_cast<std::uint16_t>(ids.integer("product_id", 0, 0xFFFF));
    out.serial = ids.string_or("serial", "");
    // The HID identity report carries 16 bytes of printable ASCII: the same rule as --serial.
    bool printable = true;
    for (const char c : out.serial) printable = printable && c >= 0x20 && c <= 0x7E;
    if (out.serial.size() > 16 || !printable) {
        ids.fail("serial", ConfigErrc::kBadValue, "at most 16 printable ASCII characters");
    }
}

void read_falcon_delta(TableReader& k, FalconDeltaGeometry& g) {
    g.a_m = k.number("a_m", positive(kMaxLink_m, "m"));
    g.b_m = k.number("b_m", positive(kMaxLink_m, "m"));
    g.c_m = k.number("c_m", closed(-kMaxLink_m, kMaxLink_m, "m"));
    g.d_m = k.number("d_m", positive(kMaxLink_m, "m"));
    g.e_m = k.number("e_m", positive(kMaxLink_m, "m"));
    g.f_m = k.number("f_m", closed(-kMaxLink_m, kMaxLink_m, "m"));
    g.r_m = k.number("r_m", closed(-kMaxLink_m, kMaxLink_m, "m"));
    g.s_m = k.number("s_m", closed(-kMaxLink_m, kMaxLink_m, "m"));
    g.leg_angles_deg = k.numbers<3>("leg_angles_deg", closed(-360, 360, "deg"));
    g.theta_offset_deg = k.number("theta_offset_deg", closed(-180, 180, "deg"));
}

/// Which top-level keys the file states: rules that tie two keys together are checked only when
/// both are there (an empty profile reports its missing keys, not a mismatch of fallbacks).
struct Stated {
    bool dof = false;
    bool reporting_space = false;
};

void read_kinematics(TableReader k, DeviceProfile& p, Stated stated) {
    const bool has_model = k.has("model");
    p.kinematic_model = static_cast<KinematicModel>(k.choice("model", kModelNames));
    if (p.kinematic_model == KinematicModel::kFalconDelta && has_model) {
        read_falcon_delta(k, p.falcon_delta);
        if (p.dof != 3 && stated.dof)
            k.fail("model", ConfigErrc::kBadValue, "", "falcon_delta needs dof = 3");
    }
    bool joint_model = p.kinematic_model != KinematicModel::kCartesian;
    if (has_model && stated.reporting_space &&
        joint_model != (p.reporting_space == ReportingSpace::kJoint)) {
        k.fail("model", ConfigErrc::kBadValue, "",
               "reporting_space = \"" + std::string(to_string(p.reporting_space)) +
                   "\" needs model = \"" + (joint_model ? "cartesian" : "falcon_delta") + "\"");
    }
}

void read_encoder(TableReader e, DeviceProfile& p) {
    if (p.reporting_space == ReportingSpace::kJoint) {
        p.encoder.counts_per_rev =
            static_cast<std::uint32_t>(e.integer("counts_per_rev", 1, 1 << 24));
        p.encoder.shaft_diameter_m = e.number("shaft_diameter_m", positive(kMaxLink_m, "m"));
        p.encoder.drum_diameter_m = e.number("drum_diameter_m", positive(kMaxLink_m, "m"));
        e.forbid("resolution_m", "only for reporting_space = \"cartesian\"");
    } else {
        p.encoder.resolution_m = e.number("resolution_m", positive(0.01, "m"));
        for (auto key : {"counts_per_rev", "shaft_diameter_m", "drum_diameter_m"})
            e.forbid(key, "only for reporting_space = \"joint\"");
    }
}

void read_limits(TableReader l, DeviceLimits& out) {
    out.peak_force_n = l.number("peak_force_n", positive(100, "N"));
    out.continuous_force_n = l.number("continuous_force_n", positive(100, "N"));
    out.max_slew_n_per_s = l.number("max_slew_n_per_s", positive(1e6, "N/s"));
    out.watchdog_ms = static_cast<std::uint32_t>(l.integer("watchdog_ms", 1, 1000));
    if (out.continuous_force_n > out.peak_force_n && out.peak_force_n > 0) {
        l.fail("continuous_force_n", ConfigErrc::kOutOfRange,
               "<= limits.peak_force_n (" + detail::format_number(out.peak_force_n) + " N)");
    }
}

void read_workspace(TableReader w, Workspace& out) {
    auto range = closed(-kMaxWorkspace_m, kMaxWorkspace_m, "m");
    out.min_m = w.numbers<3>("min_m", range);
    out.max_m = w.numbers<3>("max_m", range);
    for (int axis = 0; axis < 3; ++axis) {
        if (out.min_m[axis] >= out.max_m[axis] && w.problems().empty()) {
            w.fail("max_m", ConfigErrc::kOutOfRange, "each component > the same component of min_m",
                   std::string("axis ") + "xyz"[axis] + " is empty");
            return;
        }
    }
}

void read_emulator(TableReader e, EmulatorSpec& out) {
    out.protocol = static_cast<DeviceKind>(e.choice("protocol", kProtocolNames));
    out.socket_path = e.string("socket_path");
    std::string bad;
    if (out.socket_path.empty() && e.has("socket_path")) {
        e.fail("socket_path", ConfigErrc::kBadValue, "a non-empty path");
    } else if (!check_path_template(out.socket_path, &bad)) {
        e.fail("socket_path", ConfigErrc::kBadReference,
               "a path; variables ${config}, ${shared}, ${tmp}, ${runtime}",
               "cannot expand " + bad);
    }
    out.lockstep = e.boolean_or("lockstep", false);
}

DeviceProfile read_device_profile(TableReader& root) {
    DeviceProfile p;
    p.name = root.string("name");
    p.kind = static_cast<DeviceKind>(root.choice("kind", kKindNames));
    const Stated stated{root.has("dof"), root.has("reporting_space")};
    p.dof = static_cast<std::uint32_t>(root.integer("dof", 1, 6));
    p.reporting_space = static_cast<ReportingSpace>(root.choice("reporting_space", kSpaceNames));
    read_ids(root.table("ids"), p.ids);
    read_kinematics(root.table("kinematics"), p, stated);
    read_encoder(root.table("encoder"), p);
    if (p.reporting_space == ReportingSpace::kJoint) {
        auto m = root.table("motor");
        p.motor.command_per_n_m = m.number("command_per_n_m", positive(1e9, "command/(N·m)"));
        p.motor.command_limit = static_cast<std::int32_t>(m.integer("command_limit", 1, INT32_MAX));
    } else {
        root.forbid("motor", "only for reporting_space = \"joint\"");
    }
    read_limits(root.table("limits"), p.limits);
    read_workspace(root.table("workspace"), p.workspace);
    if (p.kind == DeviceKind::kSimulated) {
        read_emulator(root.table("emulator"), p.emulator);
    } else {
        root.forbid("emulator", "only for kind = \"simulated\"");
    }
    return p;
}

}  // namespace

std::string_view to_string(DeviceKind kind) noexcept {
    switch (kind) {
        case DeviceKind::kFalcon:
            return "falcon";
        case DeviceKind::kKerfHid:
            return "kerf_hid";
        case DeviceKind::kSimulated:
            return "simulated";
    }
    return "unknown";
}

std::string_view to_string(ReportingSpace space) noexcept {
    return space == ReportingSpace::kJoint ? "joint" : "cartesian";
}

std::string_view to_string(KinematicModel model) noexcept {
    return model == KinematicModel::kFalconDelta ? "falcon_delta" : "cartesian";
}

std::string_view device_profile_stem(std::string_view device) noexcept {
    if (device == "simulated" || device == "falcon") return device;
    return "kerf_hid_reference";  // hid, hid:<serial>
}

Result<DeviceProfile, ConfigError> parse_device_profile(std::string_view text,
                                                        std::string_view source_name) {
    return detail::parse_document<DeviceProfile>(text, source_name, read_device_profile);
}

Result<DeviceProfile, ConfigError> load_device_profile(const std::filesystem::path& path) {
    auto text = detail::read_text_file(path.string());
    if (!text) return Err{text.error()};
    return parse_device_profile(*text, path.string());
}

Result<std::vector<NamedDeviceProfile>, ConfigError> load_device_profiles(
    const std::filesystem::path& devices_dir) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(devices_dir, ec), end; !ec && it != end;
         it.increment(ec)) {
        if (it->path().extension() == ".toml") files.push_back(it->path());
    }
    if (ec) {
        ConfigError e;
        e.code = ConfigErrc::kIo;
        e.source = devices_dir.string();
        e.note = ec.message();
        return Err{described(e)};
    }
    std::sort(files.begin(), files.end());
    std::vector<NamedDeviceProfile> out;
    for (const auto& f : files) {
        auto p = load_device_profile(f);
        if (!p) return Err{p.error()};
        out.push_back({f.stem().string(), std::move(*p)});
    }
    return out;
}

}  // namespace kerf::config
