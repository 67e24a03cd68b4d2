// kerf-rt as a process: configuration, device, session segment, the scene's collision mesh, the
// builder / profile / log threads, the real-time thread, signals, the start report and the exit
// summary. main.cpp only parses the command line.
#pragma once

#include <filesystem>
#include <string>

namespace kerf::rt {

/// What the command line says.
struct RtOptions {
    std::filesystem::path config;  ///< empty: config::data_file("kerf.toml")
    std::string device;            ///< "", "simulated", "falcon", "hid" or "hid:SERIAL"
    std::string socket_path;       ///< simulated: the emulator socket (overrides the profile)
    std::string firmware_path;     ///< falcon: firmware image to load
    std::string session_name;      ///< overrides [shm] session_name
    double duration_s = 0;         ///< 0: until SIGINT / SIGTERM
    bool lockstep = false;         ///< paced by the emulator (deterministic)
    bool await_display = false;    ///< lockstep: wait for kerf-display's first world first
    std::string record_path;       ///< optional: record the device input stream (input_recording)
    std::string replay_path;       ///< optional: replay a recording instead of a device (lockstep)
    std::string trace_path;        ///< optional: per-tick force trace (CSV), written at exit
    std::string histogram_path;  ///< optional: wake-latency and tick-work histograms (CSV), at exit
};

/// Runs kerf-rt; returns the process exit status (0 ok, 1 runtime failure, 3 real time refused).
int run_rt_process(const RtOptions& options);

}  // namespace kerf::rt
