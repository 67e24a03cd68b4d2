// kerf-hapsim — the byte-level haptic device emulator. It speaks the device side of Kerf's HID
// protocol or the Novint Falcon's FTDI/firmware protocol on a Unix SOCK_SEQPACKET socket, models
// the mechanism and a scripted hand, and injects faults. See tools/hapsim/README.md.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "tools/hapsim/falcon_side.hpp"
#include "tools/hapsim/kerf_hid_side.hpp"
#include "tools/hapsim/server.hpp"

namespace {

using namespace kerf::hapsim;
namespace fh = kerf::firmware_host;

struct Args {
    std::string socket_path;
    std::string protocol = "kerf";
    bool realtime = false;
    std::string script_path;
    std::string trace_path;
    unsigned period_us = 1000;
    bool commands = false;
    bool firmware_loaded = false;
    unsigned homing_steps = 20;
    double peak_force_n = 10.0;
    double resolution_m = 1e-5;
    std::string serial = "HAPSIM-0001";
};

KerfSideParams kerf_params(const Args& a) {
    KerfSideParams p;
    p.identity.firmware_version = 0x0100;
    p.identity.vendor_id = 0x1209;
    p.identity.product_id = 0x0001;
    const std::string vendor = "Kerf", model = "kerf-hapsim";
    std::copy(vendor.begin(), vendor.end(), p.identity.vendor.begin());
    std::copy(model.begin(), model.end(), p.identity.model.begin());
    std::copy_n(a.serial.begin(), std::min<std::size_t>(a.serial.size(), 16),
                p.identity.serial.begin());
    p.mechanics.encoder_resolution = static_cast<std::uint32_t>(a.resolution_m * 1e9);
    p.mechanics.peak_force_centi_n = static_cast<std::uint16_t>(a.peak_force_n * 100);
    p.mechanics.continuous_force_centi_n = static_cast<std::uint16_t>(a.peak_force_n * 50);
    p.mechanics.workspace_min_mm = {-80, -80, -80};
    p.mechanics.workspace_max_mm = {80, 80, 80};
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
    Vec3 start = {0, 0, 0};
    if (falcon) {
        model.workspace_min_m = {-0.06, -0.06, 0.075};
        model.workspace_max_m = {0.06, 0.06, 0.135};
        model.motor_limit_n = 9.0;
        start = {0, 0, 0.11};
    }
    Simulation sim(model, std::move(script), start, a.period_us * 1e-6);
    sim.enable_trace(!a.trace_path.empty());
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
    std::string why;
    if (!a.trace_path.empty() && !sim.write_trace(a.trace_path, why)) {
        std::fprintf(stderr, "kerf-hapsim: %s\n", why.c_str());
        return 1;
    }
    return rc;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "kerf-hapsim — byte-level haptic device emulator (Kerf HID protocol or Novint Falcon)"};
    Args a;
    app.add_option("--socket", a.socket_path, "Unix socket path to listen on")->required();
    app.add_option("--protocol", a.protocol, "wire protocol: kerf or falcon")
        ->check(CLI::IsMember({"kerf", "falcon"}));
    app.add_flag("--realtime", a.realtime,
                 "run on the wall clock (default: lockstep, one step per host packet)");
    app.add_option("--script", a.script_path, "hand script (CSV: move, hold, button, sweep, fault)")
        ->check(CLI::ExistingFile);
    app.add_option("--trace", a.trace_path,
                   "write the true device positions per step (CSV) on exit");
    app.add_option("--period-us", a.period_us, "device period in microseconds")
        ->check(CLI::Range(100U, 100000U));
    app.add_flag("--commands", a.commands,
                 "read `fault <name> <value>` / `status` / `quit` lines on stdin");
    app.add_flag("--firmware-loaded", a.firmware_loaded, "falcon: start with firmware running");
    app.add_option("--homing-steps", a.homing_steps, "periods homing takes")
        ->check(CLI::Range(1U, 100000U));
    app.add_option("--peak-force-n", a.peak_force_n, "kerf: device peak force (N)")
        ->check(CLI::Range(0.1, 300.0));
    app.add_option("--resolution-m", a.resolution_m, "kerf: position quantum (m)")
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
    return run(a);
}
