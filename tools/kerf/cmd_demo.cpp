// Placeholder registration; the issue that owns this command group replaces it.
#include "tools/kerf/commands.hpp"

namespace kerf::cli {
void add_demo_command(CLI::App& /*app*/) {}
}  // namespace kerf::cli
