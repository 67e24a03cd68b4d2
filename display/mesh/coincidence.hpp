// kerf::mesh::find_coincidences — what makes a mesh look sound when it is not: distinct vertices
// that sit on top of each other (within a tolerance relative to the mesh's size; the loaders weld
// only bit-identical ones) and triangles that use the same three vertices as another (two such
// triangles make a "closed, genus 0" shell that encloses nothing). For `kerf mesh info`.
//
// Vertices are binned in a spatial hash of cells one tolerance wide and compared only with the 27
// cells around them: linear in the vertex count for any real mesh. Work is capped (kMaxComparisons)
// so that a pathological cluster cannot stall the report; `complete` says whether the cap was hit.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "display/mesh/indexed_mesh.hpp"

namespace kerf::mesh {

/// Default tolerance: this fraction of the bounding-box diagonal (0.1 um on a 100 mm bone).
inline constexpr double kCoincidenceRelativeTolerance = 1e-6;

/// Distance comparisons after which the search stops (and reports itself incomplete).
inline constexpr std::uint64_t kMaxComparisons = 50'000'000;

/// Two distinct vertices closer than the tolerance.
struct CoincidentVertices {
    std::uint32_t first = 0, second = 0;  ///< vertex indices, first < second
    Point first_m{0, 0, 0}, second_m{0, 0, 0};
    double distance_m = 0;
};

/// Coincident vertices and repeated triangles of one mesh.
struct CoincidenceReport {
    double tolerance_m = 0;                   ///< the distance under which vertices coincide
    std::size_t coincident_vertex_pairs = 0;  ///< pairs of referenced vertices within tolerance
    std::vector<CoincidentVertices> vertex_samples;  ///< the first pairs found (at most 8)
    std::size_t repeated_triangles = 0;  ///< triangles whose 3 vertices an earlier triangle has
    /// (later, earlier) triangle index pairs, the first found (at most 8).
    std::vector<std::array<std::size_t, 2>> triangle_samples;
    bool complete = true;  ///< false when kMaxComparisons stopped the vertex search
};

/// Finds coincident vertices (tolerance = `relative_tolerance` x bounding-box diagonal of the
/// vertices triangles use) and repeated triangles.
/// @pre every triangle index < mesh.positions_m.size()
CoincidenceReport find_coincidences(const IndexedMesh& mesh,
                                    double relative_tolerance = kCoincidenceRelativeTolerance);

}  // namespace kerf::mesh
