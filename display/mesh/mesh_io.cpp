#include "display/mesh/mesh_io.hpp"

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

Result<std::vector<std::byte>, MeshError> read_file(const std::filesystem::path& path) {
    // Regular files only, never blocking on a FIFO, never more than the cap (a link to /dev/zero
    // is a character device: refused before a byte is read).
    auto bytes = files::read_regular_file(path, files::kDefaultMaxInputBytes);
    if (!bytes) return Err{io_error(path, bytes.error().what)};
    return std::move(*bytes);
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
    auto bytes = read_file(path);
    if (!bytes) return Err{std::move(bytes).error()};
    return parse_mesh(*bytes, *format, units, path.string());
}

Result<std::unique_ptr<TriMesh>, MeshError> load_mesh_owned(const std::filesystem::path& path,
                                                            LengthUnit units) {
    const auto format = format_from_path(path);
    if (!format) {
        return Err{unknown_format(path)};
    }
    IndexedMesh indexed;
    {
        auto bytes = read_file(path);
        if (!bytes) return Err{std::move(bytes).error()};
        auto parsed = parse_indexed(*bytes, *format, units, path.string());
        if (!parsed) return Err{std::move(parsed).error()};
        indexed = std::move(*parsed);
    }  // the file's bytes are freed here
    auto mesh = std::make_unique<TriMesh>();
    build_tri_mesh_into(indexed, *mesh, edit_headroom_faces(indexed.triangles.size()));
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
