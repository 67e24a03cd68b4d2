// The geometry mailbox: newest complete generation wins, the writer refuses a bad mesh, and the
// reader refuses anything a scribbler left in shared memory, naming what is wrong.
#include "rt_core/ipc/mesh_mailbox.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "rt_core/ipc/shm_segment.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

/// A tetrahedron per body, `bodies` bodies, 1 cm apart.
std::unique_ptr<CollisionMesh> tetrahedra(std::uint32_t bodies) {
    auto m = std::make_unique<CollisionMesh>();
    const float v[4][3] = {{0, 0, 0}, {0.01f, 0, 0}, {0, 0.01f, 0}, {0, 0, 0.01f}};
    const std::uint32_t t[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    for (std::uint32_t b = 0; b < bodies; ++b) {
        MeshBodyEntry& e = m->bodies[b];
        e = MeshBodyEntry{};
        e.vertex_offset = 4 * b;
        e.vertex_count = 4;
        e.index_offset = 12 * b;
        e.index_count = 12;
        for (int i = 0; i < 16; ++i) e.world_from_body[i] = (i % 5 == 0) ? 1.f : 0.f;
        e.world_from_body[12] = 0.01f * float(b);
        for (int i = 0; i < 4; ++i) {
            for (int k = 0; k < 3; ++k) m->vertices_m[3 * (4 * b + i) + k] = v[i][k];
        }
        for (int i = 0; i < 12; ++i) m->indices[12 * b + i] = t[i];
        for (int i = 0; i < 4; ++i) m->materials[4 * b + i] = std::uint8_t(i % 3);
    }
    m->body_count = bodies;
    m->vertex_count = 4 * bodies;
    m->index_count = 12 * bodies;
    return m;
}

struct Box {
    std::optional<ShmSegment> seg;
    Box() {
        auto s = SegmentBuilder().name(test::unique_segment_name("mbox")).create();
        EXPECT_TRUE(s);
        seg.emplace(std::move(*s));
    }
};

TEST(MeshMailbox, ReaderTakesTheNewestCompleteGeneration) {
    Box box;
    MeshMailboxWriter writer(box.seg->layout());
    MeshMailboxReader reader(box.seg->layout());
    auto out = std::make_unique<CollisionMesh>();
    EXPECT_EQ(reader.try_take_newest(*out), MailboxRead::kNothingNew);
    ASSERT_TRUE(writer.publish(*tetrahedra(1)));
    auto g2 = writer.publish(*tetrahedra(3));
    ASSERT_TRUE(g2);
    EXPECT_EQ(*g2, 2u);
    ASSERT_EQ(reader.try_take_newest(*out), MailboxRead::kNew);
    EXPECT_EQ(out->generation, 2u);
    EXPECT_EQ(out->body_count, 3u);
    EXPECT_EQ(out->indices[12 * 2 + 5], 3u);
    EXPECT_EQ(out->materials[4 * 2 + 2], std::uint8_t(TriangleMaterial::kCutSurface));
    EXPECT_EQ(reader.try_take_newest(*out), MailboxRead::kNothingNew);
    ASSERT_TRUE(writer.publish(*tetrahedra(2)));
    ASSERT_EQ(reader.try_take_newest(*out), MailboxRead::kNew);
    EXPECT_EQ(out->generation, 3u);
}

TEST(MeshMailbox, WriterRefusesABadMeshNamingTheBodyAndElement) {
    Box box;
    MeshMailboxWriter writer(box.seg->layout());
    auto m = tetrahedra(2);
    m->indices[12 + 7] = 4;  // body 1 has 4 vertices
    auto r = writer.publish(*m);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message().find("body 1: index 7 = 4 >= 4 vertices"), std::string::npos)
        << r.error().message();
    m = tetrahedra(1);
    m->vertices_m[5] = std::numeric_limits<float>::quiet_NaN();
    r = writer.publish(*m);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message().find("not_finite"), std::string::npos) << r.error().message();
    m = tetrahedra(1);
    m->bodies[0].world_from_body[0] = 2.f;  // scaled, not rigid
    EXPECT_FALSE(writer.publish(*m));
    m = tetrahedra(1);
    m->vertex_count = kMeshMaxVertices + 1;
    EXPECT_FALSE(writer.publish(*m));
    EXPECT_EQ(box.seg->layout().mailbox.latest.value.load(), 0u);  // nothing was published
}

TEST(MeshMailbox, ReaderRejectsScribbledContentAndCountsIt) {
    Box box;
    MeshMailboxWriter writer(box.seg->layout());
    MeshMailboxReader reader(box.seg->layout());
    auto out = std::make_unique<CollisionMesh>();
    ASSERT_TRUE(writer.publish(*tetrahedra(2)));
    struct Scribble {
        const char* expect;
        void (*edit)(MeshBuffer&);
    };
    const Scribble cases[] = {
        {"bad_counts", [](MeshBuffer& b) { b.header.vertex_count = 0xFFFFFFF0u; }},
        {"bad_counts", [](MeshBuffer& b) { b.header.body_count = 1000; }},
        {"bad_body_range", [](MeshBuffer& b) { b.header.bodies[1].index_offset = 0xFFFFFFF0u; }},
        {"bad_index", [](MeshBuffer& b) { b.indices[3] = 77; }},
        {"not_finite", [](MeshBuffer& b) { b.vertices_m[2] = std::nanf(""); }},
        {"out_of_bounds", [](MeshBuffer& b) { b.vertices_m[2] = 1e6f; }},
        {"bad_transform", [](MeshBuffer& b) { b.header.bodies[0].world_from_body[15] = 0.f; }},
        {"bad_generation", [](MeshBuffer& b) { b.header.generation = 99; }},
        {"bad_material", [](MeshBuffer& b) { b.materials[5] = 3; }},
        {"bad_hash", [](MeshBuffer& b) { b.vertices_m[4] += 0.001f; }},  // valid, but not sent
        {"bad_hash", [](MeshBuffer& b) { b.materials[1] = 0; }},
    };
    std::uint64_t expected_rejections = 0;
    for (const Scribble& s : cases) {
        ASSERT_TRUE(writer.publish(*tetrahedra(2)));  // fresh generation lands in buffer 1 or 0
        MeshBuffer& target =
            box.seg->layout().mailbox.buffers[box.seg->layout().mailbox.latest.value.load() & 1u];
        s.edit(target);
        ASSERT_EQ(reader.try_take_newest(*out), MailboxRead::kRejected) << s.expect;
        EXPECT_EQ(reader.rejected(), ++expected_rejections);
        EXPECT_NE(reader.last_rejection().find(s.expect), std::string::npos)
            << reader.last_rejection();
        EXPECT_EQ(reader.try_take_newest(*out), MailboxRead::kNothingNew);  // not retried
    }
}

TEST(MeshMailbox, WriterRefusesAnUnknownMaterialNamingTheTriangle) {
    Box box;
    MeshMailboxWriter writer(box.seg->layout());
    auto m = tetrahedra(2);
    m->materials[4 + 2] = 9;
    auto r = writer.publish(*m);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message().find("body 1: triangle 2 material 9"), std::string::npos)
        << r.error().message();
}

TEST(MeshMailbox, ContentHashCoversEveryArray) {
    auto m = tetrahedra(2);
    const std::uint64_t h = mesh_content_hash(*m);
    EXPECT_EQ(mesh_content_hash(*tetrahedra(2)), h);
    m->materials[6] = 0;  // was kCutSurface
    EXPECT_NE(mesh_content_hash(*m), h);
    m = tetrahedra(2);
    m->indices[23] = 0;
    EXPECT_NE(mesh_content_hash(*m), h);
    m = tetrahedra(2);
    m->bodies[1].world_from_body[13] = 0.5f;
    EXPECT_NE(mesh_content_hash(*m), h);
}

TEST(MeshMailbox, ReaderReportsBusyWhileTheBufferIsBeingWritten) {
    Box box;
    MeshMailboxWriter writer(box.seg->layout());
    MeshMailboxReader reader(box.seg->layout());
    ASSERT_TRUE(writer.publish(*tetrahedra(1)));
    auto& buf = box.seg->layout().mailbox.buffers[0];
    buf.sequence.value.store(buf.sequence.value.load() | 1u);
    auto out = std::make_unique<CollisionMesh>();
    EXPECT_EQ(reader.try_take_newest(*out), MailboxRead::kBusy);
}

}  // namespace
}  // namespace kerf::ipc
