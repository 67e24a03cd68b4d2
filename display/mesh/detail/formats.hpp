// Internal: one parser and one writer per file format. Parsers return the welded indexed mesh
// in metres; writers take metres and write file units (`metres_per_unit` of the file).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "config/base/result.hpp"
#include "display/mesh/detail/parse_support.hpp"
#include "display/mesh/indexed_mesh.hpp"

namespace kerf::mesh::detail {

Result<IndexedMesh, MeshError> parse_stl(std::span<const std::byte> bytes, const ParseContext& ctx);
Result<IndexedMesh, MeshError> parse_obj(std::span<const std::byte> bytes, const ParseContext& ctx);
Result<IndexedMesh, MeshError> parse_ply(std::span<const std::byte> bytes, const ParseContext& ctx);
Result<IndexedMesh, MeshError> parse_off(std::span<const std::byte> bytes, const ParseContext& ctx);

inline constexpr std::size_t kStlHeaderBytes = 84;  ///< binary STL: 80 bytes, then the count
inline constexpr std::size_t kStlFacetBytes = 50;   ///< normal, 3 corners, attribute count

/// The facet count of a binary STL: the little-endian 32-bit word after the 80-byte header.
/// @pre `header` holds at least kStlHeaderBytes bytes
inline std::uint32_t stl_facet_count(const std::byte* header) {
    std::uint32_t v = 0;
    for (int i = 83; i >= 80; --i) v = (v << 8) | std::to_integer<std::uint32_t>(header[i]);
    return v;
}

class FloatBitsWelder;

/// A binary STL's facets parsed as they come, in file order (a large file need not be in memory
/// whole): what parse_stl() does with a binary file of `count` facets, the same welding, errors
/// and offsets.
class BinaryStlParser {
public:
    /// @pre count > 0 (parse_stl() reports an empty file)
    BinaryStlParser(std::uint32_t count, const ParseContext& ctx);
    ~BinaryStlParser();
    /// The next whole facets (kStlFacetBytes each; a partial one at the end is ignored, as are
    /// facets beyond `count`).
    std::optional<MeshError> add_facets(std::span<const std::byte> facets);
    /// The facets so far, welded (all `count` of them once every one was added).
    IndexedMesh finish() &&;

private:
    const ParseContext& ctx_;
    std::uint32_t count_;
    std::uint32_t next_ = 0;  ///< index of the next facet
    IndexedMesh out_;
    std::unique_ptr<FloatBitsWelder> welder_;
};

std::string write_stl(const IndexedMesh& m, double metres_per_unit, bool binary);
std::string write_obj(const IndexedMesh& m, double metres_per_unit);
std::string write_ply(const IndexedMesh& m, double metres_per_unit, bool binary, bool big_endian);
std::string write_off(const IndexedMesh& m, double metres_per_unit);

/// "%.17g": enough digits that a double reads back bit-identical.
std::string exact_number(double v);

/// Welds a list of file vertices (already in metres) and rewrites `triangles` to welded indices;
/// a welded vertex takes the material of its first raw vertex (when materials are given).
IndexedMesh weld_indexed(const std::vector<Point>& raw, std::vector<Triangle> triangles,
                         const std::vector<Material>& raw_materials = {});

}  // namespace kerf::mesh::detail
