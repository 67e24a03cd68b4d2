// OFF (Object File Format), ASCII: "OFF" (or COFF/NOFF/CNOFF), the counts "V F E", V vertex
// lines (x y z, then optional colour or normal, ignored), F face lines ("n i0 .. in-1", then an
// optional colour, ignored). '#' starts a comment. Binary OFF is not read.
#include <cmath>

#include "display/mesh/detail/formats.hpp"

namespace kerf::mesh::detail {
namespace {

class OffParser {
public:
    OffParser(std::string_view text, const ParseContext& ctx) : s_(text), ctx_(ctx) {}
    Result<IndexedMesh, MeshError> parse();

private:
    std::string_view token();  // next token, skipping comments and line breaks
    void finish_line() {
        if (!line_done_) s_.rest_of_line();
    }
    std::optional<MeshError> counts();
    std::optional<MeshError> vertex();
    std::optional<MeshError> face();
    std::optional<MeshError> integer(long long& v, std::string_view what);
    MeshError fail(MeshErrc kind, std::string what) const {
        return ctx_.error(kind, s_.line(), s_.offset(), std::move(what));
    }

    TextScanner s_;
    const ParseContext& ctx_;
    bool line_done_ = false;  // a comment already consumed the rest of the line
    long long vertex_count_ = 0;
    long long face_count_ = 0;
    std::vector<Point> raw_;
    std::vector<Triangle> triangles_;
};

std::string_view OffParser::token() {
    line_done_ = false;
    std::string_view t = s_.next_token();
    while (!t.empty() && t.front() == '#') {
        s_.rest_of_line();
        t = s_.next_token();
    }
    const std::size_t hash = t.find('#');
    if (hash != std::string_view::npos) {  // "1.0#comment": keep the number, drop the comment
        s_.rest_of_line();
        line_done_ = true;
        t = t.substr(0, hash);
    }
    return t;
}

std::optional<MeshError> OffParser::integer(long long& v, std::string_view what) {
    const std::string_view t = token();
    if (t.empty())
        return fail(MeshErrc::kTruncated, "file ends where " + std::string(what) + " was expected");
    const auto n = parse_integer(t);
    if (!n) return fail(MeshErrc::kSyntax, "expected " + std::string(what) + ", found " + quote(t));
    v = *n;
    return std::nullopt;
}

std::optional<MeshError> OffParser::counts() {
    const std::string_view magic = token();
    if (magic == "OFF" || magic == "COFF" || magic == "NOFF" || magic == "CNOFF") {
        // counts follow, possibly on the same line
    } else if (magic.size() > 3 && magic.substr(magic.size() - 3) == "OFF") {
        return fail(MeshErrc::kUnsupported, "OFF variant " + quote(magic));
    } else {
        return fail(MeshErrc::kSyntax, "an OFF file starts with 'OFF', found " + quote(magic));
    }
    long long edges = 0;
    const std::string_view first = token();
    if (first == "BINARY") return fail(MeshErrc::kUnsupported, "binary OFF");
    const auto nv = parse_integer(first);
    if (!nv) return fail(MeshErrc::kSyntax, "expected the vertex count, found " + quote(first));
    vertex_count_ = *nv;
    if (auto e = integer(face_count_, "the face count")) return e;
    if (auto e = integer(edges, "the edge count")) return e;
    // A vertex needs at least 6 bytes ("0 0 0\n"), a face at least 8 ("3 0 1 2\n").
    const auto left = static_cast<long long>(s_.remaining());
    if (vertex_count_ < 0 || face_count_ < 0 || vertex_count_ > left / 6 ||
        face_count_ > left / 8 || vertex_count_ * 6 + face_count_ * 8 > left + 1) {
        return fail(MeshErrc::kBadCount,
                    std::to_string(vertex_count_) + " vertices and " + std::to_string(face_count_) +
                        " faces cannot fit in the " + std::to_string(left) + " bytes left");
    }
    finish_line();
    return std::nullopt;
}

std::optional<MeshError> OffParser::vertex() {
    double c[3] = {0, 0, 0};
    for (double& v : c) {
        const std::string_view t = token();
        if (t.empty())
            return fail(MeshErrc::kTruncated, "file ends after " + std::to_string(raw_.size()) +
                                                  " of " + std::to_string(vertex_count_) +
                                                  " vertices");
        const auto d = parse_double(t);
        if (!d) return fail(MeshErrc::kSyntax, "expected a coordinate, found " + quote(t));
        if (!std::isfinite(*d)) return fail(MeshErrc::kNonFinite, "coordinate " + quote(t));
        v = *d;
    }
    finish_line();
    const auto p = to_metres(c[0], c[1], c[2], ctx_.metres_per_unit);
    if (!p) return fail(MeshErrc::kNonFinite, "coordinate overflows after unit scaling");
    raw_.push_back(*p);
    return std::nullopt;
}

std::optional<MeshError> OffParser::face() {
    long long n = 0;
    if (auto e = integer(n, "a face's vertex count")) return e;
    if (n < 3) return fail(MeshErrc::kSyntax, "face with " + std::to_string(n) + " vertices");
    if (n > static_cast<long long>(s_.remaining() / 2 + 1))
        return fail(MeshErrc::kTruncated,
                    "face of " + std::to_string(n) + " vertices runs past the end of the file");
    std::uint32_t first = 0, previous = 0;
    for (long long k = 0; k < n; ++k) {
        long long v = 0;
        if (auto e = integer(v, "a vertex index")) return e;
        if (v < 0 || v >= vertex_count_) {
            return fail(MeshErrc::kIndexOutOfRange,
                        "vertex index " + std::to_string(v) + " but the file has " +
                            std::to_string(vertex_count_) + " vertices");
        }
        const auto i = static_cast<std::uint32_t>(v);
        if (k == 0) first = i;
        if (k >= 2) triangles_.push_back({first, previous, i});
        previous = i;
    }
    finish_line();
    return std::nullopt;
}

Result<IndexedMesh, MeshError> OffParser::parse() {
    if (auto e = counts()) return Err{*e};
    if (vertex_count_ > 0xFFFFFFFEll)
        return Err{fail(MeshErrc::kTooLarge, "more than 2^32 - 2 vertices")};
    raw_.reserve(static_cast<std::size_t>(vertex_count_));
    triangles_.reserve(static_cast<std::size_t>(face_count_));
    for (long long i = 0; i < vertex_count_; ++i) {
        if (auto e = vertex()) return Err{*e};
    }
    for (long long i = 0; i < face_count_; ++i) {
        if (auto e = face()) return Err{*e};
    }
    if (triangles_.empty()) return Err{fail(MeshErrc::kEmpty, "OFF without faces")};
    return weld_indexed(raw_, std::move(triangles_));
}

}  // namespace

Result<IndexedMesh, MeshError> parse_off(std::span<const std::byte> bytes,
                                         const ParseContext& ctx) {
    return OffParser(as_text(bytes), ctx).parse();
}

std::string write_off(const IndexedMesh& m, double metres_per_unit) {
    std::string out = "OFF\n" + std::to_string(m.positions_m.size()) + " " +
                      std::to_string(m.triangles.size()) + " 0\n";
    for (const Point& p : m.positions_m) {
        const Point q = p / metres_per_unit;
        out += exact_number(q[0]) + " " + exact_number(q[1]) + " " + exact_number(q[2]) + "\n";
    }
    for (const Triangle& t : m.triangles) {
        out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " +
               std::to_string(t[2]) + "\n";
    }
    return out;
}

}  // namespace kerf::mesh::detail
