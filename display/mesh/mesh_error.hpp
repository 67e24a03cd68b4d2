// kerf::mesh::MeshError — why a mesh could not be read or written, and exactly where.
//
//   foot.stl: byte 84: header claims 1000 triangles (50084 bytes), file has 4084 (truncated)
//   part.obj:12: face index 17 but only 9 vertices are defined (index_out_of_range)
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "config/base/error.hpp"

namespace kerf::mesh {

/// What kind of load or save failure.
enum class MeshErrc {
    kIo,               ///< the file cannot be opened, read or written
    kEmpty,            ///< no bytes, or no triangle at all
    kUnknownFormat,    ///< the extension or the content names no format Kerf reads
    kTruncated,        ///< the file ends before the data its header or syntax promised
    kSyntax,           ///< a token, keyword or header line that the format does not allow
    kNonFinite,        ///< a coordinate that is NaN or infinite (or overflows after scaling)
    kIndexOutOfRange,  ///< a face refers to a vertex that does not exist
    kBadCount,         ///< a count in a header that is impossible or more than the file holds
    kUnsupported,      ///< legal in the format but not something Kerf reads (e.g. a 5-gon STL)
    kTooLarge,         ///< more vertices or triangles than Kerf's 32-bit indices can hold
};

/// Short snake_case name, e.g. "index_out_of_range".
std::string_view to_string(MeshErrc code) noexcept;

/// One load or save failure (kerf::Error): where is "<file>:<line>" for text formats, "<file>:
/// byte N" for binary ones, "<file>" for I/O and an unknown format; what says what is wrong, with
/// the offending value. The line (1-based, 0 for binary / n.a.) and the byte offset where the
/// problem was found are kept as numbers.
struct MeshError : Error<MeshErrc> {
    std::size_t line = 0;         ///< 1-based line for text formats, 0 for binary / n.a.
    std::size_t byte_offset = 0;  ///< offset of the offending data from the start of the file
};

/// A MeshError about `file` (a path, or the name given to an in-memory parse; "" reads
/// "<memory>") with where made from the file, the line and the byte offset.
MeshError mesh_error(MeshErrc code, std::string_view file, std::size_t line,
                     std::size_t byte_offset, std::string what);

}  // namespace kerf::mesh
