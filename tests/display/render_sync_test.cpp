// RenderSync: the renderer's flat copy follows a CutSession through the recorded stream with
// RenderMesh::apply() (the one geometry path), and severed or moved bodies get transform slots.
#include "display/app/render_sync.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "tests/display/event_script.hpp"

namespace kerf::display {
namespace {

/// Same drawn corners (position, normal, plane coordinates, kind), bodies aside.
bool same_geometry(const render::RenderMesh& a, const render::RenderMesh& b) {
    if (a.triangle_count() != b.triangle_count()) return false;
    for (std::uint32_t i = 0; i < a.triangle_count() * 3; ++i) {
        const render::RenderVertex& va = a.vertices()[a.indices()[i]];
        const render::RenderVertex& vb = b.vertices()[b.indices()[i]];
        if (std::memcmp(&va, &vb, offsetof(render::RenderVertex, body)) != 0) return false;
    }
    return true;
}

TEST(RenderSync, FollowsTheRecordedStreamAndGivesTheSeveredPieceItsOwnSlot) {
    cut::CutSession session(cut::test::two_tubes());
    cut::SessionChanges changes;
    RenderSync sync;
    session.take_changes(changes);
    sync.apply(session, changes);
    ASSERT_TRUE(sync.mesh().has_value());
    const std::uint64_t generation = sync.mesh()->generation();
    for (const ipc::EventRecord& r : test::script()) {
        apply_record(session, r);
        session.take_changes(changes);
        sync.apply(session, changes);
        EXPECT_TRUE(same_geometry(*sync.mesh(), render::RenderMesh::build(session.mesh())))
            << "after event " << r.header.sequence << " (" << ipc::to_string(r.header.type) << ")";
    }
    EXPECT_EQ(sync.mesh()->generation(), generation) << "edits applied in place, no rebuild";
    ASSERT_EQ(session.bodies().size(), 3u);
    // The severed, moved piece (body 2) is drawn with a slot of its own and its pose; the rest
    // share the identity slot 0.
    std::uint8_t piece_slot = 0;
    for (const auto v : session.mesh().vertices()) {
        if (session.mesh().status(v).deleted()) continue;
        const std::uint8_t slot = sync.mesh()->vertices()[std::size_t(v.idx())].body;
        if (session.body_of(v) == 2) {
            EXPECT_NE(slot, 0);
            piece_slot = slot;
        } else {
            EXPECT_EQ(slot, 0) << "vertex " << v.idx() << " of body " << session.body_of(v);
        }
    }
    ASSERT_NE(piece_slot, 0);
    const auto pose = session.bodies()[2].pose.matrix();
    EXPECT_EQ(sync.transforms()[piece_slot][3][2], pose.data()[14]);  // translation z
    EXPECT_EQ(sync.bodies_without_slot(), 0u);
}

}  // namespace
}  // namespace kerf::display
