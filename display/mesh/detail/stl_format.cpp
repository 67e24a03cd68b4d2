// STL, ASCII and binary. Binary is recognised by its size (84 + 50 · count bytes), not by the
// first five bytes, because many binary STLs begin with "solid".
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>
#include <vector>

#include "config/base/length_unit.hpp"
#include "display/mesh/detail/formats.hpp"

namespace kerf::mesh::detail {
namespace {

constexpr std::size_t kHeaderBytes = kStlHeaderBytes;
constexpr std::size_t kFacetBytes = kStlFacetBytes;

std::uint32_t read_u32_le(const std::byte* p) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<std::uint32_t>(p[i]);
    return v;
}

float read_f32_le(const std::byte* p) {
    const std::uint32_t bits = read_u32_le(p);
    float f = 0.0f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

bool starts_with_solid(std::string_view text) {
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    return first != std::string_view::npos && text.substr(first, 5) == "solid";
}

bool has_nul(std::string_view text) {
    return text.substr(0, 1024).find('\0') != std::string_view::npos;
}

}  // namespace

/// Welds binary STL corners on the file's float bits, with the bits kept in the table so that a
/// lookup never reads a point back. For a scale s with 2^-800 <= |s| <= 2^800 (every LengthUnit's,
/// checked below) this welds exactly what VertexWelder welds on the points in metres: a finite
/// float x maps to x · s one to one (two floats differ by more than 2^-24 relative, the product is
/// rounded by at most 2^-53 and neither underflows nor overflows), and only ±0 maps to 0, so -0 is
/// taken as +0 here as there. A small table of the corners seen last answers most lookups before
/// the large one is read: a file's neighbouring triangles share corners (in the 1M foot, 82 % of
/// lookups; each large-table lookup is a cache miss, three fifths of the parse).
class FloatBitsWelder {
public:
    struct Key {
        std::uint32_t x, y, z;
    };

    /// Room for `vertices` distinct corners before the table regrows.
    explicit FloatBitsWelder(std::size_t vertices)
        : slots_(std::max<std::size_t>(64, std::bit_ceil(2 * vertices))) {}

    /// The index of the corner with bits `k` (no -0, finite), or `next` after recording it as
    /// new.
    std::uint32_t find_or_add(const Key& k, std::uint32_t next, bool& added) {
        const std::uint64_t h = hash(k);
        Recent& r = recent_[h & (kRecent - 1)];
        added = false;
        if (same(r.key, k)) return r.index;
        r = {k, find_or_insert(k, h, next, added)};
        return r.index;
    }

private:
    struct Slot {
        Key key;
        std::uint32_t index_plus_one;  ///< 0: empty
    };
    /// A corner looked up lately (a NaN key, which no corner has, where none was).
    struct Recent {
        Key key{0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu};
        std::uint32_t index = 0;
    };
    static constexpr std::size_t kRecent = 4096;  // 64 KiB

    static bool same(const Key& a, const Key& b) noexcept {
        return a.x == b.x && a.y == b.y && a.z == b.z;
    }

    /// find_or_add() in the large table, `h` the key's hash.
    std::uint32_t find_or_insert(const Key& k, std::uint64_t h, std::uint32_t next, bool& added) {
        if (2 * (used_ + 1) > slots_.size()) grow();
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t i = h & mask;; i = (i + 1) & mask) {
            Slot& s = slots_[i];
            if (s.index_plus_one == 0) {
                s = {k, next + 1};
                ++used_;
                added = true;
                return next;
            }
            if (same(s.key, k)) return s.index_plus_one - 1;
        }
    }

    static std::uint64_t hash(const Key& k) noexcept {
        std::uint64_t h = ((std::uint64_t{k.x} << 32) | k.y) * 0x9E3779B97F4A7C15ull;
        h ^= (std::uint64_t{k.z} + (h >> 29)) * 0xBF58476D1CE4E5B9ull;
        return h ^ (h >> 32);
    }

    void grow() {
        std::vector<Slot> old = std::exchange(slots_, std::vector<Slot>(2 * slots_.size()));
        const std::size_t mask = slots_.size() - 1;
        for (const Slot& s : old) {
            if (s.index_plus_one == 0) continue;
            std::size_t i = hash(s.key) & mask;
            while (slots_[i].index_plus_one != 0) i = (i + 1) & mask;
            slots_[i] = s;
        }
    }

    std::vector<Slot> slots_;
    std::size_t used_ = 0;
    std::array<Recent, kRecent> recent_{};
};

namespace {

constexpr bool float_bits_weld_exactly(double metres_per_unit) {
    const double s = metres_per_unit < 0 ? -metres_per_unit : metres_per_unit;
    return s >= 0x1p-800 && s <= 0x1p800;
}
static_assert(std::ranges::all_of(kLengthUnits,
                                  [](LengthUnit u) {
                                      return float_bits_weld_exactly(metres_per_unit(u));
                                  }),
              "a unit whose scale could merge or split float coordinates: weld on the points");

std::uint32_t zero_as_plus(std::uint32_t float_bits) noexcept {
    return float_bits == 0x80000000u ? 0u : float_bits;
}

bool finite_bits(std::uint32_t float_bits) noexcept {
    return (float_bits & 0x7F800000u) != 0x7F800000u;
}

MeshError non_finite(const ParseContext& ctx, std::uint32_t f, std::size_t offset) {
    return ctx.error(MeshErrc::kNonFinite, 0, offset,
                     "triangle " + std::to_string(f) + " has a NaN or infinite coordinate");
}

}  // namespace

BinaryStlParser::BinaryStlParser(std::uint32_t count, const ParseContext& ctx)
    : ctx_(ctx), count_(count) {
    out_.triangles.reserve(count);
    const std::size_t expected = count / 2 + 2;  // a closed mesh: V = F/2 + 2 - 2*genus per shell
    out_.positions_m.reserve(expected);
    welder_ = std::make_unique<FloatBitsWelder>(expected);
}

BinaryStlParser::~BinaryStlParser() = default;

std::optional<MeshError> BinaryStlParser::add_facets(std::span<const std::byte> facets) {
    const std::size_t n = facets.size() / kFacetBytes;
    for (std::size_t i = 0; i < n && next_ < count_; ++i, ++next_) {
        const std::uint32_t f = next_;
        const std::size_t base = kHeaderBytes + std::size_t{f} * kFacetBytes;
        const std::byte* facet = facets.data() + i * kFacetBytes;
        Triangle t{};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::byte* v = facet + 12 + 12 * k;
            const FloatBitsWelder::Key key{read_u32_le(v), read_u32_le(v + 4), read_u32_le(v + 8)};
            if (!finite_bits(key.x) || !finite_bits(key.y) || !finite_bits(key.z))
                return non_finite(ctx_, f, base + 12 + 12 * k);
            bool added = false;
            const auto index = static_cast<std::uint32_t>(out_.positions_m.size());
            t[k] = welder_->find_or_add(
                {zero_as_plus(key.x), zero_as_plus(key.y), zero_as_plus(key.z)}, index, added);
            if (added) {
                out_.positions_m.push_back(*to_metres(read_f32_le(v), read_f32_le(v + 4),
                                                      read_f32_le(v + 8), ctx_.metres_per_unit));
            }
        }
        out_.triangles.push_back(t);
    }
    return std::nullopt;
}

IndexedMesh BinaryStlParser::finish() && {
    welder_.reset();
    return std::move(out_);
}

namespace {

Result<IndexedMesh, MeshError> parse_binary(std::span<const std::byte> bytes,
                                            const ParseContext& ctx) {
    const std::uint32_t count = stl_facet_count(bytes.data());
    if (count == 0) return Err{ctx.error(MeshErrc::kEmpty, 0, 80, "binary STL with 0 triangles")};
    BinaryStlParser parser(count, ctx);
    if (auto e = parser.add_facets(bytes.subspan(kHeaderBytes))) return Err{std::move(*e)};
    return std::move(parser).finish();
}

// Reads "vertex x y z" three times between "outer loop" and "endloop".
class AsciiStl {
public:
    AsciiStl(std::string_view text, const ParseContext& ctx) : s_(text), ctx_(ctx) {}
    Result<IndexedMesh, MeshError> parse();

private:
    std::optional<MeshError> expect(std::string_view word);
    std::optional<MeshError> facet();
    std::optional<MeshError> number(double& v, bool finite);
    MeshError fail(MeshErrc kind, std::string what) const {
        return ctx_.error(kind, s_.line(), s_.offset(), std::move(what));
    }

    TextScanner s_;
    const ParseContext& ctx_;
    IndexedMesh out_;
    VertexWelder welder_;
};

std::optional<MeshError> AsciiStl::expect(std::string_view word) {
    const std::string_view t = s_.next_token();
    if (t == word) return std::nullopt;
    if (t.empty())
        return fail(MeshErrc::kTruncated,
                    "file ends where '" + std::string(word) + "' was expected");
    return fail(MeshErrc::kSyntax, "expected '" + std::string(word) + "', found " + quote(t));
}

std::optional<MeshError> AsciiStl::number(double& v, bool finite) {
    const std::string_view t = s_.next_token();
    if (t.empty()) return fail(MeshErrc::kTruncated, "file ends where a number was expected");
    const auto d = parse_double(t);
    if (!d) return fail(MeshErrc::kSyntax, "expected a number, found " + quote(t));
    if (finite && !std::isfinite(*d)) return fail(MeshErrc::kNonFinite, "coordinate " + quote(t));
    v = *d;
    return std::nullopt;
}

std::optional<MeshError> AsciiStl::facet() {
    double ignored = 0.0;  // stored normals are recomputed from the winding
    if (auto e = expect("normal")) return e;
    for (int i = 0; i < 3; ++i) {
        if (auto e = number(ignored, false)) return e;
    }
    if (auto e = expect("outer")) return e;
    if (auto e = expect("loop")) return e;
    Triangle t{};
    int corners = 0;
    for (std::string_view w = s_.next_token(); w != "endloop"; w = s_.next_token()) {
        if (w.empty()) return fail(MeshErrc::kTruncated, "file ends inside a facet");
        if (w != "vertex")
            return fail(MeshErrc::kSyntax, "expected 'vertex' or 'endloop', found " + quote(w));
        double x = 0, y = 0, z = 0;
        if (auto e = number(x, true)) return e;
        if (auto e = number(y, true)) return e;
        if (auto e = number(z, true)) return e;
        const auto p = to_metres(x, y, z, ctx_.metres_per_unit);
        if (!p) return fail(MeshErrc::kNonFinite, "coordinate overflows after unit scaling");
        if (corners == 3) return fail(MeshErrc::kUnsupported, "facet with more than 3 vertices");
        t[static_cast<std::size_t>(corners++)] = welder_.weld(*p, out_);
    }
    if (corners != 3) {
        return fail(MeshErrc::kSyntax, "facet with " + std::to_string(corners) + " vertices");
    }
    out_.triangles.push_back(t);
    return expect("endfacet");
}

Result<IndexedMesh, MeshError> AsciiStl::parse() {
    if (auto e = expect("solid")) return Err{*e};
    s_.rest_of_line();  // the solid's name
    for (std::string_view w = s_.next_token(); !w.empty(); w = s_.next_token()) {
        if (w == "facet") {
            if (auto e = facet()) return Err{*e};
        } else if (w == "endsolid") {
            s_.rest_of_line();
            const std::string_view next = s_.next_token();
            if (next.empty()) break;
            if (next != "solid")
                return Err{fail(MeshErrc::kSyntax,
                                "expected 'solid' or end of file, found " + quote(next))};
            s_.rest_of_line();
        } else {
            return Err{
                fail(MeshErrc::kSyntax, "expected 'facet' or 'endsolid', found " + quote(w))};
        }
    }
    if (out_.triangles.empty()) return Err{fail(MeshErrc::kEmpty, "ASCII STL without facets")};
    return std::move(out_);
}

// Little-endian at `w`, which moves past it.
void put_u32(char*& w, std::uint32_t bits) {
    for (int i = 0; i < 4; ++i) *w++ = static_cast<char>((bits >> (8 * i)) & 0xFFu);
}

void put_f32(char*& w, float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    put_u32(w, bits);
}

Point facet_normal(const IndexedMesh& m, const Triangle& t) {
    const Point n =
        (m.positions_m[t[1]] - m.positions_m[t[0]]) % (m.positions_m[t[2]] - m.positions_m[t[0]]);
    const double len = n.norm();
    return len > 0.0 ? n / len : Point{0.0, 0.0, 0.0};
}

}  // namespace

Result<IndexedMesh, MeshError> parse_stl(std::span<const std::byte> bytes,
                                         const ParseContext& ctx) {
    const std::string_view text = as_text(bytes);
    if (bytes.size() >= kHeaderBytes) {
        const std::uint64_t count = stl_facet_count(bytes.data());
        const std::uint64_t expected = kHeaderBytes + count * kFacetBytes;
        if (expected == bytes.size()) return parse_binary(bytes, ctx);
        if (!starts_with_solid(text) || has_nul(text)) {
            const bool short_file = bytes.size() < expected;
            return Err{ctx.error(short_file ? MeshErrc::kTruncated : MeshErrc::kBadCount, 0, 80,
                                 "binary STL header claims " + std::to_string(count) +
                                     " triangles (" + std::to_string(expected) +
                                     " bytes) but the file has " + std::to_string(bytes.size()) +
                                     " bytes")};
        }
    } else if (!starts_with_solid(text)) {
        return Err{
            ctx.error(MeshErrc::kTruncated, 0, bytes.size(),
                      "only " + std::to_string(bytes.size()) +
                          " bytes: neither a binary STL (84-byte header) nor ASCII ('solid')")};
    }
    return AsciiStl(text, ctx).parse();
}

std::string write_stl(const IndexedMesh& m, double metres_per_unit, bool binary) {
    std::string out;
    if (binary) {
        // Sized once and written in place (a push_back per byte was a tenth of `kerf cut`);
        // the zeros resize writes are each facet's attribute bytes.
        out.resize(kHeaderBytes + m.triangles.size() * kFacetBytes, '\0');
        const std::string_view header = "kerf binary STL";
        std::fill(std::copy(header.begin(), header.end(), out.begin()), out.begin() + 80, ' ');
        char* w = out.data() + 80;
        put_u32(w, static_cast<std::uint32_t>(m.triangles.size()));
        // Each vertex in file units once (a vertex is a corner of about six facets): the same
        // division and rounding per coordinate as per corner, a sixth of the divisions.
        std::vector<std::array<float, 3>> corner(m.positions_m.size());
        for (std::size_t v = 0; v < corner.size(); ++v)
            for (int i = 0; i < 3; ++i)
                corner[v][i] = static_cast<float>(m.positions_m[v][i] / metres_per_unit);
        for (const Triangle& t : m.triangles) {
            const Point nrm = facet_normal(m, t);
            for (int i = 0; i < 3; ++i) put_f32(w, static_cast<float>(nrm[i]));
            for (std::uint32_t v : t)
                for (int i = 0; i < 3; ++i) put_f32(w, corner[v][i]);
            w += 2;  // attribute byte count: 0
        }
        return out;
    }
    out = "solid kerf\n";
    for (const Triangle& t : m.triangles) {
        const Point nrm = facet_normal(m, t);
        out += "  facet normal " + exact_number(nrm[0]) + " " + exact_number(nrm[1]) + " " +
               exact_number(nrm[2]) + "\n    outer loop\n";
        for (std::uint32_t v : t) {
            const Point p = m.positions_m[v] / metres_per_unit;
            out += "      vertex " + exact_number(p[0]) + " " + exact_number(p[1]) + " " +
                   exact_number(p[2]) + "\n";
        }
        out += "    endloop\n  endfacet\n";
    }
    out += "endsolid kerf\n";
    return out;
}

}  // namespace kerf::mesh::detail
