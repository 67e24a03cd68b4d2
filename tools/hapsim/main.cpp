// kerf-hapsim — the byte-level haptic device emulator. It speaks the device side of Kerf's HID
// protocol or the Novint Falcon's FTDI/firmware protocol on a Unix SOCK_SEQPACKET socket, models
// the mechanism and a scripted hand, and injects faults. See tools/hapsim/README.md.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "config/base/main_guard.hpp"
#include "config/device_profile.hpp"
#include "config/expand_path.hpp"
#include "firmware_host/open/open_device.hpp"
#include "tools/hapsim/falcon_side.hpp"
#include "tools/hapsim/kerf_hid_side.hpp"
#include "tools/hapsim/server.hpp"

namespace {

using namespace kerf::hapsim;
namespace fh = kerf::firmware_host;

struct Args {
    bool orientation = false;  ///< kerf: announce and report the tool orientation (6-DoF input)
    std::string socket_path;
    std::string protocol = "kerf";
    bool realtime = false;
    std::string script_path;
    std::string trace_path;
    std::uint32_t trace_max_mb = 1024;
    unsigned period_us = 1000;
    bool commands = false;
    bool firmware_loaded = false;
    unsigned homing_steps = 20;
    double peak_force_n = 10.0;
    double resolution_m = 1e-5;
    std::string serial = "HAPSIM-0001";
    std::string profile_path;
    std::uint16_t vendor_id = 0x1209;
    std::uint16_t product_id = 0x0001;
    double continuous_force_n = 5.0;
    Vec3 workspace_min_m = {-0.08, -0.08, -0.08};
    Vec3 workspace_max_m = {0.08, 0.08, 0.08};
    fh::falcon::DeltaGeometry geometry;
};

// Fills what the command line did not set from a device profile (config/devices/*.toml); an
// error message when the profile cannot be applied (e.g. its socket path does not expand).
std::string apply_profile(const kerf::config::DeviceProfile& p, const CLI::App& app, Args& a) {
    namespace cfg = kerf::config;
    const auto given = [&app](const char* option) { return app.count(option) > 0; };
    const auto kind = p.kind == cfg::DeviceKind::kSimulated ? p.emulator.protocol : p.kind;
    if (!given("--protocol")) a.protocol = kind == cfg::DeviceKind::kFalcon ? "falcon" : "kerf";
    if (!given("--serial") && !p.ids.serial.empty()) a.serial = p.ids.serial.substr(0, 16);
    if (!given("--peak-force-n")) a.peak_force_n = p.limits.peak_force_n;
    if (!given("--resolution-m") && p.encoder.resolution_m > 0)
        a.resolution_m = p.encoder.resolution_m;
    if (!given("--realtime") && !given("--lockstep") && p.kind == cfg::DeviceKind::kSimulated) {
        a.realtime = !p.emulator.lockstep;
    }
    if (!given("--socket") && p.kind == cfg::DeviceKind::kSimulated) {
        auto path = cfg::expand_path(p.emulator.socket_path, {});
        if (!path) return "[emulator] socket_path: " + path.error().message();
        a.socket_path = path->string();
    }
    a.vendor_id = p.ids.vendor_id;
    a.product_id = p.ids.product_id;
    a.continuous_force_n = p.limits.continuous_force_n;
    a.workspace_min_m = p.workspace.min_m;
    a.workspace_max_m = p.workspace.max_m;
    if (p.kinematic_model == cfg::KinematicModel::kFalconDelta) {
        a.geometry = fh::delta_geometry_from(p);
    }
    return {};
}

KerfSideParams kerf_params(const Args& a) {
    KerfSideParams p;
    p.identity.firmware_version = 0x0100;
    p.identity.vendor_id = a.vendor_id;
    p.identity.product_id = a.product_id;
    const std::string vendor = "Kerf", model = "kerf-hapsim";
    std::copy(vendor.begin(), vendor.end(), p.identity.vendor.begin());
    std::copy(model.begin(), model.end(), p.identity.model.begin());
    std::copy_n(a.serial.begin(), std::min<std::size_t>(a.serial.size(), 16),
                p.identity.serial.begin());
    p.mechanics.encoder_resolution = static_cast<std::uint32_t>(a.resolution_m * 1e9);
    p.mechanics.senses_orientation = a.orientation;
    p.mechanics.peak_force_centi_n = static_cast<std::uint16_t>(a.peak_force_n * 100);
    p.mechanics.continuous_force_centi_n =
        static_cast<std::uint16_t>(std::min(a.continuous_force_n, a.peak_force_n) * 100);
    for (int i = 0; i < 3; ++i) {
        p.mechanics.workspace_min_mm[i] =
            static_cast<std::int16_t>(std::lround(a.workspace_min_m[i] * 1000));
        p.mechanics.workspace_max_mm[i] =
            static_cast<std::int16_t>(std::lround(a.workspace_max_m[i] * 1000));
    }
    p.resolution_m = a.resolution_m;
    p.peak_force_n = a.peak_force_n;
    p.homing_steps = a.homing_steps;
    p.lockstep = !a.realtime;
    return p;
}

int run(const Args& a) {
    HandScript script;
    if (!a.script_path.empty()) {
        auto s = load_hand_script(a.script_path);
        if (!s) {
            std::fprintf(stderr, "kerf-hapsim: script: %s\n", s.error().message().c_str());
            return 1;
        }
        script = std::move(*s);
    }
    const bool falcon = a.protocol == "falcon";
    ModelParams model;
    model.workspace_min_m = a.workspace_min_m;
    model.workspace_max_m = a.workspace_max_m;
    model.motor_limit_n = a.peak_force_n;
    Vec3 start = {0, 0, 0};
    if (falcon) {
        if (a.profile_path.empty()) {  // the Falcon's box in libnifalcon's frame
            model.workspace_min_m = {-0.06, -0.06, 0.075};
            model.workspace_max_m = {0.06, 0.06, 0.135};
        }
        start = {0, 0, 0.11};
    }
    // A move or sweep that leaves the device's workspace is a script error (file:line), not a
    // hand that silently hits the end stops.
    Vec3 at = start;  // where the hand is when each action starts
    for (const ScriptAction& action : script) {
        const bool move = action.kind == ScriptAction::Kind::kMove;
        if (!move && action.kind != ScriptAction::Kind::kSweep) continue;
        for (int k = 0; k < 3; ++k) {
            const double lo = move ? action.vec[k] : at[k] - std::abs(action.vec[k]);
            const double hi = move ? action.vec[k] : at[k] + std::abs(action.vec[k]);
            if (lo < model.workspace_min_m[k] || hi > model.workspace_max_m[k]) {
                std::fprintf(stderr,
                             "kerf-hapsim: script: %s:%d: %s reaches %.4f m on axis %c, outside "
                             "the workspace [%.4f, %.4f] m\n",
                             a.script_path.c_str(), action.line, move ? "move" : "sweep",
                             lo < model.workspace_min_m[k] ? lo : hi, "xyz"[k],
                             model.workspace_min_m[k], model.workspace_max_m[k]);
                return 1;
            }
        }
        if (move) at = action.vec;
    }
    Simulation sim(model, std::move(script), start, a.period_us * 1e-6);
    std::string why;
    if (!a.trace_path.empty() &&
        !sim.open_trace(a.trace_path, std::uint64_t(a.trace_max_mb) << 20, why)) {
        std::fprintf(stderr, "kerf-hapsim: %s\n", why.c_str());
        return 1;
    }
    auto listener = fh::SeqpacketListener::listen(a.socket_path);
    if (!listener) {
        std::fprintf(stderr, "kerf-hapsim: %s\n", listener.error().message().c_str());
        return 1;
    }
    std::unique_ptr<EmulatedDevice> device;
    if (falcon) {
        FalconSideParams p;
        p.firmware_loaded = a.firmware_loaded;
        p.homing_steps = a.homing_steps;
        p.lockstep = !a.realtime;
        p.geometry = a.geometry;
        device = std::make_unique<FalconSide>(sim, p);
    } else {
        device = std::make_unique<KerfHidSide>(sim, kerf_params(a));
    }
    std::printf("ready %s protocol=%s mode=%s\n", a.socket_path.c_str(), a.protocol.c_str(),
                a.realtime ? "realtime" : "lockstep");
    std::fflush(stdout);
    Server server(std::move(*listener), *device, sim,
                  {!a.realtime, std::chrono::microseconds(a.period_us), a.commands});
    const int rc = server.run();
    if (!sim.close_trace(why)) {
        std::fprintf(stderr, "kerf-hapsim: %s\n", why.c_str());
        return 1;
    }
    return rc;
}

}  // namespace

int hapsim_main(int argc, char** argv) {
    CLI::App app{
        "kerf-hapsim — byte-level haptic device emulator (Kerf HID protocol or Novint Falcon)"};
    Args a;
    app.add_option(
        "--socket", a.socket_path,
        "Unix socket path to listen on (default: the --profile's [emulator] socket_path)");
    app.add_option("--profile", a.profile_path,
                   "device profile (config/devices/*.toml): ids, serial, limits, resolution, "
                   "workspace, Falcon geometry; options given on the command line win")
        ->check(CLI::ExistingFile);
    app.add_option("--protocol", a.protocol, "wire protocol: kerf or falcon")
        ->check(CLI::IsMember({"kerf", "falcon"}));
    auto* realtime_option =
        app.add_flag("--realtime", a.realtime,
                     "run on the wall clock (default: lockstep, one step per host packet)");
    bool lockstep_flag = false;
    app.add_flag("--lockstep", lockstep_flag,
                 "one step per host packet (the default; wins over a profile)")
        ->excludes(realtime_option);
    app.add_option("--script", a.script_path, "hand script (CSV: move, hold, button, sweep, fault)")
        ->check(CLI::ExistingFile);
    app.add_option("--trace", a.trace_path,
                   "stream the true device positions per step (CSV) to this file; it is created "
                   "at start");
    app.add_option("--trace-max-mb", a.trace_max_mb,
                   "stop the trace at this size (MiB; a 1 kHz day is ~7 GB)")
        ->check(CLI::Range(1U, 1U << 20));
    app.add_option("--period-us", a.period_us, "device period in microseconds")
        ->check(CLI::Range(100U, 100000U));
    app.add_flag("--commands", a.commands,
                 "read `fault <name> <value>` / `status` / `quit` lines on stdin");
    app.add_flag("--firmware-loaded", a.firmware_loaded, "falcon: start with firmware running");
    app.add_flag("--orientation", a.orientation,
                 "kerf: sense the tool orientation (announced in the mechanics report; the "
                 "script's orient action sets it)");
    app.add_option("--homing-steps", a.homing_steps, "periods homing takes")
        ->check(CLI::Range(1U, 100000U));
    // CLI::Range lets NaN through (every comparison is false): finiteness is checked first.
    const auto finite = [](const std::string& text) {
        try {
            std::size_t used = 0;
            const double v = std::stod(text, &used);
            if (used == text.size() && std::isfinite(v)) return std::string();
        } catch (...) {
        }
        return "'" + text + "' is not a finite number";
    };
    app.add_option("--peak-force-n", a.peak_force_n, "kerf: device peak force (N)")
        ->check(finite)
        ->check(CLI::Range(0.1, 300.0));
    app.add_option("--resolution-m", a.resolution_m, "kerf: position quantum (m)")
        ->check(finite)
        ->check(CLI::Range(1e-9, 1e-3));
    app.add_option("--serial", a.serial, "kerf: serial number string (printable ASCII, <= 16)")
        ->check([](const std::string& s) {
            if (s.size() > 16) return std::string("at most 16 characters");
            for (char c : s) {
                if (c < 0x20 || c > 0x7E) return std::string("printable ASCII only");
            }
            return std::string();
        });
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);  // prints help or the error
        return rc == 0 ? 0 : 2;      // usage errors exit 2
    }
    if (!a.profile_path.empty()) {
        auto profile = kerf::config::load_device_profile(a.profile_path);
        if (!profile) {
            std::fprintf(stderr, "kerf-hapsim: profile: %s\n", profile.error().message().c_str());
            return 1;
        }
        if (const std::string why = apply_profile(*profile, app, a); !why.empty()) {
            std::fprintf(stderr, "kerf-hapsim: profile %s: %s\n", a.profile_path.c_str(),
                         why.c_str());
            return 1;
        }
    }
    if (a.socket_path.empty()) {
        std::fprintf(stderr,
                     "kerf-hapsim: --socket is required (or a --profile with an [emulator] "
                     "socket_path)\n");
        return 2;
    }
    return run(a);
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("kerf-hapsim", [&] { return hapsim_main(argc, argv); });
}
