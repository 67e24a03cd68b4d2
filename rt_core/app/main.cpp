// kerf-rt — the 1 kHz real-time process: owns the haptic device, computes collision and force
// against the (cut) bone mesh, publishes state, telemetry and cut events into the session's
// shared memory. See rt_core/README.md.
#include <CLI/CLI.hpp>

#include "config/base/main_guard.hpp"
#include "rt_core/app/rt_process.hpp"

static int program_main(int argc, char** argv) {
    kerf::rt::RtOptions o;
    CLI::App app{"kerf-rt: the 1 kHz haptic loop (device, collision, force, cut events)"};
    app.add_option("--config", o.config,
                   "kerf.toml to read (default: $KERF_DATA_DIR, installed share/kerf or config/)")
        ->check(CLI::ExistingFile);
    app.add_option("--device", o.device, "simulated | falcon | hid[:SERIAL] (default: kerf.toml)")
        ->check([](const std::string& d) {
            if (d == "simulated" || d == "falcon" || d == "hid" || d.rfind("hid:", 0) == 0)
                return std::string();
            return "expected simulated, falcon, hid or hid:SERIAL, got '" + d + "'";
        });
    app.add_option("--socket", o.socket_path, "emulator socket (simulated device)");
    app.add_option("--firmware", o.firmware_path, "Falcon firmware image to load");
    app.add_option("--session", o.session_name, "session (segment) name, overrides kerf.toml");
    app.add_option("--duration", o.duration_s, "seconds to run (0: until SIGINT/SIGTERM)")
        ->check(CLI::Range(0.0, 1e7));
    app.add_flag("--lockstep", o.lockstep, "paced by the emulator: deterministic, not real time");
    app.add_flag("--await-display", o.await_display,
                 "with --lockstep: wait (up to 10 s) for kerf-display's first collision world "
                 "before the first tick, and up to 5 s (not 200 ms) for each emulator answer");
    app.add_option("--record", o.record_path,
                   "record the device input stream (each tick's read) into this file");
    app.add_option("--replay", o.replay_path,
                   "replay a --record file instead of a device: lockstep, as many ticks as "
                   "recorded, collision worlds swapped at the recorded ticks")
        ->check(CLI::ExistingFile);
    app.add_option("--trace", o.trace_path, "write a per-tick force trace (CSV) at exit");
    app.add_option("--histogram", o.histogram_path,
                   "write the wake-latency and tick-work histograms (CSV: bin upper edge us, "
                   "counts) at exit");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;  // --help: 0; every usage error: 2
    }
    return kerf::rt::run_rt_process(o);
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("kerf-rt", [&] { return program_main(argc, argv); });
}
