// Small file helpers shared by the `kerf` commands that run the simulator's processes (demo,
// replay, run, soak): reading and atomically writing text files, editing a copied kerf.toml, a
// temporary work folder, kerf-display's command line and reading its status file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "config/base/result.hpp"

namespace kerf::cli {

/// The whole file ("" when it cannot be read).
std::string slurp(const std::filesystem::path& path);
/// Writes `text` to PATH.tmp and renames it to `path`; false on any failure.
bool write_file(const std::filesystem::path& path, const std::string& text);
/// Replaces the value of every `key = ...` line of a TOML text (keeping the line's comment).
std::string set_key(const std::string& text, const std::string& key, const std::string& value);
/// A number after `key` in `text` ("ticks 3000," -> 3000), or -1.
double number_after(const std::string& text, const std::string& key);
/// A string value of `"key": "..."` in a flat JSON line, or "".
std::string json_string(const std::string& text, const std::string& key);
/// The first regular file in `dir` (a session's journal), or an empty path.
std::filesystem::path first_file(const std::filesystem::path& dir);

/// Removes the sockets (and empty folders) of sessions whose kerf-rt died, under the default
/// runtime folder; returns their names. Live sessions and other users' are left alone.
std::vector<std::string> remove_stale_sessions();

/// How many session journals (*.kjournal) a folder may keep, and how many bytes in all.
struct JournalBound {
    std::uint32_t max_files = 50;
    std::uint64_t max_bytes = 1ull << 30;
};
struct JournalPrune {
    std::uint32_t kept = 0, removed = 0;
    std::uint64_t kept_bytes = 0;
};
/// Removes the oldest journals of `dir` until `bound` holds; never one written since `keep_since`
/// (the running session's).
JournalPrune prune_journals(const std::filesystem::path& dir, const JournalBound& bound,
                            std::filesystem::file_time_type keep_since);

/// How a kerf command starts kerf-display.
struct DisplayLaunch {
    std::filesystem::path config;      ///< the session's kerf.toml
    std::string session;               ///< segment name
    std::filesystem::path status;      ///< the status file (JSON) the commands poll
    std::string mode;                  ///< "headless", "window", or "" (kerf.toml's [display] mode)
    bool hash = true;                  ///< --hash: the status carries the mesh hash
    std::filesystem::path screenshot;  ///< --screenshot of the last frame; empty: none
};
/// kerf-display's argument vector, the executable taken from `bin`.
std::vector<std::string> display_args(const std::filesystem::path& bin,
                                      const DisplayLaunch& launch);

/// A temporary folder /tmp/STEM-PID-XXXXXX, removed with everything in it on destruction.
class WorkDir {
public:
    /// Creates it; fails naming /tmp.
    static Result<WorkDir, std::string> create(const std::string& stem);
    WorkDir(WorkDir&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }
    WorkDir& operator=(WorkDir&&) = delete;
    WorkDir(const WorkDir&) = delete;
    WorkDir& operator=(const WorkDir&) = delete;
    ~WorkDir();
    const std::filesystem::path& path() const noexcept { return path_; }

private:
    explicit WorkDir(std::filesystem::path path) : path_(std::move(path)) {}
    std::filesystem::path path_;
};

}  // namespace kerf::cli
