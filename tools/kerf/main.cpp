// kerf — the command-line front door for people: mesh info, generators, cutting, shared-memory
// inspection, devices (and, as they land, demo, soak, tune, replay). Machine output (--json) is
// the only thing on stdout in that mode; logs go to stderr. Nothing escapes main(): an unexpected
// exception is a message and exit 1, never an abort.
#include <spdlog/sinks/stdout_color_sinks.h>  // declares stderr_color_mt too
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <new>

#include "kerf_version.hpp"
#include "tools/kerf/commands.hpp"

int main(int argc, char** argv) {
    try {
        spdlog::set_default_logger(spdlog::stderr_color_mt("kerf"));
        CLI::App app{"kerf — real-time haptic bone-saw simulator"};
        app.set_version_flag("--version", std::string{"kerf "} + kerf::kVersion);
        app.require_subcommand(1);
        kerf::cli::add_mesh_commands(app);
        kerf::cli::add_cut_command(app);
        kerf::cli::add_shm_commands(app);
        kerf::cli::add_devices_command(app);
        kerf::cli::add_demo_command(app);
        kerf::cli::add_soak_command(app);
        kerf::cli::add_replay_command(app);
        kerf::cli::add_run_command(app);
        // CLI11 answers an unknown command with "A subcommand is required": name it instead.
        bool known = argc < 2 || argv[1][0] == '-';
        for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
            known = known || sub->check_name(argv[1]);
        if (!known) {
            std::cerr
                << "kerf: unknown command '" << argv[1]
                << "' (commands: mesh, gen, cut, shm, devices, demo, run, replay; try --help)\n";
            return kerf::cli::kExitUsage;
        }
        try {
            app.parse(argc, argv);
        } catch (const CLI::RuntimeError& e) {
            return e.get_exit_code();  // a command ran and failed; it has said why
        } catch (const CLI::ParseError& e) {
            // --help and --version exit 0; every command-line error is a usage error (exit 2),
            // whatever CLI11's own code for it, so scripts can tell a bad command line from a
            // failed operation.
            return app.exit(e) == 0 ? kerf::cli::kExitOk : kerf::cli::kExitUsage;
        }
    } catch (const std::bad_alloc&) {
        std::cerr << "kerf: out of memory\n";
        return kerf::cli::kExitFailure;
    } catch (const std::exception& e) {
        std::cerr << "kerf: unexpected error: " << e.what() << "\n";
        return kerf::cli::kExitFailure;
    } catch (...) {
        std::cerr << "kerf: unexpected error\n";
        return kerf::cli::kExitFailure;
    }
    return kerf::cli::kExitOk;
}
