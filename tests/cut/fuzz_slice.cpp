// libFuzzer target for the cutter: random meshes, planes, seeds and modes in; every invariant
// checked after every operation.
//
//   byte 0      shape: sphere, torus, hollow tube (cortex + canal), box, or two spheres side by
//   side byte 1      resolution then up to four operations of 16 bytes each:
//     mode (full uniplanar, localised uniplanar, biplanar slab), plane point (3 x int16 scaled to
//     the mesh box, optionally snapped onto a vertex so the plane runs through a vertex ring),
//     normal (3 x int8; sometimes snapped to an axis so it lies along edges or caps), a vertex
//     index for the seed, the kerf width.
//
// After an accepted cut: every piece is a closed, consistently oriented 2-manifold with no
// non-finite or near-zero-area triangle, and a uniplanar cut conserves the signed volume (relative
// 1e-9, plus what the cut points merged into a neighbour within the tolerance may sweep:
// volume_change_bound); a slab never adds more than that bound. After a refusal: the mesh is
// bit-identical (mesh_hash). kInternalError is always a failure.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "display/cut/cross_section.hpp"
#include "display/cut/cut_context.hpp"
#include "display/cut/mesh_hash.hpp"
#include "display/cut/plane.hpp"
#include "display/cut/slice_by_plane.hpp"
#include "display/cut/subtract_slab.hpp"
#include "display/mesh/shapes.hpp"
#include "tests/cut/mesh_invariants.hpp"
#include "tests/cut/test_shapes.hpp"

namespace {

using kerf::cut::CutStatus;
using kerf::cut::Vec3;
using kerf::mesh::TriMesh;

struct Reader {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t at = 0;
    std::uint8_t byte() { return at < size ? data[at++] : 0; }
    std::int16_t i16() {
        const auto lo = byte();
        const auto hi = byte();
        return static_cast<std::int16_t>(static_cast<std::uint16_t>(lo | (hi << 8)));
    }
    bool more() const { return at < size; }
};

[[noreturn]] void fail(const std::string& why) {
    std::fprintf(stderr, "fuzz_slice: invariant broken: %s\n", why.c_str());
    std::abort();
}

TriMesh make_shape(std::uint8_t kind, std::uint8_t res) {
    const int r = 4 + res % 24;  // small meshes: each run stays in the milliseconds
    switch (kind % 5) {
        case 0:
            return kerf::mesh::make_uv_sphere(0.01, static_cast<std::size_t>(r) * 40);
        case 1:
            return kerf::mesh::make_torus(0.03, 0.01, r + 4, r / 2 + 3);
        case 2:
            return kerf::mesh::make_hollow_tube(0.05, 0.01, 0.006, r + 4, r / 3 + 1);
        case 3:
            return kerf::mesh::make_box(TriMesh::Point(0, 0, 0), TriMesh::Point(0.02, 0.01, 0.03),
                                        1 + r % 4);
        default: {
            TriMesh m = kerf::mesh::make_uv_sphere(0.01, static_cast<std::size_t>(r) * 30);
            kerf::cut::testing::append(
                m, kerf::mesh::make_uv_sphere(0.01, static_cast<std::size_t>(r) * 30,
                                              TriMesh::Point(0.025, 0.0, 0.0)));
            return m;
        }
    }
}

void check_mesh(const TriMesh& mesh, const char* after) {
    const auto report = kerf::cut::testing::check_closed_2_manifold(mesh);
    if (!report.ok)
        fail(std::string("after ") + after + ": " + std::to_string(report.failures) +
             " failure(s):\n" + report.failures_log);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // KERF_FUZZ_VERBOSE=1 prints each operation (to turn a crash input into a unit test).
    static const bool verbose = std::getenv("KERF_FUZZ_VERBOSE") != nullptr;
    Reader in{data, size};
    TriMesh mesh = make_shape(in.byte(), in.byte());
    kerf::cut::CutContext ctx(mesh);
    kerf::cut::CrossSection cs;
    kerf::cut::SlabCut slab;

    TriMesh::Point lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
    for (const auto v : mesh.vertices()) {
        lo.minimize(mesh.point(v));
        hi.maximize(mesh.point(v));
    }
    const std::size_t n_vertices = mesh.n_vertices();

    for (int op = 0; op < 4 && in.more(); ++op) {
        const std::uint8_t mode = in.byte();
        Vec3 point;
        for (int k = 0; k < 3; ++k)
            point[k] = lo[k] + (hi[k] - lo[k]) * (0.5 + 0.6 * in.i16() / 32768.0);
        Vec3 normal;
        for (int k = 0; k < 3; ++k) normal[k] = static_cast<std::int8_t>(in.byte());
        const std::uint8_t snap = in.byte();
        const std::uint16_t vertex_pick = static_cast<std::uint16_t>(in.i16());
        const std::uint8_t kerf_byte = in.byte();
        in.byte();  // reserved (keeps operations 16 bytes apart)
        in.byte();
        const auto seed_vertex =
            kerf::mesh::VertexHandle(static_cast<int>(vertex_pick % n_vertices));
        if (snap & 1) point = mesh.point(seed_vertex);  // the plane runs through a vertex
        if (snap & 2) normal = Vec3(0, 0, 1);           // along rings, edges, earlier caps
        if (snap & 4) normal = Vec3(1, 0, 0);

        const auto plane = kerf::cut::Plane::make(point, normal);
        if (!plane) continue;  // zero normal: refused by make(), nothing to cut

        if (verbose)
            std::fprintf(stderr,
                         "op %d: mode %d, shape %zu vertices, point (%.17g, %.17g, %.17g), normal "
                         "(%.17g, %.17g, %.17g), seed vertex %d, kerf byte %d\n",
                         op, mode % 3, n_vertices, point[0], point[1], point[2], normal[0],
                         normal[1], normal[2], seed_vertex.idx(), kerf_byte);
        const double volume_before = kerf::cut::testing::signed_volume(mesh);
        const double area_before = kerf::cut::testing::surface_area(mesh);
        const std::uint64_t hash_before = kerf::cut::mesh_hash(mesh);
        const kerf::cut::Seed seed{mesh.point(seed_vertex), kerf::mesh::FaceHandle(), -1.0};
        kerf::cut::CutResult r;
        const char* what = "?";
        switch (mode % 3) {
            case 0:
                what = "full-plane slice";
                r = kerf::cut::slice_by_plane(ctx, *plane, cs);
                break;
            case 1:
                what = "localised slice";
                r = kerf::cut::slice_by_plane(ctx, *plane, seed, cs);
                break;
            default:
                what = "biplanar slab";
                r = kerf::cut::subtract_slab(ctx, *plane, 1e-4 * (1 + kerf_byte % 40), seed, slab);
                break;
        }
        if (verbose)
            std::fprintf(stderr, "  -> %s, %u point(s) merged\n",
                         std::string(to_string(r.status)).c_str(), r.stats.vertices_merged);
        if (r.status == CutStatus::kInternalError) fail(std::string(what) + ": internal error");
        if (!r.ok()) {
            if (kerf::cut::mesh_hash(mesh) != hash_before)
                fail(std::string(what) + " refused (" + std::string(to_string(r.status)) +
                     ") but changed the mesh");
            continue;
        }
        check_mesh(mesh, what);
        const double volume_after = kerf::cut::testing::signed_volume(mesh);
        if (mode % 3 != 2) {
            const double bound = kerf::cut::testing::volume_change_bound(
                volume_before, r.stats.vertices_merged, ctx.tolerance_m(), area_before);
            if (std::abs(volume_after - volume_before) > bound) {
                char buf[200];
                std::snprintf(buf, sizeof buf,
                              ": volume %.17g -> %.17g m^3 (change %.3g, bound %.3g, %u merged)",
                              volume_before, volume_after, volume_after - volume_before, bound,
                              r.stats.vertices_merged);
                fail(std::string(what) + buf);
            }
        } else if (volume_after - volume_before >
                   kerf::cut::testing::volume_change_bound(volume_before, r.stats.vertices_merged,
                                                           ctx.tolerance_m(), area_before)) {
            fail("biplanar slab added volume");
        }
    }
    return 0;
}
