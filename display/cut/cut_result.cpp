#include "display/cut/cut_result.hpp"

namespace kerf::cut {

std::string_view to_string(CutStatus s) noexcept {
    switch (s) {
        case CutStatus::kOk:
            return "ok";
        case CutStatus::kPlaneMissesMesh:
            return "plane_misses_mesh";
        case CutStatus::kSeedNotOnSurface:
            return "seed_not_on_surface";
        case CutStatus::kSeedFarFromCut:
            return "seed_far_from_cut";
        case CutStatus::kSeedOnInnerBoundary:
            return "seed_on_inner_boundary";
        case CutStatus::kNonManifoldInput:
            return "non_manifold_input";
        case CutStatus::kInvalidPlane:
            return "invalid_plane";
        case CutStatus::kInvalidArgument:
            return "invalid_argument";
        case CutStatus::kDegenerateCrossSection:
            return "degenerate_cross_section";
        case CutStatus::kCapTriangulationFailed:
            return "cap_triangulation_failed";
        case CutStatus::kSliverSplit:
            return "sliver_split";
        case CutStatus::kInternalError:
            return "internal_error";
    }
    return "unknown";
}

}  // namespace kerf::cut
