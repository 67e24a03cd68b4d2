// kerf::mesh::MeshError — why a mesh could not be read or written, and exactly where.
//
//   foot.stl: byte 84: truncated: header claims 1000 triangles (50084 bytes), file has 4084
//   part.obj:12: index out of range: face index 17 but only 9 vertices are defined
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace kerf::mesh {

enum class MeshErrorKind {
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
std::string_view to_string(MeshErrorKind kind) noexcept;

/// One load or save failure. `line` is 1-based for text formats and 0 when it does not apply;
/// `byte_offset` is where in the file the problem was found.
struct MeshError {
    MeshErrorKind kind = MeshErrorKind::kIo;
    std::string file;             ///< path, or the name given to an in-memory parse
    std::size_t line = 0;         ///< 1-based line for text formats, 0 for binary / n.a.
    std::size_t byte_offset = 0;  ///< offset of the offending data from the start of the file
    std::string detail;           ///< what is wrong, with the offending value

    /// "file:line: kind: detail" (text) or "file: byte N: kind: detail" (binary).
    std::string to_string() const;
};

}  // namespace kerf::mesh
