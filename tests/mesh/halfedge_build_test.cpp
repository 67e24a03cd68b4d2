// build_tri_mesh() builds the half-edge connectivity on flat arrays instead of calling OpenMesh's
// add_face() per triangle; it must give exactly what add_face() gives (every handle, so every tie
// a cut breaks by handle and every mesh hash). The reference here is the add_face() loop that
// build_tri_mesh() used before; the two are compared element by element on the shared bone
// meshes (also with their triangles shuffled and some flipped, which makes add_face relink
// patches, and only part of them, which leaves boundary links as relinking set them), a generated
// foot, and random triangle soups over a few vertices (complex vertices and
// edges, refused faces, detached copies).
#include <gtest/gtest.h>

#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "display/mesh/foot_generator.hpp"
#include "display/mesh/indexed_mesh.hpp"
#include "display/mesh/mesh_io.hpp"

namespace kerf::mesh {
namespace {

/// The mesh as OpenMesh's add_face() builds it: build_tri_mesh() before its own builder.
BuiltMesh reference_build(const IndexedMesh& in) {
    BuiltMesh out{make_mesh(), 0};
    TriMesh& m = out.mesh;
    m.reserve(in.positions_m.size(), in.triangles.size() * 3 / 2, in.triangles.size());
    const bool has_materials = in.materials.size() == in.positions_m.size();
    const auto add = [&m](const Point& p, Material material) {
        const VertexHandle v = m.add_vertex(p);
        m.set_texcoord2D(v, TriMesh::TexCoord2D(0.0f, 0.0f));
        m.set_color(v, TriMesh::Color(1.0f, 1.0f, 1.0f));
        m.data(v).set_material(material);
        return v;
    };
    for (std::size_t i = 0; i < in.positions_m.size(); ++i)
        add(in.positions_m[i], has_materials ? in.materials[i] : Material::kCortical);
    const bool was_enabled = omerr().is_enabled();
    omerr().disable();
    for (const Triangle& t : in.triangles) {
        const VertexHandle a(static_cast<int>(t[0])), b(static_cast<int>(t[1])),
            c(static_cast<int>(t[2]));
        if (a != b && b != c && a != c && m.add_face(a, b, c).is_valid()) continue;
        ++out.detached_triangles;
        VertexHandle copies[3];
        for (std::size_t k = 0; k < 3; ++k) {
            const VertexHandle src(static_cast<int>(t[k]));
            const Point p = m.point(src);
            copies[k] = add(p, m.data(src).material());
        }
        m.add_face(copies[0], copies[1], copies[2]);
    }
    if (was_enabled) omerr().enable();
    m.update_normals();
    return out;
}

template <class V>
bool same_bits(const V& a, const V& b) {
    for (std::size_t k = 0; k < V::size_; ++k) {
        if (std::bit_cast<std::uint64_t>(static_cast<double>(a[k])) !=
            std::bit_cast<std::uint64_t>(static_cast<double>(b[k])))
            return false;
    }
    return true;
}

/// Every element of `got` equals `want`'s: counts, every half-edge's links, every vertex's and
/// face's half-edge, points, attributes and normals bit for bit.
void expect_identical(const BuiltMesh& got, const BuiltMesh& want, const std::string& what) {
    SCOPED_TRACE(what);
    const TriMesh &g = got.mesh, &w = want.mesh;
    ASSERT_EQ(got.detached_triangles, want.detached_triangles);
    ASSERT_EQ(g.n_vertices(), w.n_vertices());
    ASSERT_EQ(g.n_edges(), w.n_edges());
    ASSERT_EQ(g.n_faces(), w.n_faces());
    for (std::size_t i = 0; i < g.n_halfedges(); ++i) {
        const HalfedgeHandle h(static_cast<int>(i));
        ASSERT_EQ(g.to_vertex_handle(h), w.to_vertex_handle(h)) << "halfedge " << i;
        ASSERT_EQ(g.face_handle(h), w.face_handle(h)) << "halfedge " << i;
        ASSERT_EQ(g.next_halfedge_handle(h), w.next_halfedge_handle(h)) << "halfedge " << i;
        ASSERT_EQ(g.prev_halfedge_handle(h), w.prev_halfedge_handle(h)) << "halfedge " << i;
    }
    for (std::size_t i = 0; i < g.n_vertices(); ++i) {
        const VertexHandle v(static_cast<int>(i));
        ASSERT_EQ(g.halfedge_handle(v), w.halfedge_handle(v)) << "vertex " << i;
        ASSERT_TRUE(same_bits(g.point(v), w.point(v))) << "vertex " << i;
        ASSERT_TRUE(same_bits(g.normal(v), w.normal(v))) << "vertex " << i;
        ASSERT_TRUE(same_bits(g.texcoord2D(v), w.texcoord2D(v))) << "vertex " << i;
        ASSERT_TRUE(same_bits(g.color(v), w.color(v))) << "vertex " << i;
        ASSERT_EQ(g.data(v).material(), w.data(v).material()) << "vertex " << i;
    }
    for (std::size_t i = 0; i < g.n_faces(); ++i) {
        const FaceHandle f(static_cast<int>(i));
        ASSERT_EQ(g.halfedge_handle(f), w.halfedge_handle(f)) << "face " << i;
        ASSERT_TRUE(same_bits(g.normal(f), w.normal(f))) << "face " << i;
    }
}

void expect_builds_as_add_face(const IndexedMesh& in, const std::string& what) {
    expect_identical(build_tri_mesh(in), reference_build(in), what);
}

IndexedMesh load_indexed(const std::filesystem::path& file) {
    const std::string bytes = [&] {
        std::ifstream f(file, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    auto parsed = parse_indexed({reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()},
                                Format::kStl, LengthUnit::kMillimetre, file.string());
    EXPECT_TRUE(parsed) << file;
    return parsed ? std::move(*parsed) : IndexedMesh{};
}

TEST(HalfedgeBuild, SharedBoneMeshesAsGivenShuffledAndFlipped) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(KERF_SHARED_MESHES))
        if (e.path().extension() == ".stl") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 8u);
    std::mt19937 rng(11);
    for (const auto& file : files) {
        IndexedMesh in = load_indexed(file);
        ASSERT_FALSE(in.triangles.empty()) << file;
        expect_builds_as_add_face(in, file.filename().string());
        // Triangles in random order, one in ten flipped: fans grow from several places at once
        // (patch relinking) and flipped neighbours meet as complex edges.
        std::shuffle(in.triangles.begin(), in.triangles.end(), rng);
        for (std::size_t i = 0; i < in.triangles.size(); i += 10)
            std::swap(in.triangles[i][1], in.triangles[i][2]);
        expect_builds_as_add_face(in, file.filename().string() + " shuffled, flipped");
        // Part of them: an open surface of many patches, whose boundary links (set by relinking,
        // overwritten once the surface closes) stay as add_face left them.
        in.triangles.resize(in.triangles.size() * 2 / 5);
        expect_builds_as_add_face(in, file.filename().string() + " shuffled, 40 %");
    }
}

TEST(HalfedgeBuild, GeneratedFootWithMaterials) {
    FootParams params;
    params.target_triangles = 60'000;
    auto foot = generate_foot(params);
    ASSERT_TRUE(foot) << foot.error();
    const IndexedMesh in = to_indexed(foot->mesh);
    ASSERT_EQ(in.materials.size(), in.positions_m.size());
    expect_builds_as_add_face(in, "foot");
}

TEST(HalfedgeBuild, RandomSoupsOfFewVertices) {
    // Few vertices, many triangles: non-manifold edges, complex vertices, repeated indices,
    // opposite windings; whatever add_face refuses is detached the same way.
    std::mt19937 rng(3);
    std::size_t refused = 0;
    for (int round = 0; round < 3000; ++round) {
        IndexedMesh in;
        const auto n_vertices = static_cast<std::uint32_t>(3 + round % 10);
        for (std::uint32_t i = 0; i < n_vertices; ++i)
            in.positions_m.push_back(Point(std::cos(i), std::sin(i * 1.7), 0.1 * i));
        std::uniform_int_distribution<std::uint32_t> pick(0, n_vertices - 1);
        const int n_triangles = 1 + round % 24;
        for (int t = 0; t < n_triangles; ++t)
            in.triangles.push_back({pick(rng), pick(rng), pick(rng)});
        const BuiltMesh want = reference_build(in);
        refused += want.detached_triangles;
        expect_identical(build_tri_mesh(in), want, "soup " + std::to_string(round));
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(refused, 1000u);  // the refusal paths were exercised
}

TEST(HalfedgeBuild, EmptyAndIsolatedVertices) {
    expect_builds_as_add_face(IndexedMesh{}, "empty");
    IndexedMesh in;
    for (int i = 0; i < 5; ++i) in.positions_m.push_back(Point(i, 0, 0));
    expect_builds_as_add_face(in, "no triangles");
    in.triangles.push_back({0, 2, 4});
    expect_builds_as_add_face(in, "one triangle, two isolated vertices");
}

}  // namespace
}  // namespace kerf::mesh
