// kerf-display: the process. Parses its command line and kerf.toml, opens the EGL output and the
// renderer, starts the SessionFollower (cutting on its worker) and runs the frame loop:
//
//   per frame: upload what the worker changed (dirty ranges, under a short lock) ── place the
//   bodies ── draw bone (in chunks: an edit handed over while they are issued begins the frame
//   again, once, not in two frames running) ── blade (latest pose from the seqlock, read last)
//   and HUD ── finish ── present ── measure frame time and event -> pixels latency ──
//   screenshot when asked.
//
//   kerf-display [--config kerf.toml] [--mode headless|window|kms] [--size 1280x720]
//                [--session NAME] [--frames N] [--screenshot PATH [--at-frame N | --on-cut-end]]
//                [--exit-after-events N] [--status PATH] [--on-demand]
//
// --exit-after-events N (tests, benchmarks): once N events are applied, draw one more frame and
// exit, printing "mesh hash <16 hex digits>". --status PATH writes counters as JSON (temp file +
// rename) every half second and at exit. --on-demand draws a frame only when an edit is waiting,
// the blade moved or a second passed, so an edit never waits for a frame already in flight.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace kerf::display {

struct DisplayOptions {
    std::filesystem::path config_path;      ///< empty: config::data_file("kerf.toml")
    std::optional<std::string> mode;        ///< overrides [display] mode: headless | window | kms
    std::optional<int> width, height;       ///< override [display] width_px / height_px
    std::optional<std::string> session;     ///< overrides [shm] session_name
    std::uint64_t frames = 0;               ///< stop after this many frames (0: until closed)
    std::string screenshot;                 ///< PNG path; empty: none
    std::uint64_t screenshot_at_frame = 0;  ///< 1-based frame to shoot (0: the last frame)
    bool screenshot_on_cut_end = false;     ///< shoot the first frame after a completed cut
    std::uint64_t exit_after_events = 0;    ///< exit once this many events are applied (0: never)
    std::string status_path;                ///< JSON status file; empty: none
    bool on_demand = false;  ///< draw only when an edit, the blade pose or a second calls for it
    bool hash_in_status = false;  ///< --hash: keep the mesh hash current when idle
};

/// Parses the command line; on --help or an error prints and returns the exit code to use.
struct ParsedArgs {
    DisplayOptions options;
    std::optional<int> exit_code;
};
ParsedArgs parse_display_args(int argc, char** argv);

/// Runs the display until the frame count, the event count, SIGINT/SIGTERM or a closed window.
/// Returns the process exit code (0 ok, 2 bad configuration, 3 no output/renderer, 4 scene).
int run_display(const DisplayOptions& options);

}  // namespace kerf::display
