// kerf::config::data_dir — where Kerf's shipped data lives (kerf.toml, devices/, force/, scenes/),
// found the same way by every executable, installed or in the source tree. The first folder that
// holds a kerf.toml wins:
//   1. $KERF_DATA_DIR                      (a person's or a test's override)
//   2. <this executable's folder>/../share/kerf   (installed; relocatable: any prefix)
//   3. <source tree>/config                (compiled in: ./build/bin/kerf in a checkout, even on a
//                                           machine where an older Kerf is installed)
//   4. <CMAKE_INSTALL_PREFIX>/share/kerf   (compiled in: an installed program copied elsewhere)
//
//   const std::filesystem::path cfg = kerf::config::data_file("kerf.toml");
#pragma once

#include <filesystem>
#include <string_view>
#include <vector>

namespace kerf::config {

/// The candidate data folders in search order (the environment's first, when set).
std::vector<std::filesystem::path> data_dir_candidates();
/// The first candidate holding a kerf.toml; the source tree's config/ when none does.
std::filesystem::path data_dir();
/// `relative` inside data_dir() ("kerf.toml", "devices/simulated.toml").
std::filesystem::path data_file(std::string_view relative);

}  // namespace kerf::config
