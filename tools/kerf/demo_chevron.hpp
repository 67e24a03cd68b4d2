// The demo's chevron osteotomy of the first metatarsal (Austin): two planes through an apex on
// the bone's axis near the head, both containing the mediolateral direction, limbs 30 degrees
// either side of the proximal axis (a 60-degree V). Cut in place on the scene's mesh, localised
// from a seed on the bone's outer surface, so the other 18 bones stay untouched.
#pragma once

#include <string>

#include "config/base/result.hpp"
#include "display/mesh/foot_generator.hpp"
#include "tools/kerf/cut_job.hpp"

namespace kerf::cli {

/// Where the chevron goes on a bone and what it left.
struct ChevronReport {
    cut::Vec3 apex_m;
    cut::Vec3 seed_m;
    CutJob job;
    CutReport cuts;
    std::vector<std::size_t> fragments;  ///< indices into cuts.pieces of the bone's pieces
    double elapsed_ms = 0.0;             ///< both cuts plus the piece search
};

/// The chevron job for `bone` (apex at `apex_fraction` of the axis from the base) and its
/// seed, found by casting a ray from the apex along the mediolateral axis onto the outer shell.
Result<CutJob, std::string> chevron_job(const mesh::Foot& foot, const mesh::BoneInfo& bone,
                                        double apex_fraction = 0.8);

/// Cuts the chevron into `foot.mesh` and reports the bone's pieces.
Result<ChevronReport, std::string> cut_chevron(mesh::Foot& foot);

}  // namespace kerf::cli
