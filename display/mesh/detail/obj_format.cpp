// Wavefront OBJ: `v` and `f` statements; texture coordinates, normals, groups and materials are
// read past. Polygons are split into a fan of triangles; negative indices count back from the
// last vertex defined so far.
#include <cmath>
#include <cstdio>

#include "display/mesh/detail/formats.hpp"

namespace kerf::mesh::detail {
namespace {

// Statements that are legal OBJ but carry nothing Kerf uses.
constexpr std::string_view kIgnored[] = {
    "vt",    "vn",     "vp",       "l",        "p",    "g",          "o",         "s",
    "mg",    "usemtl", "mtllib",   "cstype",   "deg",  "bmat",       "step",      "curv",
    "curv2", "surf",   "parm",     "trim",     "hole", "scrv",       "sp",        "end",
    "con",   "bevel",  "c_interp", "d_interp", "lod",  "shadow_obj", "trace_obj", "ctech",
    "stech", "maplib", "usemap",   "call"};

bool ignored(std::string_view keyword) {
    for (std::string_view k : kIgnored) {
        if (k == keyword) return true;
    }
    return false;
}

// A face corner reference "i", "i/t", "i//n" or "i/t/n": the vertex index part; nullopt when
// any part is not an integer ("1//x", "1/", "1/2/3/4").
std::optional<long long> vertex_ref(std::string_view token) {
    std::string_view parts[3];
    std::size_t n = 0;
    for (std::size_t start = 0;;) {
        const std::size_t slash = token.find('/', start);
        if (n == 3) return std::nullopt;
        parts[n++] = token.substr(start, slash == std::string_view::npos ? slash : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
    }
    for (std::size_t i = 1; i < n; ++i) {
        const bool empty_texture_ok = i == 1 && n == 3;  // "i//n": no texture index
        if (parts[i].empty() ? !empty_texture_ok : !parse_integer(parts[i])) return std::nullopt;
    }
    return parse_integer(parts[0]);
}

class ObjParser {
public:
    ObjParser(std::string_view text, const ParseContext& ctx) : s_(text), ctx_(ctx) {}
    Result<IndexedMesh, MeshError> parse();

private:
    std::optional<MeshError> vertex();
    std::optional<MeshError> face();
    MeshError fail(MeshErrc kind, std::string what) const {
        return ctx_.error(kind, s_.line(), s_.offset(), std::move(what));
    }

    TextScanner s_;
    const ParseContext& ctx_;
    std::vector<Point> raw_;
    std::vector<Triangle> triangles_;
    std::vector<std::size_t> face_lines_;  // line of each triangle, for late index errors
};

std::optional<MeshError> ObjParser::vertex() {
    double c[3] = {0, 0, 0};
    for (double& v : c) {
        const std::string_view t = s_.next_token_on_line();
        if (t.empty()) return fail(MeshErrc::kSyntax, "'v' needs 3 coordinates");
        const auto d = parse_double(t);
        if (!d) return fail(MeshErrc::kSyntax, "expected a number, found " + quote(t));
        if (!std::isfinite(*d)) return fail(MeshErrc::kNonFinite, "coordinate " + quote(t));
        v = *d;
    }
    // Optional: w, or r g b (a common extension), or w r g b; nothing else (`v 0 0 0 junk`).
    std::size_t extra = 0;
    for (std::string_view t = s_.next_token_on_line(); !t.empty(); t = s_.next_token_on_line()) {
        if (t.front() == '#') break;  // a comment ends the line
        const auto d = parse_double(t);
        if (!d || !std::isfinite(*d) || ++extra > 4) {
            return fail(MeshErrc::kSyntax,
                        "after x y z, 'v' takes only w or r g b numbers, found " + quote(t));
        }
    }
    if (extra == 2) return fail(MeshErrc::kSyntax, "'v' with 5 numbers (expected 3, 4, 6 or 7)");
    s_.rest_of_line();
    const auto p = to_metres(c[0], c[1], c[2], ctx_.metres_per_unit);
    if (!p) return fail(MeshErrc::kNonFinite, "coordinate overflows after unit scaling");
    if (raw_.size() >= 0xFFFFFFFEu) return fail(MeshErrc::kTooLarge, "more than 2^32 - 2 vertices");
    raw_.push_back(*p);
    return std::nullopt;
}

std::optional<MeshError> ObjParser::face() {
    std::uint32_t corner[3] = {0, 0, 0};
    std::size_t n = 0;
    for (std::string_view t = s_.next_token_on_line(); !t.empty(); t = s_.next_token_on_line()) {
        const auto ref = vertex_ref(t);
        if (!ref) return fail(MeshErrc::kSyntax, "bad vertex reference " + quote(t));
        long long index = *ref;
        if (index < 0) index += static_cast<long long>(raw_.size()) + 1;  // relative
        if (*ref == 0 || index <= 0 || index > 0xFFFFFFFFll) {
            return fail(MeshErrc::kIndexOutOfRange, "vertex reference " + quote(t) + " with " +
                                                        std::to_string(raw_.size()) +
                                                        " vertices defined");
        }
        const auto v = static_cast<std::uint32_t>(index - 1);
        if (n < 2) {
            corner[n] = v;
        } else {
            corner[2] = v;
            triangles_.push_back({corner[0], corner[1], corner[2]});
            face_lines_.push_back(s_.line());
            corner[1] = v;
        }
        ++n;
    }
    if (n < 3) return fail(MeshErrc::kSyntax, "face with " + std::to_string(n) + " vertices");
    return std::nullopt;
}

Result<IndexedMesh, MeshError> ObjParser::parse() {
    while (!s_.at_end()) {
        const std::string_view keyword = s_.next_token_on_line();
        std::optional<MeshError> e;
        if (keyword == "v") {
            e = vertex();
        } else if (keyword == "f") {
            e = face();
            s_.rest_of_line();
        } else if (keyword.empty() || keyword.front() == '#' || ignored(keyword)) {
            s_.rest_of_line();
        } else {
            e = fail(MeshErrc::kSyntax, "unknown statement " + quote(keyword));
        }
        if (e) return Err{*e};
    }
    for (std::size_t i = 0; i < triangles_.size(); ++i) {
        for (std::uint32_t v : triangles_[i]) {
            if (v >= raw_.size()) {
                return Err{ctx_.error(MeshErrc::kIndexOutOfRange, face_lines_[i], 0,
                                      "face refers to vertex " + std::to_string(v + 1) +
                                          " but only " + std::to_string(raw_.size()) +
                                          " vertices are defined")};
            }
        }
    }
    if (triangles_.empty()) return Err{ctx_.error(MeshErrc::kEmpty, 0, 0, "OBJ without faces")};
    return weld_indexed(raw_, std::move(triangles_));
}

}  // namespace

Result<IndexedMesh, MeshError> parse_obj(std::span<const std::byte> bytes,
                                         const ParseContext& ctx) {
    return ObjParser(as_text(bytes), ctx).parse();
}

std::string write_obj(const IndexedMesh& m, double metres_per_unit) {
    std::string out = "# kerf\n";
    for (const Point& p : m.positions_m) {
        const Point q = p / metres_per_unit;
        out +=
            "v " + exact_number(q[0]) + " " + exact_number(q[1]) + " " + exact_number(q[2]) + "\n";
    }
    for (const Triangle& t : m.triangles) {
        out += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
               std::to_string(t[2] + 1) + "\n";
    }
    return out;
}

std::string exact_number(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

IndexedMesh weld_indexed(const std::vector<Point>& raw, std::vector<Triangle> triangles,
                         const std::vector<Material>& raw_materials) {
    IndexedMesh out;
    VertexWelder welder;
    std::vector<std::uint32_t> remap(raw.size());
    const bool with_materials = raw_materials.size() == raw.size() && !raw.empty();
    for (std::size_t i = 0; i < raw.size(); ++i) {
        const std::size_t before = out.positions_m.size();
        remap[i] = welder.weld(raw[i], out);
        if (with_materials && out.positions_m.size() > before)
            out.materials.push_back(raw_materials[i]);
    }
    for (Triangle& t : triangles) {
        for (std::uint32_t& v : t) v = remap[v];
    }
    out.triangles = std::move(triangles);
    return out;
}

}  // namespace kerf::mesh::detail
