// Every kind of bad input gives the expected MeshError — kind, line or byte offset, and a
// message naming the problem — and never a crash.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "display/mesh/mesh_io.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/mesh/mesh_test_support.hpp"

namespace kerf::mesh {
namespace {

struct Bad {
    const char* name;  // test label
    Format format;
    std::string bytes;
    MeshErrc kind;
    std::size_t line;      // 0 = not checked
    const char* mentions;  // substring of the message
};

std::string binary_stl(std::uint32_t claimed, std::size_t facets) {
    std::string s(80, ' ');
    for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((claimed >> (8 * i)) & 0xFFu));
    s += std::string(50 * facets, '\0');
    return s;
}

std::string binary_stl_with_nan() {
    std::string s = binary_stl(1, 1);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(s.data() + 84 + 12 + 12 + 4, &nan, 4);  // second vertex, y
    return s;
}

const std::string kAsciiFacet = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

std::string ply_binary_lying_count() {
    return "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
           "property float y\nproperty float z\nend_header\n" +
           std::string(24, '\0');
}

std::string ply_binary_long_face_list() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
        "y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    s += std::string(36, '\0');
    s.push_back(static_cast<char>(255));  // 255 indices claimed, 4 bytes follow
    s += std::string(4, '\0');
    return s;
}

std::string ply_binary_nan() {
    std::string s =
        "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty double x\nproperty double "
        "y\n"
        "property double z\nend_header\n";
    const unsigned char nan_be[8] = {0x7F, 0xF8, 0, 0, 0, 0, 0, 0};
    s += std::string(16, '\0');
    s.append(reinterpret_cast<const char*>(nan_be), 8);
    return s;
}

// A face whose third index is a float beyond any integer (or NaN): refused by name, never
// converted to an integer (out-of-range float-to-int conversion is undefined; the fuzzer found it).
std::string ply_binary_float_index(float third) {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
        "y\n"
        "property float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n";
    s += std::string(36, '\0');
    s.push_back(3);
    const float idx[3] = {0.0f, 1.0f, third};
    s.append(reinterpret_cast<const char*>(idx), sizeof idx);  // little-endian host (x86-64)
    return s;
}

const Bad kBad[] = {
    {"StlEmpty", Format::kStl, "", MeshErrc::kEmpty, 0, "empty"},
    {"StlTooShortForAHeader", Format::kStl, std::string(50, 'x'), MeshErrc::kTruncated, 0,
     "84-byte"},
    {"StlBinaryTruncated", Format::kStl, binary_stl(1000, 1), MeshErrc::kTruncated, 0,
     "1000 triangles"},
    {"StlBinaryTrailingBytes", Format::kStl, binary_stl(1, 2), MeshErrc::kBadCount, 0,
     "claims 1 triangles"},
    {"StlBinaryNoTriangles", Format::kStl, binary_stl(0, 0), MeshErrc::kEmpty, 0, "0 triangles"},
    {"StlBinaryNaNVertex", Format::kStl, binary_stl_with_nan(), MeshErrc::kNonFinite, 0,
     "triangle 0"},
    {"StlAsciiEndsInsideFacet", Format::kStl, kAsciiFacet + "vertex 1 0 0\n", MeshErrc::kTruncated,
     6, "inside a facet"},
    {"StlAsciiNaN", Format::kStl, kAsciiFacet + "vertex nan 0 0\n", MeshErrc::kNonFinite, 5,
     "'nan'"},
    {"StlAsciiOverflow", Format::kStl, kAsciiFacet + "vertex 1e999 0 0\n", MeshErrc::kNonFinite, 5,
     "1e999"},
    {"StlAsciiNotANumber", Format::kStl, kAsciiFacet + "vertex 1 zero 0\n", MeshErrc::kSyntax, 5,
     "'zero'"},
    {"StlAsciiQuad", Format::kStl,
     kAsciiFacet + "vertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\n", MeshErrc::kUnsupported, 7,
     "more than 3"},
    {"StlAsciiTwoVertices", Format::kStl, kAsciiFacet + "vertex 1 0 0\nendloop\n",
     MeshErrc::kSyntax, 6, "2 vertices"},
    {"StlAsciiBadKeyword", Format::kStl, "solid t\nfacett normal 0 0 1\n", MeshErrc::kSyntax, 2,
     "'facett'"},
    {"StlAsciiNoFacets", Format::kStl, "solid t\nendsolid t\n", MeshErrc::kEmpty, 0,
     "without facets"},
    {"ObjIndexPastTheEnd", Format::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n",
     MeshErrc::kIndexOutOfRange, 4, "vertex 5"},
    {"ObjIndexZero", Format::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
     MeshErrc::kIndexOutOfRange, 4, "'0'"},
    {"ObjRelativeIndexTooFarBack", Format::kObj, "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n",
     MeshErrc::kIndexOutOfRange, 3, "'-3'"},
    {"ObjFaceWithTwoVertices", Format::kObj, "v 0 0 0\nv 1 0 0\nf 1 2\n", MeshErrc::kSyntax, 3,
     "2 vertices"},
    {"ObjVertexWithTwoCoordinates", Format::kObj, "v 0 0\n", MeshErrc::kSyntax, 1, "3 coordinates"},
    {"ObjInfiniteCoordinate", Format::kObj, "v 0 inf 0\n", MeshErrc::kNonFinite, 1, "'inf'"},
    {"ObjBadReference", Format::kObj, "v 0 0 0\nf 1 x/2 1\n", MeshErrc::kSyntax, 2, "'x/2'"},
    {"ObjBadNormalReference", Format::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//x 2 3\n",
     MeshErrc::kSyntax, 4, "'1//x'"},
    {"ObjTooManySlashes", Format::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n",
     MeshErrc::kSyntax, 4, "'1/1/1/1'"},
    {"ObjEmptyTextureWithoutNormal", Format::kObj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n",
     MeshErrc::kSyntax, 4, "'1/'"},
    {"ObjVertexTrailingJunk", Format::kObj, "v 0 0 0 junk\n", MeshErrc::kSyntax, 1, "'junk'"},
    {"ObjVertexFiveNumbers", Format::kObj, "v 0 0 0 1 1\n", MeshErrc::kSyntax, 1, "5 numbers"},
    {"ObjUnknownStatement", Format::kObj, "# ok\nv 0 0 0\nbogus 1 2\n", MeshErrc::kSyntax, 3,
     "'bogus'"},
    {"ObjBinaryGarbage", Format::kObj, std::string("\x7f\x45\x4c\x46\x02\x01", 6),
     MeshErrc::kSyntax, 1, "unknown statement"},
    {"ObjNoFaces", Format::kObj, "v 0 0 0\n", MeshErrc::kEmpty, 0, "without faces"},
    {"PlyNoMagic", Format::kPly, "plx\n", MeshErrc::kSyntax, 1, "'ply'"},
    {"PlyHeaderNeverEnds", Format::kPly, "ply\nformat ascii 1.0\nelement vertex 3\n",
     MeshErrc::kTruncated, 0, "header"},
    {"PlyUnknownEncoding", Format::kPly, "ply\nformat binary_middle_endian 1.0\nend_header\n",
     MeshErrc::kSyntax, 2, "binary_middle_endian"},
    {"PlyVersionTwo", Format::kPly, "ply\nformat ascii 2.0\nend_header\n", MeshErrc::kUnsupported,
     2, "2.0"},
    {"PlyUnknownType", Format::kPly,
     "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", MeshErrc::kSyntax, 4,
     "'quad'"},
    {"PlyFloatListCount", Format::kPly,
     "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
     MeshErrc::kSyntax, 4, "list count type"},
    {"PlyNegativeCount", Format::kPly, "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
     MeshErrc::kBadCount, 3, "'-3'"},
    {"PlyLyingVertexCount", Format::kPly, ply_binary_lying_count(), MeshErrc::kBadCount, 3,
     "4000000000 items"},
    {"PlyFaceListRunsPastEnd", Format::kPly, ply_binary_long_face_list(), MeshErrc::kTruncated, 0,
     "255 entries"},
    {"PlyBinaryNaN", Format::kPly, ply_binary_nan(), MeshErrc::kNonFinite, 0, "vertex 0"},
    {"PlyHugeFloatIndex", Format::kPly, ply_binary_float_index(3.0e38f), MeshErrc::kIndexOutOfRange,
     0, "vertex index 3e+38"},
    {"PlyNaNIndex", Format::kPly, ply_binary_float_index(std::numeric_limits<float>::quiet_NaN()),
     MeshErrc::kIndexOutOfRange, 0, "vertex index nan"},
    {"PlyMissingZ", Format::kPly,
     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 "
     "0\n",
     MeshErrc::kSyntax, 3, "x, y or z"},
    {"PlyIndexOutOfRange", Format::kPly, kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
     MeshErrc::kIndexOutOfRange, 13, "vertex 3"},
    // Faces before vertices: the index is checked at the end but still named by its line.
    {"PlyIndexOutOfRangeFacesFirst", Format::kPly,
     "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement "
     "vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n3 0 1 "
     "9\n0 0 0\n1 0 0\n0 1 0\n",
     MeshErrc::kIndexOutOfRange, 10, "vertex 9"},
    {"PlyNegativeIndex", Format::kPly, kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
     MeshErrc::kIndexOutOfRange, 13, "-1"},
    {"PlyFractionalIndex", Format::kPly, kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n",
     MeshErrc::kSyntax, 13, "'1.5'"},
    {"PlyAsciiTruncated", Format::kPly, kPlyHead + "0 0 0\n1 0 0\n", MeshErrc::kBadCount, 3,
     "element 'vertex'"},
    {"PlyAsciiEndsInFace", Format::kPly, kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1",
     MeshErrc::kTruncated, 13, "3 entries"},
    {"OffBadMagic", Format::kOff, "PFF\n3 1 0\n", MeshErrc::kSyntax, 1, "'PFF'"},
    {"OffBinary", Format::kOff, "OFF BINARY\n", MeshErrc::kUnsupported, 1, "binary"},
    {"OffLyingCounts", Format::kOff, "OFF\n99999999 99999999 0\n0 0 0\n", MeshErrc::kBadCount, 2,
     "cannot fit"},
    {"OffTruncatedVertices", Format::kOff,
     "OFF\n3 1 0\n0 0 0\n1 0 0\n# padding padding padding padding\n", MeshErrc::kTruncated, 0,
     "2 of 3 vertices"},
    {"OffIndexOutOfRange", Format::kOff, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
     MeshErrc::kIndexOutOfRange, 6, "index 7"},
    {"OffFaceWithTwoVertices", Format::kOff, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
     MeshErrc::kSyntax, 6, "2 vertices"},
    {"OffNaN", Format::kOff, "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", MeshErrc::kNonFinite,
     4, "'NaN'"},
};

class MalformedInput : public ::testing::TestWithParam<Bad> {};

TEST_P(MalformedInput, GivesTheExpectedErrorNamingWhereAndWhat) {
    const Bad& b = GetParam();
    auto r = parse_mesh(as_bytes(b.bytes), b.format, LengthUnit::kMillimetre, "bad.mesh");
    ASSERT_FALSE(r) << b.name << " parsed";
    const MeshError& e = r.error();
    EXPECT_EQ(e.code, b.kind) << e.message();
    if (b.line > 0) {
        EXPECT_EQ(e.line, b.line) << e.message();
    }
    EXPECT_EQ(e.where.rfind("bad.mesh", 0), 0u) << e.where;
    EXPECT_NE(e.message().find(b.mentions), std::string::npos) << e.message();
    EXPECT_EQ(e.message().rfind("bad.mesh", 0), 0u) << e.message();
}

std::string bad_name(const ::testing::TestParamInfo<Bad>& param_info) {
    return param_info.param.name;
}

INSTANTIATE_TEST_SUITE_P(EveryKind, MalformedInput, ::testing::ValuesIn(kBad), bad_name);

// Issue 9, item 16: a bad index in a binary PLY names the byte where the index is (it said
// "byte 0"), and the OBJ forms that are legal still parse.
TEST(MalformedInputPosition, ABinaryPlyIndexErrorNamesTheIndexByte) {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty "
        "float y\nproperty float z\nelement face 1\nproperty list uchar int "
        "vertex_indices\nend_header\n";
    const std::size_t data = s.size();
    s += std::string(36, '\0');
    s.push_back(3);
    const std::int32_t idx[3] = {0, 1, 7};
    s.append(reinterpret_cast<const char*>(idx), sizeof idx);  // little-endian host (x86-64)
    auto r = parse_mesh(as_bytes(s), Format::kPly, LengthUnit::kMillimetre, "bad.ply");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, MeshErrc::kIndexOutOfRange);
    EXPECT_EQ(r.error().byte_offset, data + 36 + 1 + 8) << r.error().message();
    EXPECT_NE(r.error().message().find("byte " + std::to_string(data + 45)), std::string::npos)
        << r.error().message();
}

TEST(MalformedInputPosition, LegalObjCornerAndVertexFormsStillParse) {
    const std::string ok =
        "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 # comment\nv 0 0 1 1 0 0 0\n"
        "f 1/1/1 2//2 3/3\nf 1 2 4\nf -4 -2 -1\nf 2 3 4\n";
    auto r = parse_mesh(as_bytes(ok), Format::kObj, LengthUnit::kMillimetre, "ok.obj");
    ASSERT_TRUE(r) << r.error().message();
    EXPECT_EQ(r->indexed.triangles.size(), 4u);
}

TEST(MalformedInputTruncation, EveryPrefixOfEveryFormatFailsCleanlyOrParses) {
    const TriMesh box = make_box({0, 0, 0}, {1, 2, 3});
    for (Format f : {Format::kStl, Format::kObj, Format::kPly, Format::kOff}) {
        for (Encoding enc :
             {Encoding::kAscii, Encoding::kBinaryLittleEndian, Encoding::kBinaryBigEndian}) {
            const std::string full = serialize_mesh(box, f, LengthUnit::kMetre, enc);
            for (std::size_t n = 0; n < full.size(); ++n) {
                auto r = parse_indexed(as_bytes(std::string_view(full).substr(0, n)), f,
                                       LengthUnit::kMetre);
                if (r) {
                    EXPECT_LE(r->triangles.size(), 12u);  // text cut at a line end may parse
                }
            }
        }
    }
}

TEST(MalformedInputCorruption, RandomByteFlipsFailCleanlyOrKeepEveryTriangle) {
    const TriMesh tube = make_hollow_tube(0.03, 0.006, 0.003, 8, 2);
    std::uint64_t state = 12345;  // deterministic LCG
    auto next = [&] {
        return (state = state * 6364136223846793005ull + 1442695040888963407ull) >> 33;
    };
    const char kInteresting[] = {'0', '9', '-', '.', 'e', ' ', '\n', '/', '\0', '\xff', 'n', '#'};
    for (Format f : {Format::kStl, Format::kObj, Format::kPly, Format::kOff}) {
        for (Encoding enc :
             {Encoding::kAscii, Encoding::kBinaryLittleEndian, Encoding::kBinaryBigEndian}) {
            const std::string clean = serialize_mesh(tube, f, LengthUnit::kMillimetre, enc);
            for (int trial = 0; trial < 300; ++trial) {
                std::string bytes = clean;
                for (int k = 0; k < 3; ++k) {
                    bytes[next() % bytes.size()] = kInteresting[next() % sizeof kInteresting];
                }
                auto r = parse_mesh(as_bytes(bytes), f, LengthUnit::kMillimetre, "corrupt");
                if (r) {
                    EXPECT_EQ(r->mesh.n_faces(), r->indexed.triangles.size());
                } else {
                    EXPECT_FALSE(r.error().what.empty());
                }
            }
        }
    }
}

}  // namespace
}  // namespace kerf::mesh
