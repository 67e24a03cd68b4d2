// A sequence of planar cuts on one mesh and the pieces it leaves: what `kerf cut` and `kerf demo`
// run. Lengths in metres (the CLI converts from the file's units before calling).
//
//   CutJob job{.mode = CutMode::kUniplanar};
//   job.planes.push_back({apex, n1});
//   job.planes.push_back({apex, n2});
//   job.seeds_m.push_back(surface_point);                  // one seed for every plane
//   auto report = run_cut_job(mesh, job);  // unique_ptr<TriMesh>: cuts in order, finds pieces
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/error.hpp"
#include "config/base/result.hpp"
#include "display/cut/components.hpp"
#include "display/cut/cut_result.hpp"
#include "display/cut/plane.hpp"
#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::cli {

/// How each plane cuts: one plane (sides touch), a slab a kerf wide, or one plane then the kerf
/// opened by gradual separation swept to completion.
enum class CutMode : std::uint8_t { kUniplanar, kBiplanar, kSeparated };
std::string_view to_string(CutMode m) noexcept;
std::optional<CutMode> parse_cut_mode(std::string_view text) noexcept;

struct PlaneSpec {
    cut::Vec3 point_m;
    cut::Vec3 normal;
};

struct CutJob {
    std::vector<PlaneSpec> planes;   ///< cut in this order
    std::vector<cut::Vec3> seeds_m;  ///< none (full plane), one for all planes, or one per plane
    double kerf_m = 0.0;             ///< blade width; required (> 0) for biplanar and separated
    CutMode mode = CutMode::kUniplanar;
};

/// One cut's outcome.
struct CutStep {
    std::size_t plane = 0;  ///< index into CutJob::planes
    cut::CutResult result;
};

struct CutReport {
    std::vector<CutStep> steps;
    std::vector<cut::Body> pieces;  ///< bodies (shells with their cavities), largest first
    std::uint64_t mesh_hash = 0;
};

/// Why a job stopped (kerf::Error with the cut's status as its code): where is the option at
/// fault ("--seed #2", "--kerf"), else "plane #N" (or "cut job" for the job's shape); the mesh
/// keeps every cut made before `plane`.
struct CutJobError : Error<cut::CutStatus> {
    std::size_t plane = 0;  ///< 0-based index of the plane that failed (0 for the job's shape)
    std::string argument;   ///< the option at fault ("--seed #2", "--kerf"), "" if plane or mode
};

/// A CutJobError about plane `plane` (or, with `whole_job`, about the job's shape; with
/// `argument`, about that option).
CutJobError cut_job_error(std::size_t plane, cut::CutStatus code, std::string what,
                          bool whole_job = false, std::string argument = {});

/// How far a seed may lie from its plane: half a typical 1 mm blade. A seed is where the blade
/// touches the bone, so it is on the blade's plane.
inline constexpr double kSeedPlaneTolerance_m = 0.5e-3;

/// A refused cut in words for the user: what happened and what to try, then the status name in
/// brackets (for a bug report), e.g. "the plane passes ... [sliver_split]".
std::string refusal_text(cut::CutStatus status);

/// Checks the job's shape (seed count, kerf for the mode, planes valid) without cutting.
Status<CutJobError> check_cut_job(const CutJob& job);

/// Cuts `mesh` in place plane by plane, then finds the pieces. Held by pointer so that the
/// CutSession of seeded cuts takes it and hands it back without a copy (mesh_io.hpp).
/// @pre mesh != nullptr
Result<CutReport, CutJobError> run_cut_job(std::unique_ptr<mesh::TriMesh>& mesh, const CutJob& job);

/// `piece` as a standalone indexed mesh, ready to write: its vertices in the body's order with
/// their materials, its triangles in the body's order renumbered. Every triangle is kept (no
/// half-edge structure is built, so none can be refused).
mesh::IndexedMesh extract_piece(const mesh::TriMesh& mesh, const cut::Body& piece);

}  // namespace kerf::cli
