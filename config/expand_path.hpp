// kerf::config::expand_path — turns a path as written in a config file into a real path.
//
// Variables (the only ones; anything else in `${...}` is an error):
//   ${config}   the folder holding kerf.toml
//   ${shared}   the shared data folder (`[paths] shared` in kerf.toml; meshes/ lives there)
//   ${tmp}      $TMPDIR, else /tmp
//   ${runtime}  $XDG_RUNTIME_DIR, else /tmp
// A path that is still relative after expansion is taken relative to ${config}.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "config/base/result.hpp"
#include "config/config_error.hpp"

namespace kerf::config {

/// Directories the variables stand for (the environment supplies ${tmp} and ${runtime}).
struct PathVars {
    std::filesystem::path config_dir;  ///< `${config}`
    std::filesystem::path shared_dir;  ///< `${shared}`
};

/// Checks the `${...}` uses in `raw`; on failure returns false and puts the bad text in `bad`.
bool check_path_template(std::string_view raw, std::string* bad);

/// Expands the variables in `raw` (see above); errors are kBadReference naming the variable.
Result<std::filesystem::path, ConfigError> expand_path(std::string_view raw, const PathVars& vars);

}  // namespace kerf::config
