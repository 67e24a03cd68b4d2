// The `kerf` command's subcommands. Each group lives in its own cmd_*.cpp and registers itself
// on the application; main.cpp only wires them up.
#pragma once

#include <CLI/CLI.hpp>

namespace kerf::cli {

void add_mesh_commands(CLI::App& app);    ///< `kerf mesh info`, `kerf gen foot`     (cmd_mesh.cpp)
void add_cut_command(CLI::App& app);      ///< `kerf cut`                           (cmd_cut.cpp)
void add_shm_commands(CLI::App& app);     ///< `kerf shm ls|tail|stats`             (cmd_shm.cpp)
void add_devices_command(CLI::App& app);  ///< `kerf devices` (cmd_devices.cpp)
void add_demo_command(CLI::App& app);     ///< `kerf demo`: the README's main job    (cmd_demo.cpp)
void add_soak_command(CLI::App& app);     ///< `kerf soak`: faults, checks, plots   (cmd_soak.cpp)
void add_replay_command(CLI::App& app);  ///< `kerf replay DIR`                     (cmd_replay.cpp)
void add_run_command(CLI::App& app);     ///< `kerf run`: the kiosk form            (cmd_run.cpp)

/// Process exit codes shared by every subcommand.
enum ExitCode : int {
    kExitOk = 0,
    kExitFailure = 1,  ///< the operation ran and failed (bad input file, cut refused, ...)
    kExitUsage = 2,    ///< bad command line (CLI11 reports these itself)
};

}  // namespace kerf::cli
