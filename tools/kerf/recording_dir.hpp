// A recorded session on disk — what `kerf demo` and `kerf run --record DIR` keep and `kerf replay
// DIR` re-runs:
//
//   DIR/recording.json   what was recorded: device, lockstep, ticks, events, the mesh hash
//   DIR/config/          the kerf.toml the session ran with and the files it names (the
//                        device, force and scene profiles, kerf-rt's --device profile, scene
//                        meshes inside the config folder)
//   DIR/shared/          the scene meshes from the shared folder (${shared}), at the same
//                        relative path (kerf replay sets ${shared} to this folder)
//   DIR/input.rec        the device input stream (rt_core/loop/input_recording.hpp)
//   DIR/session.journal  the event journal kerf-rt wrote
//   DIR/force-trace.csv  kerf-rt's per-tick tool position and commanded force (when kept)
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "config/base/result.hpp"

namespace kerf::cli {

/// The files of `config_dir` a session started with its kerf.toml reads (relative paths, sorted):
/// kerf.toml, the device, force and scene profiles it names, the profile of kerf-rt's
/// `--device` (`device`; empty: none), and the scene's mesh files that lie inside the folder.
Result<std::vector<std::filesystem::path>, std::string> session_config_files(
    const std::filesystem::path& config_dir, const std::string& device);

/// The scene meshes a session's kerf.toml names in the shared folder (`${shared}`), outside the
/// config folder: (file, path relative to the shared folder), sorted.
Result<std::vector<std::pair<std::filesystem::path, std::filesystem::path>>, std::string>
shared_scene_files(const std::filesystem::path& config_dir);

/// Copies a session's files into `dir` (created) and writes recording.json from `meta`; every
/// file is written beside its target and renamed. Returns what failed.
Result<bool, std::string> save_recording(const std::filesystem::path& dir,
                                         const std::filesystem::path& config_dir,
                                         const std::filesystem::path& input,
                                         const std::filesystem::path& journal,
                                         const std::filesystem::path& trace,
                                         const nlohmann::json& meta);

/// Records in a device input file (rt_core/loop/input_recording.hpp), from its size.
std::uint64_t input_records(const std::filesystem::path& input);

/// Empty when `input` holds all of a session's `ticks`; else why it does not (a format 2
/// recording stopped where a device was lost; a cut-short file), for a warning when it is saved.
std::string recording_gap(const std::filesystem::path& input, std::uint64_t ticks);

/// recording.json of `dir`, checked for the files and keys replay needs, and refused when its
/// input stream stops before the session's last tick.
Result<nlohmann::json, std::string> load_recording_meta(const std::filesystem::path& dir);

/// Two event journals compared record by record: sequence, type and payload (not the time
/// stamps, the checksum or the session id, which differ between runs by design).
struct JournalComparison {
    std::uint64_t records_a = 0, records_b = 0;
    std::uint64_t first_difference = 0;  ///< sequence of the first differing record
    bool equal = false;
};
Result<JournalComparison, std::string> compare_journals(const std::filesystem::path& a,
                                                        const std::filesystem::path& b);

}  // namespace kerf::cli
