// Random withdrawn-cut sequences on the calcaneus through the display's own CutSession (as
// withdrawn_cut_contact_test.cpp applies them), each cut turned about the surface normal, with a
// random kerf, length and depth: every CutBegin must be sliced and the rendered mesh must not
// cross itself near an opened kerf. Opt-in (KERF_WITHDRAWN_PROBE=1, about a minute), because it
// fails today: on 853676d, 2 of 181 CutBegins refused and faces cross after 144 of them (later
// localised cuts slice one side of an earlier withdrawn cut only: display/cut/README.md, Gradual
// separation); with Separator::keep_off, 1 refused and faces cross after 131 (5,363 crossing
// pairs summed over the cuts, from 60,341); with keep_off's ramp (kKeepOffRampKerfs), none
// refused and faces cross after 35 (227 pairs); with earlier caps' long triangles held where they
// leave the band, after 24 (117 pairs, sequences 2, 6 and 13). 6 sequences that pass run by default
// (TheSequencesThatOpenCleanlyStayClean, about 25 s of CPU in the debug-checks build).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "display/mesh/mesh_io.hpp"
#include "tests/cut/self_intersection.hpp"
#include "tests/physics/withdrawn_cuts.hpp"
#include "tests/rt/rt_rig.hpp"

namespace kerf {
namespace {

constexpr int kSequences = 14;

/// What the sequences (random seeds 1000 + sequence) did: CutBegins refused by status, and the
/// cuts after which faces cross. Prints what it found by sequence and cut.
struct ProbeResult {
    int begins = 0, refused = 0, crossing_cuts = 0;
};

ProbeResult probe(const std::vector<int>& sequences) {
    ProbeResult result;
    std::map<std::string, int> refusals;
    for (const int sequence : sequences) {
        // Sequence 0 is WithdrawnCutContact.CutsThroughTurnedWithdrawnCutsAreSliced.
        auto scene = mesh::load_mesh_owned(rt::test::calcaneus_path(), LengthUnit::kMillimetre);
        if (!scene) {
            ADD_FAILURE() << scene.error().message();
            return result;
        }
        cut::CutSession session(std::move(*scene));
        const auto after_cut = [&](int k, int cuts, const cut::ApplyReport& r) {
            ++result.begins;
            if (r.outcome == cut::EventOutcome::kRefused) {
                const std::string status(cut::to_string(r.status));
                ++refusals[status];
                ++result.refused;
                std::printf("sequence %d cut %d of %d refused: %s\n", sequence, k, cuts,
                            status.c_str());
            }
            // Faces with a corner within 1.6 mm (two of the widest kerfs) of a withdrawn plane.
            const mesh::TriMesh& m = session.mesh();
            const auto withdrawn = session.withdrawn_cuts();
            const auto near_kerf = [&](mesh::FaceHandle f) {
                for (const auto v : m.fv_range(f))
                    for (const auto& w : withdrawn)
                        if (std::abs(w.plane.signed_distance(m.point(v))) < 0.0016) return true;
                return false;
            };
            const auto crossing = cut::testing::crossing_face_pairs(m, 0.001, 1e-10, near_kerf);
            if (!crossing.empty()) {
                ++result.crossing_cuts;
                std::printf("sequence %d after cut %d: %zu crossing face pairs (first %d, %d)\n",
                            sequence, k, crossing.size(), crossing[0].a, crossing[0].b);
            }
        };
        physics::test::apply_turned_withdrawn_sequence(session, 1000 + sequence, after_cut);
    }
    std::printf("%d CutBegins; faces crossing after %d; refused:", result.begins,
                result.crossing_cuts);
    for (const auto& [status, n] : refusals) std::printf(" %s %d", status.c_str(), n);
    std::printf("\n");
    return result;
}

TEST(WithdrawnCutProbe, EveryCutIsSlicedAndNothingCrossesNearTheKerfs) {
    if (std::getenv("KERF_WITHDRAWN_PROBE") == nullptr)
        GTEST_SKIP() << "opt-in: KERF_WITHDRAWN_PROBE=1 (fails today, see the file comment)";
    if (!rt::test::have_shared_meshes()) GTEST_SKIP() << "no " << rt::test::calcaneus_path();
    std::vector<int> all;
    for (int sequence = 0; sequence < kSequences; ++sequence) all.push_back(sequence);
    const ProbeResult r = probe(all);
    EXPECT_EQ(r.refused, 0);
    EXPECT_EQ(r.crossing_cuts, 0);
}

TEST(WithdrawnCutProbe, TheSequencesThatOpenCleanlyStayClean) {
    // 6 of the 11 sequences of the probe that pass today (84 CutBegins), run by default so that
    // they stay clean: on 1324355 (before keep_off's ramp) faces crossed in sequences 0, 3, 8,
    // 10, 11 and 12 after 4, 3, 3, 2, 1 and 3 cuts, and sequence 8's cut 16 was refused; on
    // 7d300ec sequence 10 still crossed after its cut 2 (an earlier cap's long triangle).
    if (!rt::test::have_shared_meshes()) GTEST_SKIP() << "no " << rt::test::calcaneus_path();
    const ProbeResult r = probe({0, 3, 8, 10, 11, 12});
    EXPECT_EQ(r.refused, 0);
    EXPECT_EQ(r.crossing_cuts, 0);
}

}  // namespace
}  // namespace kerf
