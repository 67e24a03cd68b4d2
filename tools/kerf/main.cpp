// kerf — the command-line front door for people: mesh info, generators, cutting, shared-memory
// inspection, devices (and, as they land, demo, soak, tune, replay).
#include <CLI/CLI.hpp>

#include "kerf_version.hpp"
#include "tools/kerf/commands.hpp"

int main(int argc, char** argv) {
    CLI::App app{"kerf — real-time haptic bone-saw simulator"};
    app.set_version_flag("--version", std::string{"kerf "} + kerf::kVersion);
    app.require_subcommand(1);
    kerf::cli::add_mesh_commands(app);
    kerf::cli::add_cut_command(app);
    kerf::cli::add_shm_commands(app);
    kerf::cli::add_devices_command(app);
    kerf::cli::add_demo_command(app);
    CLI11_PARSE(app, argc, argv);
    return kerf::cli::kExitOk;
}
