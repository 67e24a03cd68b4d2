#include "display/mesh/mesh_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <vector>

#include "config/file_io/file_io.hpp"
#include "display/mesh/detail/formats.hpp"

namespace kerf::mesh {
namespace {

MeshError io_error(const std::filesystem::path& path, std::string detail) {
    return mesh_error(MeshErrc::kIo, path.string(), 0, 0, std::move(detail));
}

MeshError unknown_format(const std::filesystem::path& path) {
    return mesh_error(
        MeshErrc::kUnknownFormat, path.string(), 0, 0,
        "extension '" + path.extension().string() + "' is not one of .stl .obj .ply .off");
}

/// A binary STL parsed as it is read, a megabyte at a time: no buffer of the file's size (50 MB
/// for a 1M-triangle file, every page of it faulted in, and a hole in the heap that the mesh
/// does not fit). nullopt where the file is something else, or changed while it was read: the
/// caller then reads it whole, as every other file, and gets what parsing that gives.
std::optional<Result<IndexedMesh, MeshError>> parse_stl_streamed(files::RegularFile& file,
                                                                 const std::filesystem::path& path,
                                                                 LengthUnit units) {
    std::byte header[detail::kStlHeaderBytes];
    auto got = file.read(header);
    if (!got || *got != sizeof header) return std::nullopt;
    const std::uint64_t count = detail::stl_facet_count(header);
    if (count == 0 || file.size() != detail::kStlHeaderBytes + count * detail::kStlFacetBytes)
        return std::nullopt;
    const std::string name = path.string();
    const detail::ParseContext ctx{name, metres_per_unit(units)};
    detail::BinaryStlParser parser(static_cast<std::uint32_t>(count), ctx);
    constexpr std::size_t kChunkFacets = 20'000;
    std::vector<std::byte> chunk(kChunkFacets * detail::kStlFacetBytes);
    for (std::uint64_t left = count; left > 0;) {
        const std::size_t facets =
            static_cast<std::size_t>(std::min<std::uint64_t>(left, kChunkFacets));
        const std::span<std::byte> piece(chunk.data(), facets * detail::kStlFacetBytes);
        got = file.read(piece);
        if (!got || *got != piece.size()) return std::nullopt;  // shrank, or unreadable
        if (auto e = parser.add_facets(piece))
            return Result<IndexedMesh, MeshError>{Err{std::move(*e)}};
        left -= facets;
    }
    std::byte probe[1];
    got = file.read(probe);
    if (!got || *got != 0) return std::nullopt;  // grew
    return Result<IndexedMesh, MeshError>{std::move(parser).finish()};
}

/// The file's welded contents, as parse_indexed() gives them from its bytes.
Result<IndexedMesh, MeshError> read_indexed(const std::filesystem::path& path, Format format,
                                            LengthUnit units) {
    // Regular files only, never blocking on a FIFO, never more than the cap (a link to /dev/zero
    // is a character device: refused before a byte is read).
    auto file = files::RegularFile::open(path, files::kDefaultMaxInputBytes);
    if (!file) return Err{io_error(path, file.error().what)};
    if (format == Format::kStl) {
        if (auto streamed = parse_stl_streamed(*file, path, units)) return std::move(*streamed);
    }
    auto bytes = file->read_whole();
    if (!bytes) return Err{io_error(path, bytes.error().what)};
    return parse_indexed(*bytes, format, units, path.string());
}

}  // namespace

std::string_view to_string(Format f) noexcept {
    switch (f) {
        case Format::kStl:
            return "stl";
        case Format::kObj:
            return "obj";
        case Format::kPly:
            return "ply";
        case Format::kOff:
            return "off";
    }
    return "unknown";
}

std::string_view to_string(Encoding e) noexcept {
    switch (e) {
        case Encoding::kAscii:
            return "ascii";
        case Encoding::kBinaryLittleEndian:
            return "binary_little_endian";
        case Encoding::kBinaryBigEndian:
            return "binary_big_endian";
    }
    return "unknown";
}

std::optional<Format> format_from_path(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (Format f : {Format::kStl, Format::kObj, Format::kPly, Format::kOff}) {
        if (ext.size() > 1 && ext.substr(1) == to_string(f)) return f;
    }
    return std::nullopt;
}

Result<IndexedMesh, MeshError> parse_indexed(std::span<const std::byte> bytes, Format format,
                                             LengthUnit units, std::string_view name) {
    const detail::ParseContext ctx{name, metres_per_unit(units)};
    if (bytes.empty()) return Err{ctx.error(MeshErrc::kEmpty, 0, 0, "the file is empty")};
    switch (format) {
        case Format::kStl:
            return detail::parse_stl(bytes, ctx);
        case Format::kObj:
            return detail::parse_obj(bytes, ctx);
        case Format::kPly:
            return detail::parse_ply(bytes, ctx);
        case Format::kOff:
            return detail::parse_off(bytes, ctx);
    }
    return Err{ctx.error(MeshErrc::kUnknownFormat, 0, 0, "unknown format")};
}

Result<LoadedMesh, MeshError> parse_mesh(std::span<const std::byte> bytes, Format format,
                                         LengthUnit units, std::string_view name) {
    auto indexed = parse_indexed(bytes, format, units, name);
    if (!indexed) return Err{std::move(indexed).error()};
    BuiltMesh built = build_tri_mesh(*indexed);
    return LoadedMesh{std::move(*indexed), std::move(built.mesh), built.detached_triangles};
}

Result<LoadedMesh, MeshError> load_mesh_file(const std::filesystem::path& path, LengthUnit units) {
    const auto format = format_from_path(path);
    if (!format) {
        return Err{unknown_format(path)};
    }
    auto indexed = read_indexed(path, *format, units);
    if (!indexed) return Err{std::move(indexed).error()};
    BuiltMesh built = build_tri_mesh(*indexed);
    return LoadedMesh{std::move(*indexed), std::move(built.mesh), built.detached_triangles};
}

Result<std::unique_ptr<TriMesh>, MeshError> load_mesh_owned(const std::filesystem::path& path,
                                                            LengthUnit units) {
    const auto format = format_from_path(path);
    if (!format) {
        return Err{unknown_format(path)};
    }
    auto indexed = read_indexed(path, *format, units);  // the file's bytes are freed here
    if (!indexed) return Err{std::move(indexed).error()};
    auto mesh = std::make_unique<TriMesh>();
    build_tri_mesh_into(*indexed, *mesh, edit_headroom_faces(indexed->triangles.size()));
    return mesh;
}

Result<TriMesh, MeshError> load_mesh(const std::filesystem::path& path, LengthUnit units) {
    auto loaded = load_mesh_owned(path, units);
    if (!loaded) return Err{std::move(loaded).error()};
    return std::move(**loaded);  // the one copy
}

std::string serialize_mesh(const TriMesh& mesh, Format format, LengthUnit units,
                           Encoding encoding) {
    return serialize_mesh(to_indexed(mesh), format, units, encoding);
}

std::string serialize_mesh(const IndexedMesh& m, Format format, LengthUnit units,
                           Encoding encoding) {
    const double scale = metres_per_unit(units);
    const bool binary = encoding != Encoding::kAscii;
    switch (format) {
        case Format::kStl:
            return detail::write_stl(m, scale, binary);
        case Format::kObj:
            return detail::write_obj(m, scale);
        case Format::kPly:
            return detail::write_ply(m, scale, binary, encoding == Encoding::kBinaryBigEndian);
        case Format::kOff:
            return detail::write_off(m, scale);
    }
    return {};
}

Status<MeshError> save_mesh(const TriMesh& mesh, const std::filesystem::path& path,
                            LengthUnit units) {
    const auto format = format_from_path(path);
    if (!format) {
        return Err{unknown_format(path)};
    }
    // Temp file in the target folder, then rename: a failed write never damages an old file.
    auto written = files::write_file_atomically(path, serialize_mesh(mesh, *format, units));
    if (!written) return Err{io_error(path, written.error().what)};
    return {};
}

}  // namespace kerf::mesh
