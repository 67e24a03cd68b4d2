// kerf::config::load_config — kerf.toml plus the three profiles it names, resolved and
// cross-checked. This is what a Kerf process calls at start.
//
//   auto cfg = kerf::config::load_config("config/kerf.toml");
//   if (!cfg) { fmt::print(stderr, "kerf demo: {}\n", cfg.error().message()); return 1; }
//   run(cfg->device, cfg->force, cfg->scene, cfg->main.realtime);
#pragma once

#include <filesystem>

#include "config/base/result.hpp"
#include "config/config_error.hpp"
#include "config/device_profile.hpp"
#include "config/force_profile.hpp"
#include "config/kerf_config.hpp"
#include "config/scene.hpp"

namespace kerf::config {

/// A fully resolved configuration.
struct Config {
    std::filesystem::path config_dir;   ///< folder holding kerf.toml (absolute)
    std::filesystem::path shared_dir;   ///< `[paths] shared`, resolved (absolute, may not exist)
    std::filesystem::path journal_dir;  ///< `[journal] dir`, expanded (absolute)
    KerfConfig main;
    DeviceProfile device;
    ForceProfile force;
    Scene scene;
};

/// Loads `kerf_toml` and `devices/<device>.toml`, `force/<force>.toml`, `scenes/<scene>.toml`
/// beside it. A profile name without a file is a kBadReference error listing the names that do
/// exist. Cross-checks: the force profile's max_force_n may not exceed the device's
/// peak_force_n; every file-backed mesh of the scene exists (resolve_mesh_path()); meshes are
/// not read here.
Result<Config, ConfigError> load_config(const std::filesystem::path& kerf_toml);

/// The path variables (`${config}`, `${shared}`) of a loaded configuration.
PathVars path_vars(const Config& config);

}  // namespace kerf::config
