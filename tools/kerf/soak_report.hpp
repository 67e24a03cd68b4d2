// `kerf soak`'s outputs from its rounds: report.json (nlohmann-json), a one-screen summary, the
// plots' data files and gnuplot scripts, and the PNGs gnuplot makes from them (wake-latency
// histogram, force and penetration over time with the faults marked, resident memory over time)
// — all written into the output folder at once (files::AtomicFileSet), with each round's logs,
// hand script and journal under rounds/<n>/.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "config/base/result.hpp"
#include "tools/kerf/soak_round.hpp"

namespace kerf::cli {

/// The run as a whole.
struct SoakRun {
    double requested_s = 0;
    double wall_s = 0;
    std::uint64_t seed = 0;
    std::vector<SoakFault> faults;
    std::vector<RoundResult> rounds;
    std::vector<std::string> failures;  ///< "round N: ..." and run-level ones
};

/// The human summary (about 15 lines).
std::string soak_summary(const SoakRun& run, const std::filesystem::path& out);

/// Writes everything into `out` (created if missing); `scratch` holds gnuplot's inputs while it
/// runs. Fails naming what could not be made or written.
Status<std::string> write_soak_outputs(const SoakRun& run, const std::filesystem::path& out,
                                       const std::filesystem::path& scratch);

}  // namespace kerf::cli
