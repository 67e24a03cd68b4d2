// libFuzzer target for the cap triangulator: random loops in, every invariant checked out.
//
// Byte 0 picks the mode:
//   0: a structured valid region (star outer loop, holes, islands) seeded from the other bytes;
//   1: raw loops with small integer coordinates (exact predicates: any accepted input must
//      satisfy every invariant exactly, any other must be refused, never crash or hang);
//   2: raw loops of arbitrary doubles (NaN, huge, tiny): must not crash or hang, indices in range.
// Every input also goes to triangulate_strip (the annulus path with every point kept).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>

#include "display/cut/triangulate.hpp"
#include "tests/cut/triangulation_checks.hpp"

namespace {

using kerf::cut::Point2;
using kerf::cut::testing::Loops;

struct Reader {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t at = 0;
    bool take(void* out, std::size_t n) {
        if (at + n > size) return false;
        std::memcpy(out, data + at, n);
        at += n;
        return true;
    }
};

Loops raw_loops(Reader& r, bool doubles) {
    Loops loops;
    std::uint8_t nloops = 0;
    if (!r.take(&nloops, 1)) return loops;
    for (int l = 0; l < nloops % 8 + 1; ++l) {
        std::uint8_t npts = 0;
        if (!r.take(&npts, 1)) break;
        std::vector<Point2> loop;
        for (int k = 0; k < npts % 64; ++k) {
            if (doubles) {
                double xy[2];
                if (!r.take(xy, sizeof xy)) break;
                loop.emplace_back(xy[0], xy[1]);
            } else {
                std::int8_t xy[2];
                if (!r.take(xy, sizeof xy)) break;
                loop.emplace_back(xy[0], xy[1]);
            }
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

void fail(const std::string& why) {
    std::fprintf(stderr, "fuzz_triangulate: invariant broken: %s\n", why.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    Reader r{data + 1, size - 1};
    const int mode = data[0] % 3;
    Loops loops;
    if (mode == 0) {
        std::uint64_t seed = 0;
        r.take(&seed, std::min<std::size_t>(8, size - 1));
        std::mt19937_64 rng(seed);
        loops = kerf::cut::testing::random_region(rng, 6 + static_cast<int>(seed % 120));
    } else {
        loops = raw_loops(r, mode == 2);
    }
    kerf::cut::Triangulator t;
    std::vector<kerf::cut::Triangle> tris;
    const auto status = t.triangulate(kerf::cut::testing::spans_of(loops), tris);
    // The annulus strip with every point kept: never stitches what triangulate refuses; on
    // exact input what it stitches keeps every invariant; indices always in range.
    std::vector<kerf::cut::Triangle> strip;
    if (kerf::cut::Triangulator().triangulate_strip(kerf::cut::testing::spans_of(loops), strip)) {
        if (!status && mode == 1)
            fail(std::string("strip stitched loops triangulate refuses: ") +
                 std::string(to_string(status.error().code)));
        std::size_t n = 0;
        for (const auto& l : loops) n += l.size();
        for (const auto& tri : strip)
            if (tri.a >= n || tri.b >= n || tri.c >= n) fail("strip index out of range");
        if (mode == 1) {
            const std::string why = kerf::cut::testing::check_triangulation(loops, strip, true);
            if (!why.empty()) fail("strip: " + why);
        }
    }
    if (!status) {
        if (!tris.empty()) fail("refusal left triangles behind");
        if (mode == 0)
            fail(std::string("valid region refused: ") +
                 std::string(to_string(status.error().code)));
        return 0;
    }
    if (mode == 2) {
        std::size_t n = 0;
        for (const auto& l : loops) n += l.size();
        for (const auto& tri : tris) {
            if (tri.a >= n || tri.b >= n || tri.c >= n) fail("index out of range");
        }
        return 0;
    }
    if (t.stats().degenerate_ears != 0) fail("degenerate ear on exact input");
    const std::string why = kerf::cut::testing::check_triangulation(loops, tris, true);
    if (!why.empty()) fail(why);
    return 0;
}
