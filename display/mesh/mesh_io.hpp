// Mesh files in and out: STL (ASCII and binary), OBJ, PLY (ASCII, binary little and big endian)
// and OFF, read by Kerf's own parsers (OpenMesh's readers are not trusted with hostile input).
//
//   Result<TriMesh, MeshError> r = load_mesh("calcaneus.stl", LengthUnit::kMillimetre);
//   if (!r) { std::cerr << r.error().message() << '\n'; return 1; }
//
// Every loader: converts the file's units to metres; welds vertices whose coordinates are
// bit-identical (deterministic first-seen order, also for indexed formats, so seams split for
// texture coordinates become one surface); ignores stored normals (STL facet normals, OBJ vn,
// PLY nx/ny/nz) and recomputes face and vertex normals from the winding; triangulates polygons
// as a fan. Bad input of any kind gives a MeshError naming the file, the line or byte offset
// and what is wrong, never a crash; a header count is checked against the bytes left before
// anything is reserved. Triangles OpenMesh cannot hold are kept detached and counted
// (LoadedMesh::detached_triangles) — never dropped silently.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "config/base/length_unit.hpp"
#include "config/base/result.hpp"
#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/mesh_error.hpp"
#include "display/mesh/tri_mesh.hpp"

namespace kerf::mesh {

enum class Format { kStl, kObj, kPly, kOff };
std::string_view to_string(Format f) noexcept;

/// How a writer encodes the data. STL and PLY have both; OBJ and OFF are always ASCII.
enum class Encoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
std::string_view to_string(Encoding e) noexcept;

/// The format named by a file extension (case-insensitive .stl .obj .ply .off), or nullopt.
std::optional<Format> format_from_path(const std::filesystem::path& path);

/// A loaded file: the exact indexed contents (for validation) and the half-edge mesh.
struct LoadedMesh {
    IndexedMesh indexed;                 ///< what the file holds, welded, in metres
    TriMesh mesh;                        ///< the same, with normals, ready for cutting
    std::size_t detached_triangles = 0;  ///< triangles OpenMesh could not connect (see above)
};

/// Parses bytes already in memory; `name` only labels errors. The fuzz target's entry point.
Result<IndexedMesh, MeshError> parse_indexed(std::span<const std::byte> bytes, Format format,
                                             LengthUnit units, std::string_view name = "<memory>");

/// Parses bytes already in memory into a half-edge mesh.
Result<LoadedMesh, MeshError> parse_mesh(std::span<const std::byte> bytes, Format format,
                                         LengthUnit units, std::string_view name = "<memory>");

/// Reads and parses a file; the format comes from its extension. Only a regular file of at most
/// 2 GiB is read (a FIFO, device or link to one is a kIo error naming it, never a hang).
Result<LoadedMesh, MeshError> load_mesh_file(const std::filesystem::path& path, LengthUnit units);

/// Reads a file and returns only the half-edge mesh (normals computed). One copy of the mesh
/// on the way out (OpenMesh meshes have no move constructor: moving a TriMesh copies it);
/// large meshes: load_mesh_owned().
Result<TriMesh, MeshError> load_mesh(const std::filesystem::path& path, LengthUnit units);

/// The same on the heap, built where it stays: no copy of the mesh at all, and the file's bytes
/// are freed before the half-edge mesh is built (`kerf cut` of a 1M-triangle file peaked at
/// four meshes' worth of memory through load_mesh and CutSession's copies). Room for edits is
/// reserved (edit_headroom_faces(), address space only), so a CutContext on it copies nothing.
Result<std::unique_ptr<TriMesh>, MeshError> load_mesh_owned(const std::filesystem::path& path,
                                                            LengthUnit units);

/// Encodes a mesh (metres inside) in `units`. Binary PLY/STL default to little endian; a
/// big-endian STL does not exist, so STL with kBinaryBigEndian gives little endian.
/// PLY carries each vertex's material as a `uchar material` property (read back by Kerf).
std::string serialize_mesh(const TriMesh& mesh, Format format, LengthUnit units,
                           Encoding encoding = Encoding::kBinaryLittleEndian);
/// The same for a plain indexed mesh (no half-edge mesh needed to write a file).
std::string serialize_mesh(const IndexedMesh& mesh, Format format, LengthUnit units,
                           Encoding encoding = Encoding::kBinaryLittleEndian);

/// Writes a file atomically (temp file in its folder + rename); the format comes from the
/// extension; STL and PLY are written binary.
Status<MeshError> save_mesh(const TriMesh& mesh, const std::filesystem::path& path,
                            LengthUnit units);

}  // namespace kerf::mesh
