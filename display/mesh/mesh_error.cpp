#include "display/mesh/mesh_error.hpp"

namespace kerf::mesh {

std::string_view to_string(MeshErrorKind kind) noexcept {
    switch (kind) {
        case MeshErrorKind::kIo:
            return "io";
        case MeshErrorKind::kEmpty:
            return "empty";
        case MeshErrorKind::kUnknownFormat:
            return "unknown_format";
        case MeshErrorKind::kTruncated:
            return "truncated";
        case MeshErrorKind::kSyntax:
            return "syntax";
        case MeshErrorKind::kNonFinite:
            return "non_finite";
        case MeshErrorKind::kIndexOutOfRange:
            return "index_out_of_range";
        case MeshErrorKind::kBadCount:
            return "bad_count";
        case MeshErrorKind::kUnsupported:
            return "unsupported";
        case MeshErrorKind::kTooLarge:
            return "too_large";
    }
    return "unknown";
}

std::string MeshError::to_string() const {
    std::string out = file.empty() ? std::string{"<memory>"} : file;
    if (line > 0) {
        out += ":" + std::to_string(line);
    } else if (kind != MeshErrorKind::kIo && kind != MeshErrorKind::kUnknownFormat) {
        out += ": byte " + std::to_string(byte_offset);
    }
    out += ": ";
    out += mesh::to_string(kind);
    out += ": ";
    out += detail;
    return out;
}

}  // namespace kerf::mesh
