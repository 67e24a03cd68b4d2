// kerf-display: see display/app/display_app.hpp.
#include <spdlog/sinks/stdout_color_sinks.h>  // declares stderr_color_mt too
#include <spdlog/spdlog.h>

#include "config/base/main_guard.hpp"
#include "display/app/display_app.hpp"

static int program_main(int argc, char** argv) {
    // Logs and errors on stderr (stdout stays free for output a caller reads).
    spdlog::set_default_logger(spdlog::stderr_color_mt("kerf-display"));
    const auto args = kerf::display::parse_display_args(argc, argv);
    if (args.exit_code) return *args.exit_code;
    return kerf::display::run_display(args.options);
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("kerf-display", [&] { return program_main(argc, argv); });
}
