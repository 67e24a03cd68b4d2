// kerf-display: see display/app/display_app.hpp.
#include "display/app/display_app.hpp"

int main(int argc, char** argv) {
    const auto args = kerf::display::parse_display_args(argc, argv);
    if (args.exit_code) return *args.exit_code;
    return kerf::display::run_display(args.options);
}
