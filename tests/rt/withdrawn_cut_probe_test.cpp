// Random withdrawn-cut sequences on the calcaneus through the display's own CutSession (as
// withdrawn_cut_contact_test.cpp applies them), each cut turned about the surface normal, with a
// random kerf, length and depth: every CutBegin must be sliced and the rendered mesh must not
// cross itself near an opened kerf. Opt-in (KERF_WITHDRAWN_PROBE=1, about a minute), because it
// fails today: on 853676d, 2 of 181 CutBegins refused and faces cross after 144 of them (later
// localised cuts slice one side of an earlier withdrawn cut only: display/cut/README.md, Gradual
// separation); with Separator::keep_off, 1 refused and faces cross after 131 (5,363 crossing
// pairs summed over the cuts, from 60,341); with keep_off's ramp (kKeepOffRampKerfs), none
// refused and faces cross after 35 (227 pairs). Prints what it found by sequence and cut.
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

TEST(WithdrawnCutProbe, EveryCutIsSlicedAndNothingCrossesNearTheKerfs) {
    if (std::getenv("KERF_WITHDRAWN_PROBE") == nullptr)
        GTEST_SKIP() << "opt-in: KERF_WITHDRAWN_PROBE=1 (fails today, see the file comment)";
    if (!rt::test::have_shared_meshes()) GTEST_SKIP() << "no " << rt::test::calcaneus_path();
    std::map<std::string, int> refusals;
    int begins = 0, crossing_cuts = 0;
    for (int sequence = 0; sequence < kSequences; ++sequence) {
        // Sequence 0 is WithdrawnCutContact.CutsThroughTurnedWithdrawnCutsAreSliced.
        auto scene = mesh::load_mesh_owned(rt::test::calcaneus_path(), LengthUnit::kMillimetre);
        ASSERT_TRUE(scene) << scene.error().message();
        cut::CutSession session(std::move(*scene));
        const auto after_cut = [&](int k, int cuts, const cut::ApplyReport& r) {
            ++begins;
            if (r.outcome == cut::EventOutcome::kRefused) {
                const std::string status(cut::to_string(r.status));
                ++refusals[status];
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
                ++crossing_cuts;
                std::printf("sequence %d after cut %d: %zu crossing face pairs (first %d, %d)\n",
                            sequence, k, crossing.size(), crossing[0].a, crossing[0].b);
            }
        };
        physics::test::apply_turned_withdrawn_sequence(session, 1000 + sequence, after_cut);
    }
    int refused = 0;
    std::printf("%d CutBegins; faces crossing after %d; refused:", begins, crossing_cuts);
    for (const auto& [status, n] : refusals) {
        std::printf(" %s %d", status.c_str(), n);
        refused += n;
    }
    std::printf("\n");
    EXPECT_EQ(refused, 0);
    EXPECT_EQ(crossing_cuts, 0);
}

}  // namespace
}  // namespace kerf
