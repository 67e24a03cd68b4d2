// SessionFollower in one process: a producer (ProducerBuilder, real shared memory and journal)
// publishes the recorded stream while the follower's worker thread applies it, hands changes to
// a sink and publishes collision meshes; the main thread reads status() concurrently. The hash it
// reaches is CutSession's from the same records. Labelled concurrent: the TSan build runs it.
#include "display/app/session_follower.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include "display/app/render_sync.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/ipc/producer.hpp"
#include "tests/display/event_script.hpp"
#include "tests/display/process_support.hpp"

namespace kerf::display {
namespace {

std::uint64_t now_ns() {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                          std::chrono::steady_clock::now().time_since_epoch())
                                          .count());
}

TEST(SessionFollower, AppliesTheStreamOnItsWorkerToTheSameHashAsCutSession) {
    auto records = test::script();
    cut::CutSession reference(cut::test::two_tubes());
    for (const auto& r : records) apply_record(reference, r);

    char tmpl[] = "/tmp/kerf-follower-XXXXXX";
    const std::string dir = mkdtemp(tmpl);
    const std::string name = "kerffollow_" + std::to_string(getpid());
    auto producer = ipc::ProducerBuilder().segment_name(name).journal_dir(dir).create();
    ASSERT_TRUE(producer.has_value()) << producer.error().message();
    std::uint64_t tick = 0;
    producer->heartbeat(++tick, now_ns());

    std::atomic<int> edits{0};
    RenderSync sync;  // touched only by the worker, through the sink
    auto follower = SessionFollower::start(
        FollowerOptions{name, true, 2'000'000'000, 500, records.size()},
        [] { return Result<mesh::TriMesh, std::string>(cut::test::two_tubes()); },
        [&](const cut::CutSession& s, const cut::SessionChanges& c, std::uint64_t) {
            sync.apply(s, c);
            ++edits;
        });
    ASSERT_TRUE(follower.has_value()) << follower.error();
    std::size_t next = 0;
    const bool done = test::wait_for(
        [&] {
            producer->heartbeat(++tick, now_ns());
            if (next < records.size()) producer->publish_event(records[next++]);
            const FollowerStatus st = (*follower)->status();
            return st.hash_valid && st.hash_sequence == records.size();
        },
        120.0);
    const FollowerStatus st = (*follower)->status();
    (*follower)->stop();
    ASSERT_TRUE(done) << "applied " << st.next_sequence << " of " << records.size() << "; "
                      << st.waiting_for << st.last_error;
    EXPECT_EQ(st.hash, reference.hash());
    EXPECT_EQ(st.session.refused, 0u);
    EXPECT_EQ(st.bodies, 3u);
    EXPECT_GT(edits.load(), 1);
    EXPECT_GE(st.publishes, 1u);
    EXPECT_EQ(st.publish_failures, 0u) << st.last_error;

    // What kerf-rt would read: the newest collision mesh, valid, with the severed body.
    auto mesh = std::make_unique<ipc::CollisionMesh>();
    ipc::MeshMailboxReader reader(producer->layout());
    ASSERT_EQ(reader.try_take_newest(*mesh), ipc::MailboxRead::kNew) << reader.last_rejection();
    EXPECT_EQ(mesh->body_count, 3u);
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

// The end of a cut may arrive in a batch of its own (kerf-rt publishes it a tick or more after
// the last progress; a slow display reads them apart). A withdrawn CutEnd changes no geometry,
// yet the mesh held back while the cut was open is still owed: lockstep and replay runs of
// kerf-rt wait for it (once they waited 30 s under ASan and counted a late world).
TEST(SessionFollower, PublishesTheHeldBackMeshWhenACutEndArrivesAlone) {
    auto records = test::script();
    ASSERT_EQ(records.back().header.type, ipc::EventType::kCutEnd);
    char tmpl[] = "/tmp/kerf-follower-XXXXXX";
    const std::string dir = mkdtemp(tmpl);
    const std::string name = "kerffollowend_" + std::to_string(getpid());
    auto producer = ipc::ProducerBuilder().segment_name(name).journal_dir(dir).create();
    ASSERT_TRUE(producer.has_value()) << producer.error().message();
    std::uint64_t tick = 0;
    producer->heartbeat(++tick, now_ns());
    auto follower = SessionFollower::start(
        FollowerOptions{name, true, 2'000'000'000, 500, 0},
        [] { return Result<mesh::TriMesh, std::string>(cut::test::two_tubes()); },
        [](const cut::CutSession&, const cut::SessionChanges&, std::uint64_t) {});
    ASSERT_TRUE(follower.has_value()) << follower.error();

    // Everything but the last CutEnd, applied: cut 2 is open, its edits held back.
    std::size_t next = 0;
    const std::uint64_t all_but_end = records.size() - 1;
    ASSERT_TRUE(test::wait_for(
        [&] {
            producer->heartbeat(++tick, now_ns());
            if (next < all_but_end) producer->publish_event(records[next++]);
            return (*follower)->status().next_sequence == all_but_end;
        },
        120.0));
    // (status is published after each step's hand-over: nothing is published while cut 2 is open)
    const std::uint64_t before = (*follower)->status().publishes;

    producer->publish_event(records.back());
    const bool published = test::wait_for(
        [&] {
            producer->heartbeat(++tick, now_ns());
            return (*follower)->status().publishes > before;
        },
        60.0);
    const FollowerStatus st = (*follower)->status();
    (*follower)->stop();
    EXPECT_EQ(st.next_sequence, records.size());
    EXPECT_TRUE(published) << "no collision mesh after the lone CutEnd (" << st.publishes
                           << " publishes; " << st.last_error << ")";
    EXPECT_EQ(st.publish_failures, 0u) << st.last_error;
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

}  // namespace
}  // namespace kerf::display
