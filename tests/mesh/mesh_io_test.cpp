// Loaders and writers: round trips through every format and encoding, unit conversion,
// welding, STL binary/ASCII detection, and what becomes of non-manifold input.
#include "display/mesh/mesh_io.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "display/mesh/shapes.hpp"
#include "display/mesh/validate.hpp"
#include "tests/mesh/mesh_test_support.hpp"

namespace kerf::mesh {
namespace {

struct Case {
    Format format;
    Encoding encoding;
    bool exact;  // doubles survive; STL stores float32
};

class RoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(RoundTrip, TorusSurvivesWithSameTopologyVolumeAndPositions) {
    const Case c = GetParam();
    const TriMesh torus = make_torus(0.03, 0.01, 24, 12);
    const std::string data = serialize_mesh(torus, c.format, LengthUnit::kMillimetre, c.encoding);
    auto back = parse_mesh(as_bytes(data), c.format, LengthUnit::kMillimetre, "roundtrip");
    ASSERT_TRUE(back) << back.error().message();
    const ValidationReport a = validate(torus);
    const ValidationReport b = validate(back->indexed);
    EXPECT_EQ(b.triangles, a.triangles);
    EXPECT_EQ(b.vertices, a.vertices);
    EXPECT_TRUE(b.closed);
    EXPECT_TRUE(b.oriented);
    EXPECT_EQ(back->detached_triangles, 0u);
    EXPECT_NEAR(b.volume_m3, a.volume_m3, a.volume_m3 * (c.exact ? 1e-12 : 1e-6));
    const IndexedMesh original = to_indexed(torus);
    ASSERT_EQ(back->indexed.triangles.size(), original.triangles.size());
    for (std::size_t i = 0; i < original.triangles.size(); ++i) {  // same corners, same winding
        for (std::size_t k = 0; k < 3; ++k) {
            const Point p = back->indexed.positions_m[back->indexed.triangles[i][k]];
            const double d = (p - original.positions_m[original.triangles[i][k]]).norm();
            EXPECT_LE(d, c.exact ? 1e-16 : 1e-8) << "triangle " << i;  // mm -> m: 1 ulp
        }
    }
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, RoundTrip,
                         ::testing::Values(Case{Format::kStl, Encoding::kBinaryLittleEndian, false},
                                           Case{Format::kStl, Encoding::kAscii, false},
                                           Case{Format::kObj, Encoding::kAscii, true},
                                           Case{Format::kPly, Encoding::kAscii, true},
                                           Case{Format::kPly, Encoding::kBinaryLittleEndian, true},
                                           Case{Format::kPly, Encoding::kBinaryBigEndian, true},
                                           Case{Format::kOff, Encoding::kAscii, true}),
                         [](const auto& param_info) {  // e.g. ply_binary_little_endian
                             std::string name = std::string(to_string(param_info.param.format)) +
                                                "_" +
                                                std::string(to_string(param_info.param.encoding));
                             for (char& c : name) {
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             }
                             return name;
                         });

TEST(MeshIo, PlyCarriesVertexMaterialsThroughARoundTrip) {
    const TriMesh tube = make_hollow_tube(0.04, 0.006, 0.003, 16, 4);
    const std::string data = serialize_mesh(tube, Format::kPly, LengthUnit::kMetre);
    auto back = parse_mesh(as_bytes(data), Format::kPly, LengthUnit::kMetre);
    ASSERT_TRUE(back) << back.error().message();
    std::size_t cancellous = 0;
    for (const VertexHandle v : back->mesh.vertices()) {
        cancellous += back->mesh.data(v).material() == Material::kCancellous ? 1 : 0;
    }
    EXPECT_EQ(cancellous, 16u * 5u);
}

// load_mesh_owned builds the mesh where it stays (no copy: OpenMesh meshes have no move
// constructor); it reads the same mesh as load_mesh and refuses what load_mesh refuses.
TEST(MeshIo, LoadMeshOwnedReadsWhatLoadMeshReads) {
    const auto dir =
        std::filesystem::temp_directory_path() /
        ("kerf-owned-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::create_directories(dir);
    const auto file = dir / "tube.ply";
    const TriMesh tube = make_hollow_tube(0.04, 0.006, 0.003, 16, 4);
    ASSERT_TRUE(save_mesh(tube, file, LengthUnit::kMillimetre));
    auto value = load_mesh(file, LengthUnit::kMillimetre);
    auto owned = load_mesh_owned(file, LengthUnit::kMillimetre);
    ASSERT_TRUE(value) << value.error().message();
    ASSERT_TRUE(owned) << owned.error().message();
    ASSERT_NE(owned->get(), nullptr);
    const TriMesh& o = **owned;
    ASSERT_EQ(o.n_vertices(), value->n_vertices());
    ASSERT_EQ(o.n_faces(), value->n_faces());
    for (const VertexHandle v : o.vertices()) {
        EXPECT_EQ(o.point(v), value->point(v));
        EXPECT_EQ(o.normal(v), value->normal(v));
        EXPECT_EQ(o.data(v).material(), value->data(v).material());
    }
    auto missing = load_mesh_owned(dir / "absent.stl", LengthUnit::kMillimetre);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message().find("absent.stl"), std::string::npos);
    auto unknown = load_mesh_owned(dir / "tube.xyz", LengthUnit::kMillimetre);
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().message(),
              load_mesh(dir / "tube.xyz", LengthUnit::kMillimetre).error().message());
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

// A binary STL file is parsed as it is read, a piece at a time (no buffer of its size): it must
// give exactly what parsing its bytes in memory gives — the same welded mesh, and for a bad file
// the same error, also where the bad facet lies pieces into the file, or the size is not the
// header's (those files are read whole).
TEST(MeshIo, ABinaryStlFileReadInPiecesGivesWhatItsBytesGive) {
    const auto dir =
        std::filesystem::temp_directory_path() /
        ("kerf-pieces-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::create_directories(dir);
    const TriMesh torus = make_torus(0.03, 0.01, 240, 120);  // 57,600 facets: three pieces
    const std::string good = serialize_mesh(torus, Format::kStl, LengthUnit::kMillimetre);
    const auto write = [&](const std::string& name, const std::string& bytes) {
        const auto path = dir / name;
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    };
    const auto expect_same = [&](const std::string& name, const std::string& bytes) {
        SCOPED_TRACE(name);
        const auto path = write(name, bytes);
        auto from_file = load_mesh_file(path, LengthUnit::kMillimetre);
        auto from_bytes =
            parse_indexed(as_bytes(bytes), Format::kStl, LengthUnit::kMillimetre, path.string());
        ASSERT_EQ(bool(from_file), bool(from_bytes));
        if (!from_bytes) {
            EXPECT_EQ(from_file.error().message(), from_bytes.error().message());
            EXPECT_EQ(load_mesh_owned(path, LengthUnit::kMillimetre).error().message(),
                      from_bytes.error().message());
            return;
        }
        EXPECT_EQ(from_file->indexed.triangles, from_bytes->triangles);
        ASSERT_EQ(from_file->indexed.positions_m.size(), from_bytes->positions_m.size());
        for (std::size_t v = 0; v < from_bytes->positions_m.size(); ++v)
            ASSERT_EQ(from_file->indexed.positions_m[v], from_bytes->positions_m[v]) << v;
        auto owned = load_mesh_owned(path, LengthUnit::kMillimetre);
        ASSERT_TRUE(owned) << owned.error().message();
        EXPECT_EQ((*owned)->n_faces(), from_bytes->triangles.size());
        EXPECT_EQ((*owned)->n_vertices(), from_bytes->positions_m.size());
    };
    expect_same("good.stl", good);
    std::string bad = good;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bad.data() + 84 + 45'000 * 50 + 12 + 24 + 8, &nan, 4);  // facet 45,000, corner 3
    expect_same("nan.stl", bad);
    expect_same("trailing.stl", good + "x");
    expect_same("truncated.stl", good.substr(0, good.size() - 7));
    expect_same("empty_count.stl", good.substr(0, 80) + std::string(4, '\0'));
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

TEST(MeshIo, UnitsScaleEveryCoordinateToMetres) {
    const std::string obj = "v 0 0 0\nv 10 0 0\nv 0 20 0\nf 1 2 3\n";
    for (const auto& [units, metres] :
         {std::pair{LengthUnit::kMillimetre, 0.01}, std::pair{LengthUnit::kCentimetre, 0.1},
          std::pair{LengthUnit::kInch, 0.254}, std::pair{LengthUnit::kMetre, 10.0}}) {
        auto m = parse_indexed(as_bytes(obj), Format::kObj, units);
        ASSERT_TRUE(m) << m.error().message();
        EXPECT_DOUBLE_EQ(m->positions_m[1][0], metres) << to_string(units);
        EXPECT_DOUBLE_EQ(m->positions_m[2][1], 2.0 * metres) << to_string(units);
    }
}

TEST(MeshIo, BinaryStlThatBeginsWithSolidIsReadAsBinary) {
    std::string data =
        serialize_mesh(make_box({0, 0, 0}, {1, 1, 1}), Format::kStl, LengthUnit::kMetre);
    std::memcpy(data.data(), "solid exported-by-a-cad-tool", 28);
    auto m = parse_indexed(as_bytes(data), Format::kStl, LengthUnit::kMetre);
    ASSERT_TRUE(m) << m.error().message();
    EXPECT_EQ(m->triangles.size(), 12u);
    EXPECT_EQ(m->positions_m.size(), 8u);
}

TEST(MeshIo, StoredStlNormalsAreIgnoredEvenWhenGarbage) {
    std::string data =
        serialize_mesh(make_box({0, 0, 0}, {1, 1, 1}), Format::kStl, LengthUnit::kMetre);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t f = 0; f < 12; ++f) std::memcpy(data.data() + 84 + 50 * f, &nan, 4);
    auto m = parse_mesh(as_bytes(data), Format::kStl, LengthUnit::kMetre);
    ASSERT_TRUE(m) << m.error().message();
    for (const FaceHandle f : m->mesh.faces()) EXPECT_NEAR(m->mesh.normal(f).norm(), 1.0, 1e-12);
}

TEST(MeshIo, VerticesWeldOnlyWhenBitIdenticalWithNegativeZeroAsZero) {
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -0 0 0\nv 1.0000001 0 0\nv 0 1 0\n"
        "f 1 2 3\nf 4 5 6\n";
    auto m = parse_indexed(as_bytes(obj), Format::kObj, LengthUnit::kMetre);
    ASSERT_TRUE(m) << m.error().message();
    EXPECT_EQ(m->positions_m.size(), 4u);  // v4 = v1, v6 = v3, v5 is new
    EXPECT_EQ(m->triangles[1], (Triangle{0, 3, 2}));
}

TEST(MeshIo, PolygonsBecomeTriangleFans) {
    const std::string off = "OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n5 0 1 2 3 4\n";
    auto m = parse_indexed(as_bytes(off), Format::kOff, LengthUnit::kMetre);
    ASSERT_TRUE(m) << m.error().message();
    ASSERT_EQ(m->triangles.size(), 3u);
    EXPECT_EQ(m->triangles[2], (Triangle{0, 3, 4}));
}

TEST(MeshIo, NonManifoldEdgeIsKeptDetachedAndCountedNotDropped) {
    // Three triangles on one edge (a "book" of three pages).
    const std::string obj =
        "v 0 0 0\nv 0 0 1\nv 1 0 0\nv 0 1 0\nv -1 0 0\n"
        "f 1 2 3\nf 2 1 4\nf 1 2 5\n";
    auto m = parse_mesh(as_bytes(obj), Format::kObj, LengthUnit::kMetre);
    ASSERT_TRUE(m) << m.error().message();
    EXPECT_EQ(m->mesh.n_faces(), 3u);
    EXPECT_EQ(m->detached_triangles, 1u);
    const ValidationReport r = validate(m->indexed);
    EXPECT_EQ(r.non_manifold_edges, 1u);
    EXPECT_EQ(r.non_manifold_vertices, 2u);
    EXPECT_FALSE(r.closed);
    EXPECT_FALSE(r.oriented);
}

TEST(MeshIo, RepeatedIndexTriangleIsDegenerateAndDetached) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 2\n";
    auto m = parse_mesh(as_bytes(obj), Format::kObj, LengthUnit::kMetre);
    ASSERT_TRUE(m) << m.error().message();
    EXPECT_EQ(m->mesh.n_faces(), 2u);
    EXPECT_EQ(m->detached_triangles, 1u);
    EXPECT_EQ(validate(m->indexed).degenerate_triangles, 1u);
}

TEST(MeshIo, SaveAndLoadThroughTheFileSystem) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("kerf_mesh_io_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const TriMesh sphere = make_uv_sphere(0.01, 800);
    for (const char* name : {"s.stl", "s.obj", "s.ply", "s.off", "S.STL"}) {
        const auto path = dir / name;
        auto saved = save_mesh(sphere, path, LengthUnit::kMillimetre);
        ASSERT_TRUE(saved) << saved.error().message();
        auto loaded = load_mesh(path, LengthUnit::kMillimetre);
        ASSERT_TRUE(loaded) << loaded.error().message();
        EXPECT_EQ(loaded->n_faces(), sphere.n_faces()) << name;
    }
    std::filesystem::remove_all(dir);
}

TEST(MeshIo, FileErrorsNameThePathAndTheReason) {
    auto missing = load_mesh("/nonexistent/dir/bone.stl", LengthUnit::kMillimetre);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, MeshErrc::kIo);
    EXPECT_EQ(missing.error().message(), "/nonexistent/dir/bone.stl: no such file (io)");
    auto directory =
        load_mesh_file(std::filesystem::temp_directory_path() / ".", LengthUnit::kMetre);
    ASSERT_FALSE(directory);
    auto unknown = load_mesh("bone.vtk", LengthUnit::kMillimetre);
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().code, MeshErrc::kUnknownFormat);
    auto unwritable =
        save_mesh(make_box({0, 0, 0}, {1, 1, 1}), "/nonexistent/dir/x.stl", LengthUnit::kMetre);
    ASSERT_FALSE(unwritable);
    EXPECT_EQ(unwritable.error().code, MeshErrc::kIo);
    EXPECT_NE(unwritable.error().message().find("/nonexistent/dir/x.stl"), std::string::npos);
}

}  // namespace
}  // namespace kerf::mesh

namespace kerf::mesh {
namespace {

TEST(MeshIo, EveryFuzzSeedParsesWithEveryTriangleKept) {
    const std::filesystem::path dir = std::filesystem::path(KERF_SOURCE_DIR) / "tests/mesh/corpus";
    constexpr Format kFormats[] = {Format::kStl, Format::kObj, Format::kPly, Format::kOff};
    std::size_t seen = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        std::ifstream in(entry.path(), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
        ASSERT_FALSE(bytes.empty());
        const Format f = kFormats[static_cast<unsigned char>(bytes[0]) % 4];
        auto m = parse_mesh(as_bytes(std::string_view(bytes).substr(1)), f, LengthUnit::kMillimetre,
                            entry.path().filename().string());
        ASSERT_TRUE(m) << m.error().message();
        EXPECT_EQ(m->mesh.n_faces(), m->indexed.triangles.size()) << entry.path();
        ++seen;
    }
    EXPECT_GE(seen, 8u);
}

}  // namespace
}  // namespace kerf::mesh
