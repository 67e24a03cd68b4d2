// PLY: ASCII, binary little endian and binary big endian. Reads the `vertex` element's x, y, z
// (and Kerf's own `material`), the `face` element's `vertex_indices` (or `vertex_index`) list;
// every other element and property is read past. Every count is checked against the bytes left
// before anything is reserved.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "display/mesh/detail/formats.hpp"

namespace kerf::mesh::detail {
namespace {

enum class PlyType { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };
enum class PlyEncoding { kAscii, kLittle, kBig };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::kF32;
    bool is_list = false;
    PlyType count_type = PlyType::kU8;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> props;
    std::size_t line = 0;
};

std::optional<PlyType> parse_type(std::string_view t) {
    static constexpr std::pair<std::string_view, PlyType> kNames[] = {
        {"char", PlyType::kI8},    {"int8", PlyType::kI8},     {"uchar", PlyType::kU8},
        {"uint8", PlyType::kU8},   {"short", PlyType::kI16},   {"int16", PlyType::kI16},
        {"ushort", PlyType::kU16}, {"uint16", PlyType::kU16},  {"int", PlyType::kI32},
        {"int32", PlyType::kI32},  {"uint", PlyType::kU32},    {"uint32", PlyType::kU32},
        {"float", PlyType::kF32},  {"float32", PlyType::kF32}, {"double", PlyType::kF64},
        {"float64", PlyType::kF64}};
    for (const auto& [name, type] : kNames) {
        if (name == t) return type;
    }
    return std::nullopt;
}

std::size_t size_of(PlyType t) {
    switch (t) {
        case PlyType::kI8:
        case PlyType::kU8:
            return 1;
        case PlyType::kI16:
        case PlyType::kU16:
            return 2;
        case PlyType::kI32:
        case PlyType::kU32:
        case PlyType::kF32:
            return 4;
        case PlyType::kF64:
            return 8;
    }
    return 1;
}

bool is_integer(PlyType t) { return t != PlyType::kF32 && t != PlyType::kF64; }

class PlyParser {
public:
    PlyParser(std::span<const std::byte> bytes, const ParseContext& ctx)
        : bytes_(bytes), text_(as_text(bytes)), s_(text_), ctx_(ctx) {}
    Result<IndexedMesh, MeshError> parse();

private:
    std::optional<MeshError> header();
    std::optional<MeshError> header_line(std::string_view keyword);
    std::optional<MeshError> element(const PlyElement& e);
    std::optional<MeshError> value(PlyType type, double& v);
    std::optional<MeshError> check_room(const PlyElement& e);
    std::optional<MeshError> face(const PlyProperty& p);
    MeshError fail(MeshErrc kind, std::string what) const {
        const bool ascii = encoding_ == PlyEncoding::kAscii || !in_data_;
        return ctx_.error(kind, ascii ? s_.line() : 0, ascii ? s_.offset() : pos_, std::move(what));
    }

    std::span<const std::byte> bytes_;
    std::string_view text_;
    TextScanner s_;
    const ParseContext& ctx_;
    PlyEncoding encoding_ = PlyEncoding::kAscii;
    bool in_data_ = false;
    std::size_t pos_ = 0;  // binary read position
    std::vector<PlyElement> elements_;
    std::vector<Point> raw_;
    std::vector<Material> materials_;
    std::vector<Triangle> triangles_;
    /// "vertex" elements not read yet: while any is left, face indices are checked at the end.
    std::size_t vertex_elements_left_ = 0;
    /// A face read before its vertices: its triangles and where its index list was, so that a
    /// bad index found at the end still names the real line or byte.
    struct FaceSite {
        std::size_t first_triangle, triangles, line, offset;
    };
    std::vector<FaceSite> deferred_;
};

std::optional<MeshError> PlyParser::header_line(std::string_view keyword) {
    if (keyword == "comment" || keyword == "obj_info" || keyword.empty()) {
        s_.rest_of_line();
        return std::nullopt;
    }
    if (keyword == "format") {
        const std::string_view f = s_.next_token_on_line();
        const std::string_view version = s_.next_token_on_line();
        if (f == "ascii")
            encoding_ = PlyEncoding::kAscii;
        else if (f == "binary_little_endian")
            encoding_ = PlyEncoding::kLittle;
        else if (f == "binary_big_endian")
            encoding_ = PlyEncoding::kBig;
        else
            return fail(MeshErrc::kSyntax, "unknown PLY format " + quote(f));
        if (version != "1.0") return fail(MeshErrc::kUnsupported, "PLY version " + quote(version));
    } else if (keyword == "element") {
        PlyElement e;
        e.name = std::string(s_.next_token_on_line());
        const std::string_view count = s_.next_token_on_line();
        const auto n = parse_integer(count);
        e.line = s_.line();
        if (e.name.empty() || !n || *n < 0)
            return fail(MeshErrc::kBadCount, "bad element count " + quote(count));
        e.count = static_cast<std::uint64_t>(*n);
        elements_.push_back(std::move(e));
    } else if (keyword == "property") {
        if (elements_.empty()) return fail(MeshErrc::kSyntax, "property before any element");
        PlyProperty p;
        std::string_view t = s_.next_token_on_line();
        if (t == "list") {
            p.is_list = true;
            const auto ct = parse_type(t = s_.next_token_on_line());
            if (!ct || !is_integer(*ct))
                return fail(MeshErrc::kSyntax, "bad list count type " + quote(t));
            p.count_type = *ct;
            t = s_.next_token_on_line();
        }
        const auto type = parse_type(t);
        if (!type) return fail(MeshErrc::kSyntax, "unknown property type " + quote(t));
        p.type = *type;
        p.name = std::string(s_.next_token_on_line());
        if (p.name.empty()) return fail(MeshErrc::kSyntax, "property without a name");
        elements_.back().props.push_back(std::move(p));
    } else {
        return fail(MeshErrc::kSyntax, "unknown PLY header line " + quote(keyword));
    }
    if (!s_.next_token_on_line().empty())
        return fail(MeshErrc::kSyntax, "extra words on header line");
    s_.rest_of_line();
    return std::nullopt;
}

std::optional<MeshError> PlyParser::header() {
    if (s_.rest_of_line() != "ply")
        return fail(MeshErrc::kSyntax, "a PLY file starts with the line 'ply'");
    bool has_format = false;
    while (true) {
        if (s_.at_end()) return fail(MeshErrc::kTruncated, "file ends inside the PLY header");
        const std::string_view keyword = s_.next_token_on_line();
        if (keyword == "end_header") break;
        has_format = has_format || keyword == "format";
        if (auto e = header_line(keyword)) return e;
    }
    if (!has_format) return fail(MeshErrc::kSyntax, "PLY header without a 'format' line");
    s_.rest_of_line();
    pos_ = s_.position();
    in_data_ = true;
    return std::nullopt;
}

std::optional<MeshError> PlyParser::value(PlyType type, double& v) {
    if (encoding_ == PlyEncoding::kAscii) {
        const std::string_view t = s_.next_token();
        if (t.empty()) return fail(MeshErrc::kTruncated, "file ends inside the PLY data");
        const auto d = parse_double(t);
        if (!d) return fail(MeshErrc::kSyntax, "expected a number, found " + quote(t));
        if (is_integer(type) && (*d != std::floor(*d) || !std::isfinite(*d))) {
            return fail(MeshErrc::kSyntax, "expected an integer, found " + quote(t));
        }
        v = *d;
        return std::nullopt;
    }
    const std::size_t n = size_of(type);
    if (bytes_.size() - pos_ < n)
        return fail(MeshErrc::kTruncated, "file ends inside the PLY data");
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = encoding_ == PlyEncoding::kBig ? i : n - 1 - i;
        bits = (bits << 8) | static_cast<std::uint64_t>(bytes_[pos_ + k]);
    }
    pos_ += n;
    switch (type) {
        case PlyType::kI8:
            v = static_cast<std::int8_t>(bits);
            break;
        case PlyType::kU8:
            v = static_cast<double>(bits);
            break;
        case PlyType::kI16:
            v = static_cast<std::int16_t>(bits);
            break;
        case PlyType::kU16:
            v = static_cast<double>(bits);
            break;
        case PlyType::kI32:
            v = static_cast<std::int32_t>(bits);
            break;
        case PlyType::kU32:
            v = static_cast<double>(bits);
            break;
        case PlyType::kF32: {
            float f = 0.0f;
            const auto b32 = static_cast<std::uint32_t>(bits);
            std::memcpy(&f, &b32, sizeof f);
            v = f;
            break;
        }
        case PlyType::kF64:
            std::memcpy(&v, &bits, sizeof v);
            break;
    }
    return std::nullopt;
}

std::optional<MeshError> PlyParser::check_room(const PlyElement& e) {
    std::size_t min_bytes = 0;  // per item; an ASCII value takes at least 2 bytes
    for (const PlyProperty& p : e.props) {
        min_bytes +=
            encoding_ == PlyEncoding::kAscii ? 2 : size_of(p.is_list ? p.count_type : p.type);
    }
    const std::size_t left =
        encoding_ == PlyEncoding::kAscii ? s_.remaining() + 1 : bytes_.size() - pos_;
    if (min_bytes > 0 && e.count > left / min_bytes) {
        return ctx_.error(MeshErrc::kBadCount, e.line, 0,
                          "element '" + e.name + "' claims " + std::to_string(e.count) +
                              " items, which needs at least " + std::to_string(min_bytes) +
                              " bytes each, but only " + std::to_string(left) + " bytes are left");
    }
    return std::nullopt;
}

// A number read from the file, for an error message: an integer when it is one and fits, else as
// written by %g (never a float-to-integer conversion out of range: that is undefined).
std::string number_text(double x) {
    if (std::isfinite(x) && std::abs(x) < 9.0e15 && x == std::floor(x))
        return std::to_string(static_cast<long long>(x));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

// Reads one face's index list of `n` entries and appends its fan of triangles.
std::optional<MeshError> PlyParser::face(const PlyProperty& p) {
    double count = 0;
    if (auto e = value(p.count_type, count)) return e;
    if (!(count >= 3))  // NaN too
        return fail(MeshErrc::kSyntax, "face with " + number_text(count) + " vertices");
    const std::size_t per = encoding_ == PlyEncoding::kAscii ? 2 : size_of(p.type);
    const std::size_t left =
        encoding_ == PlyEncoding::kAscii ? s_.remaining() + 1 : bytes_.size() - pos_;
    if (count > static_cast<double>(left / per)) {
        return fail(MeshErrc::kTruncated, "face list of " + number_text(count) +
                                              " entries but only " + std::to_string(left) +
                                              " bytes left");
    }
    const auto n = static_cast<std::size_t>(count);
    const bool ascii = encoding_ == PlyEncoding::kAscii;
    if (vertex_elements_left_ > 0) {
        deferred_.push_back(
            {triangles_.size(), n - 2, ascii ? s_.line() : 0, ascii ? s_.offset() : pos_});
    }
    std::uint32_t first = 0, previous = 0;
    for (std::size_t k = 0; k < n; ++k) {
        double raw = 0;
        const std::size_t at = pos_;  // binary: the index's own byte
        if (auto e = value(p.type, raw)) return e;
        if (raw < 0 || raw > 4294967294.0 || raw != std::floor(raw)) {
            return fail(MeshErrc::kIndexOutOfRange, "vertex index " + number_text(raw));
        }
        const auto v = static_cast<std::uint32_t>(raw);
        if (vertex_elements_left_ == 0 && v >= raw_.size()) {
            return ctx_.error(MeshErrc::kIndexOutOfRange, ascii ? s_.line() : 0,
                              ascii ? s_.offset() : at,
                              "a face refers to vertex " + std::to_string(v) + " but only " +
                                  std::to_string(raw_.size()) + " vertices exist");
        }
        if (k == 0) first = v;
        if (k >= 2) triangles_.push_back({first, previous, v});
        previous = v;
    }
    return std::nullopt;
}

std::optional<MeshError> PlyParser::element(const PlyElement& e) {
    if (auto err = check_room(e)) return err;
    if (e.props.empty()) return std::nullopt;
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int slot_of[64];  // property -> 0,1,2 (x,y,z), 3 (material), 4 (face list), -1 (skip)
    if (e.props.size() > 64)
        return ctx_.error(MeshErrc::kUnsupported, e.line, 0, "more than 64 properties");
    bool found[5] = {false, false, false, false, false};
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const PlyProperty& p = e.props[i];
        int slot = -1;
        if (is_vertex && !p.is_list) {
            slot = p.name == "x"          ? 0
                   : p.name == "y"        ? 1
                   : p.name == "z"        ? 2
                   : p.name == "material" ? 3
                                          : -1;
        } else if (is_face && p.is_list &&
                   (p.name == "vertex_indices" || p.name == "vertex_index")) {
            slot = found[4] ? -1 : 4;
        }
        if (slot >= 0) found[slot] = true;
        slot_of[i] = slot;
    }
    if (is_vertex && !(found[0] && found[1] && found[2])) {
        return ctx_.error(MeshErrc::kSyntax, e.line, 0,
                          "element 'vertex' lacks an x, y or z property");
    }
    if (is_face && !found[4]) {
        return ctx_.error(MeshErrc::kSyntax, e.line, 0,
                          "element 'face' lacks a 'vertex_indices' list");
    }
    if (is_vertex) raw_.reserve(raw_.size() + e.count);
    if (is_face) triangles_.reserve(triangles_.size() + e.count);
    for (std::uint64_t item = 0; item < e.count; ++item) {
        double c[4] = {0, 0, 0, 0};
        for (std::size_t i = 0; i < e.props.size(); ++i) {
            const PlyProperty& p = e.props[i];
            if (slot_of[i] == 4) {
                if (auto err = face(p)) return err;
            } else if (p.is_list) {
                double n = 0, ignored = 0;
                if (auto err = value(p.count_type, n)) return err;
                const std::size_t per = encoding_ == PlyEncoding::kAscii ? 2 : size_of(p.type);
                const std::size_t left =
                    encoding_ == PlyEncoding::kAscii ? s_.remaining() + 1 : bytes_.size() - pos_;
                if (!(n >= 0) || n > static_cast<double>(left / per))  // NaN too
                    return fail(MeshErrc::kTruncated, "list longer than the data left");
                for (auto k = static_cast<std::size_t>(n); k > 0; --k) {
                    if (auto err = value(p.type, ignored)) return err;
                }
            } else {
                double v = 0;
                if (auto err = value(p.type, v)) return err;
                if (slot_of[i] >= 0) c[slot_of[i]] = v;
            }
        }
        if (is_vertex) {
            const auto pt = to_metres(c[0], c[1], c[2], ctx_.metres_per_unit);
            if (!pt)
                return fail(MeshErrc::kNonFinite,
                            "vertex " + std::to_string(item) + " has a NaN or infinite coordinate");
            if (!(c[3] >= 0 && c[3] <= 2))  // NaN too
                return fail(MeshErrc::kSyntax, "material must be 0, 1 or 2");
            if (raw_.size() >= 0xFFFFFFFEu)
                return fail(MeshErrc::kTooLarge, "more than 2^32 - 2 vertices");
            raw_.push_back(*pt);
            materials_.push_back(static_cast<Material>(static_cast<int>(c[3])));
        }
    }
    return std::nullopt;
}

Result<IndexedMesh, MeshError> PlyParser::parse() {
    if (auto e = header()) return Err{*e};
    for (const PlyElement& e : elements_) vertex_elements_left_ += e.name == "vertex" ? 1 : 0;
    for (const PlyElement& e : elements_) {
        if (auto err = element(e)) return Err{*err};
        if (e.name == "vertex") --vertex_elements_left_;
    }
    for (const FaceSite& f : deferred_) {  // faces that came before (some of) the vertices
        for (std::size_t i = f.first_triangle; i < f.first_triangle + f.triangles; ++i) {
            for (std::uint32_t v : triangles_[i]) {
                if (v >= raw_.size()) {
                    return Err{ctx_.error(MeshErrc::kIndexOutOfRange, f.line, f.offset,
                                          "a face refers to vertex " + std::to_string(v) +
                                              " but only " + std::to_string(raw_.size()) +
                                              " vertices exist")};
                }
            }
        }
    }
    if (triangles_.empty()) return Err{ctx_.error(MeshErrc::kEmpty, 0, 0, "PLY without faces")};
    return weld_indexed(raw_, std::move(triangles_), materials_);
}

void put_binary(std::string& out, const void* value, std::size_t n, bool big_endian) {
    const auto* b = static_cast<const unsigned char*>(value);
    for (std::size_t i = 0; i < n; ++i)
        out.push_back(static_cast<char>(b[big_endian ? n - 1 - i : i]));
}

}  // namespace

Result<IndexedMesh, MeshError> parse_ply(std::span<const std::byte> bytes,
                                         const ParseContext& ctx) {
    return PlyParser(bytes, ctx).parse();
}

std::string write_ply(const IndexedMesh& m, double metres_per_unit, bool binary, bool big_endian) {
    const bool with_material = m.materials.size() == m.positions_m.size();
    std::string out = "ply\nformat ";
    out += !binary ? "ascii" : big_endian ? "binary_big_endian" : "binary_little_endian";
    out += " 1.0\ncomment written by kerf\nelement vertex " + std::to_string(m.positions_m.size()) +
           "\nproperty double x\nproperty double y\nproperty double z\n";
    if (with_material) out += "property uchar material\n";
    out += "element face " + std::to_string(m.triangles.size()) +
           "\nproperty list uchar int vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < m.positions_m.size(); ++i) {
        const Point p = m.positions_m[i] / metres_per_unit;
        const auto material = with_material ? static_cast<unsigned char>(m.materials[i]) : 0;
        if (!binary) {
            out += exact_number(p[0]) + " " + exact_number(p[1]) + " " + exact_number(p[2]);
            out += with_material ? " " + std::to_string(material) + "\n" : "\n";
            continue;
        }
        for (int k = 0; k < 3; ++k) put_binary(out, &p[k], 8, big_endian);
        if (with_material) out.push_back(static_cast<char>(material));
    }
    for (const Triangle& t : m.triangles) {
        if (!binary) {
            out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " +
                   std::to_string(t[2]) + "\n";
            continue;
        }
        out.push_back(3);
        for (std::uint32_t v : t) {
            const auto i = static_cast<std::int32_t>(v);
            put_binary(out, &i, 4, big_endian);
        }
    }
    return out;
}

}  // namespace kerf::mesh::detail
