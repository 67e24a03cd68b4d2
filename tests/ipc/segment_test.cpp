// ShmSegment / SegmentBuilder: creation, header verification with a message per differing field,
// stale-segment replacement, refusal of a live owner, bad names, permissions.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rt_core/ipc/shm_segment.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

using test::unique_segment_name;

TEST(ShmSegment, CreateFillsEveryHeaderFieldAndOpenAcceptsIt) {
    const auto name = unique_segment_name("seg");
    auto created = SegmentBuilder().name(name).create();
    ASSERT_TRUE(created) << created.error().message;
    const SegmentHeader& h = created->layout().header;
    EXPECT_EQ(h.magic, kMagic);
    EXPECT_EQ(h.layout_version, kLayoutVersion);
    EXPECT_EQ(h.layout_hash, kLayoutHash);
    EXPECT_NE(h.session_id, 0u);
    EXPECT_EQ(h.producer_pid, getpid());
    EXPECT_GT(h.start_time_unix_ns, 0u);
    EXPECT_EQ(journal_path_of(h).rfind("/dev/shm/" + name + "-", 0), 0u);
    auto opened = SegmentBuilder().name(name).open();
    ASSERT_TRUE(opened) << opened.error().message;
    EXPECT_FALSE(opened->owner());
    EXPECT_EQ(opened->layout().header.session_id, h.session_id);
}

TEST(ShmSegment, OwnerOnlyPermissionsByDefaultGroupOnRequest) {
    for (bool group : {false, true}) {
        const auto name = unique_segment_name("perm");
        auto seg = SegmentBuilder().name(name).group_access(group).create();
        ASSERT_TRUE(seg);
        struct stat st {};
        ASSERT_EQ(stat(("/dev/shm/" + name).c_str(), &st), 0);
        EXPECT_EQ(st.st_mode & 0777, group ? 0660u : 0600u);
    }
}

TEST(ShmSegment, OpenNamesEveryHeaderFieldThatDiffers) {
    const auto name = unique_segment_name("diff");
    auto seg = SegmentBuilder().name(name).create();
    ASSERT_TRUE(seg);
    SegmentHeader& h = seg->layout().header;
    h.layout_version = 7;
    h.layout_hash ^= 1;
    h.event_capacity = 100;
    auto opened = SegmentBuilder().name(name).open();
    ASSERT_FALSE(opened);
    EXPECT_EQ(opened.error().code, IpcErrc::kBadHeader);
    const std::string& msg = opened.error().message;
    EXPECT_NE(msg.find("segment " + name), std::string::npos) << msg;
    EXPECT_NE(msg.find("layout version 7, expected " + std::to_string(kLayoutVersion)),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("layout hash"), std::string::npos) << msg;
    EXPECT_NE(msg.find("event capacity 100, expected 4096"), std::string::npos) << msg;
    h.layout_version = kLayoutVersion;
    h.layout_hash = kLayoutHash;
    h.event_capacity = kEventCapacity;
    h.magic = 0x1234;
    opened = SegmentBuilder().name(name).open();
    ASSERT_FALSE(opened);
    EXPECT_NE(opened.error().message.find("magic 0x1234"), std::string::npos);
}

TEST(ShmSegment, OpenRefusesATruncatedSegmentSayingItsSize) {
    const auto name = unique_segment_name("short");
    const int fd = shm_open(("/" + name).c_str(), O_RDWR | O_CREAT | O_EXCL, 0600);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(ftruncate(fd, 100), 0);
    close(fd);
    auto opened = SegmentBuilder().name(name).open();
    ASSERT_FALSE(opened);
    EXPECT_NE(opened.error().message.find("100 bytes"), std::string::npos)
        << opened.error().message;
    shm_unlink(("/" + name).c_str());
}

TEST(ShmSegment, MissingSegmentIsNotFound) {
    auto opened = SegmentBuilder().name(unique_segment_name("none")).open();
    ASSERT_FALSE(opened);
    EXPECT_EQ(opened.error().code, IpcErrc::kNotFound);
}

TEST(ShmSegment, BadNamesAreRefusedBeforeAnySystemCall) {
    for (const char* bad : {"", "a/b", "..", "white space", "x\n"}) {
        auto r = SegmentBuilder().name(bad).create();
        ASSERT_FALSE(r) << bad;
        EXPECT_EQ(r.error().code, IpcErrc::kBadArgument);
    }
    auto r = SegmentBuilder().name(unique_segment_name()).journal_dir("relative").create();
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("journal dir"), std::string::npos);
}

TEST(ShmSegment, LiveProducersSegmentIsRefused) {
    const auto name = unique_segment_name("live");
    auto first = SegmentBuilder().name(name).create();
    ASSERT_TRUE(first);
    first->layout().producer.heartbeat_ns.store(monotonic_ns());
    auto second = SegmentBuilder().name(name).create();
    ASSERT_FALSE(second);
    EXPECT_EQ(second.error().code, IpcErrc::kInUse);
    EXPECT_NE(second.error().message.find(std::to_string(getpid())), std::string::npos);
}

TEST(ShmSegment, StaleSegmentOfADeadProducerIsReplaced) {
    const auto name = unique_segment_name("stale");
    const pid_t child = fork();
    if (child == 0) {
        auto seg = SegmentBuilder().name(name).create();
        if (!seg) _exit(3);
        seg->layout().header.state.store(std::uint32_t(SegmentState::kRunning));
        seg->layout().producer.heartbeat_ns.store(monotonic_ns());
        _exit(0);  // dies without unlinking (no destructors run)
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_EQ(WEXITSTATUS(status), 0);
    auto left = SegmentBuilder().name(name).open();
    ASSERT_TRUE(left);
    EXPECT_EQ(producer_health(left->layout()), ProducerHealth::kDead);
    const auto old_session = left->layout().header.session_id;
    auto replaced = SegmentBuilder().name(name).create();
    ASSERT_TRUE(replaced) << replaced.error().message;
    EXPECT_NE(replaced->layout().header.session_id, old_session);
    EXPECT_EQ(replaced->layout().header.producer_pid, getpid());
}

TEST(ShmSegment, GarbageSegmentUnderTheNameIsReplaced) {
    const auto name = unique_segment_name("junk");
    const int fd = shm_open(("/" + name).c_str(), O_RDWR | O_CREAT | O_EXCL, 0600);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(ftruncate(fd, sizeof(SegmentLayout)), 0);
    ASSERT_EQ(write(fd, "garbage!", 8), 8);
    close(fd);
    auto replaced = SegmentBuilder().name(name).create();
    ASSERT_TRUE(replaced) << replaced.error().message;
    EXPECT_EQ(replaced->layout().header.magic, kMagic);
}

TEST(ShmSegment, ProducerHealthReadsStateHeartbeatAndPid) {
    const auto name = unique_segment_name("health");
    auto seg = SegmentBuilder().name(name).create();
    ASSERT_TRUE(seg);
    SegmentLayout& s = seg->layout();
    s.producer.heartbeat_ns.store(monotonic_ns());
    EXPECT_EQ(producer_health(s), ProducerHealth::kAlive);
    s.producer.heartbeat_ns.store(monotonic_ns() - 200'000'000);
    EXPECT_EQ(producer_health(s), ProducerHealth::kStale);
    s.header.state.store(std::uint32_t(SegmentState::kStopped));
    EXPECT_EQ(producer_health(s), ProducerHealth::kStopped);
    s.header.state.store(std::uint32_t(SegmentState::kRunning));
    s.header.producer_pid = -5;
    EXPECT_EQ(producer_health(s), ProducerHealth::kDead);
    s.header.producer_pid = getpid();
    EXPECT_STREQ(to_string(ProducerHealth::kStale), "stale");
}

}  // namespace
}  // namespace kerf::ipc
