#include "display/mesh/mesh_error.hpp"

namespace kerf::mesh {

std::string_view to_string(MeshErrc code) noexcept {
    switch (code) {
        case MeshErrc::kIo:
            return "io";
        case MeshErrc::kEmpty:
            return "empty";
        case MeshErrc::kUnknownFormat:
            return "unknown_format";
        case MeshErrc::kTruncated:
            return "truncated";
        case MeshErrc::kSyntax:
            return "syntax";
        case MeshErrc::kNonFinite:
            return "non_finite";
        case MeshErrc::kIndexOutOfRange:
            return "index_out_of_range";
        case MeshErrc::kBadCount:
            return "bad_count";
        case MeshErrc::kUnsupported:
            return "unsupported";
        case MeshErrc::kTooLarge:
            return "too_large";
    }
    return "unknown";
}

MeshError mesh_error(MeshErrc code, std::string_view file, std::size_t line,
                     std::size_t byte_offset, std::string what) {
    MeshError e;
    e.code = code;
    e.where = file.empty() ? std::string{"<memory>"} : std::string(file);
    if (line > 0) {
        e.where += ":" + std::to_string(line);
    } else if (code != MeshErrc::kIo && code != MeshErrc::kUnknownFormat) {
        e.where += ": byte " + std::to_string(byte_offset);
    }
    e.what = std::move(what);
    e.line = line;
    e.byte_offset = byte_offset;
    return e;
}

}  // namespace kerf::mesh
