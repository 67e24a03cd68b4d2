// The demo's own check of what the display did: the session journal kerf-rt left on disk is
// replayed through kerf::cut::CutSession (the same decoding as kerf-display, apply_record), giving
// the mesh hash, the pieces and their volumes, and headless renders of chosen moments (before,
// mid-cut, after) with the same renderer and camera as the display. Deterministic: the same scene
// and journal give the same hash and pictures.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "config/load_config.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cli {

/// One body after the replay.
struct ReplayPiece {
    std::uint32_t body = 0;
    std::uint32_t parent = 0xFFFFFFFFu;  ///< body it was severed from, or none
    std::uint32_t severed_by_cut = 0;    ///< 0 for scene bodies
    double volume_m3 = 0;
    double position_m[3] = {0, 0, 0};  ///< its pose's translation (moved by BodyMoved), m
};

/// What the journal held and what replaying it made.
struct ReplayResult {
    std::uint64_t events = 0;
    std::uint64_t cut_begins = 0, cut_progress = 0, cut_ends_completed = 0, cut_ends_other = 0;
    std::uint64_t body_moves = 0;  ///< BodyMoved records
    std::uint64_t applied = 0, refused = 0, ignored = 0;
    std::size_t bodies_before = 0, bodies_after = 0;  ///< the scene's, and after every event
    std::uint64_t first_cut_end_sequence = 0;         ///< 0 when no cut ended
    std::uint64_t hash = 0;
    std::vector<ReplayPiece> pieces;  ///< the cut bone's pieces: severed bodies and their parents
    std::vector<std::string> shots;   ///< PNGs written
};

/// A picture to take: after the first `events` records are applied.
struct ReplayShot {
    std::uint64_t events = 0;
    std::filesystem::path png;
    std::string caption;
};

/// Reads every record of `journal`, applies them to a session built from `config`'s scene and
/// renders `shots` (headless EGL; none when empty), close on `focus` when given (world, m).
/// Fails naming the file or the renderer.
Result<ReplayResult, std::string> replay_journal(const config::Config& config,
                                                 const std::filesystem::path& journal,
                                                 std::vector<ReplayShot> shots,
                                                 std::optional<mesh::Point> focus = {});

/// "0123456789abcdef".
std::string hash_hex(std::uint64_t hash);

}  // namespace kerf::cli
