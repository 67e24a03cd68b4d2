// Internal: one parser and one writer per file format. Parsers return the welded indexed mesh
// in metres; writers take metres and write file units (`metres_per_unit` of the file).
#pragma once

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
