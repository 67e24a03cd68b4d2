// mesh_hash — a deterministic 64-bit fingerprint of a TriMesh, to prove two runs made the same
// mesh.
//
//   EXPECT_EQ(mesh_hash(replayed), mesh_hash(original));   // bit-identical, element for element
//
// What goes in, over the elements NOT marked deleted, in index order:
//  - per vertex: the exact bits of its position, normal, texture coordinates and colour (each only
//    if the mesh has that attribute) and its material tag;
//  - per face: its three vertices renumbered densely (deleted vertices skipped), rotated so the
//    lowest number comes first (the winding is kept; which halfedge a face starts at is not);
//  - the live vertex and face counts.
// Face normals are left out (derived data that the cutter recomputes only where it edits).
// The hash reads values, never addresses or hash-map order, and mixes 64-bit words with fixed
// constants, so the same mesh gives the same hash on every platform and every run. Deleting an
// element and never having it give the same hash; reordering elements (garbage_collection()) does
// not, by design: a replay must reproduce the order too. O(V + F), no allocation beyond one
// renumbering array.
#pragma once

#include <cstdint>
#include <string>

#include "display/mesh/tri_mesh.hpp"

namespace kerf::cut {

/// The 64-bit fingerprint of `mesh` described above.
std::uint64_t mesh_hash(const mesh::TriMesh& mesh);

/// The hash as 16 lower-case hexadecimal digits (for logs, the CLI and JSON).
std::string mesh_hash_hex(const mesh::TriMesh& mesh);

}  // namespace kerf::cut
