// ShmSegment / SegmentBuilder: creation, header verification with a message per differing field,
// stale-socket replacement, refusal of a live owner, bad names, permissions, seals, trust.
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
    ASSERT_TRUE(created) << created.error().message();
    const SegmentHeader& h = created->layout().header;
    EXPECT_EQ(h.magic, kMagic);
    EXPECT_EQ(h.layout_version, kLayoutVersion);
    EXPECT_EQ(h.layout_hash, kLayoutHash);
    EXPECT_NE(h.session_id, 0u);
    EXPECT_EQ(h.producer_pid, getpid());
    EXPECT_GT(h.start_time_unix_ns, 0u);
    EXPECT_EQ(journal_path_of(h).rfind(session_dir_of(default_runtime_dir(), name) + "/", 0), 0u);
    auto opened = SegmentBuilder().name(name).open();
    ASSERT_TRUE(opened) << opened.error().message();
    EXPECT_FALSE(opened->owner());
    EXPECT_EQ(opened->layout().header.session_id, h.session_id);
}

TEST(ShmSegment, OwnerOnlyPermissionsByDefaultGroupOnRequest) {
    for (bool group : {false, true}) {
        const auto name = unique_segment_name("perm");
        auto seg = SegmentBuilder().name(name).group_access(group).create();
        ASSERT_TRUE(seg);
        EXPECT_EQ(seg->mode(), group ? 0660u : 0600u);
        struct stat st {};
        ASSERT_EQ(stat(seg->socket_path().c_str(), &st), 0);
        EXPECT_TRUE(S_ISSOCK(st.st_mode));
        EXPECT_EQ(st.st_mode & 0777, group ? 0660u : 0600u);
        ASSERT_EQ(stat(session_dir_of(default_runtime_dir(), name).c_str(), &st), 0);
        EXPECT_EQ(st.st_mode & 0777, group ? 0750u : 0700u);
        auto opened = SegmentBuilder().name(name).open();
        ASSERT_TRUE(opened) << opened.error().message();
        EXPECT_EQ(opened->mode(), group ? 0660u : 0600u);
        EXPECT_EQ(opened->owner_uid(), geteuid());
    }
}

TEST(ShmSegment, AGroupThatDoesNotExistIsAnError) {
    auto seg =
        SegmentBuilder().name(unique_segment_name("nogrp")).group("kerf-no-such-group").create();
    ASSERT_FALSE(seg);
    EXPECT_EQ(seg.error().code, IpcErrc::kBadArgument);
    EXPECT_NE(seg.error().message().find("group 'kerf-no-such-group' does not exist"),
              std::string::npos)
        << seg.error().message();
}

TEST(ShmSegment, TheServedSegmentIsSealedAgainstResizing) {
    const auto name = unique_segment_name("seal");
    auto seg = SegmentBuilder().name(name).create();
    ASSERT_TRUE(seg);
    auto fds = fetch_session(default_runtime_dir(), name);
    ASSERT_TRUE(fds) << fds.error().message();
    const int seals = fcntl(fds->segment_fd, F_GET_SEALS);
    EXPECT_EQ(seals & (F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL),
              F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL);
    EXPECT_NE(ftruncate(fds->segment_fd, 0), 0);
    EXPECT_EQ(errno, EPERM);
    EXPECT_NE(ftruncate(fds->segment_fd, 2 * sizeof(SegmentLayout)), 0);
    EXPECT_NE(fcntl(fds->segment_fd, F_ADD_SEALS, F_SEAL_WRITE), 0);  // F_SEAL_SEAL
    close(fds->segment_fd);
    if (fds->journal_fd >= 0) close(fds->journal_fd);
    seg->layout().producer.heartbeat_ns.store(monotonic_ns());  // still mapped and writable
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
    const std::string& msg = opened.error().message();
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
    EXPECT_NE(opened.error().message().find("magic 0x1234"), std::string::npos);
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
    EXPECT_NE(r.error().message().find("journal dir"), std::string::npos);
}

TEST(ShmSegment, LiveProducersSegmentIsRefused) {
    const auto name = unique_segment_name("live");
    auto first = SegmentBuilder().name(name).create();
    ASSERT_TRUE(first);
    first->layout().producer.heartbeat_ns.store(monotonic_ns());
    auto second = SegmentBuilder().name(name).create();
    ASSERT_FALSE(second);
    EXPECT_EQ(second.error().code, IpcErrc::kInUse);
    EXPECT_NE(second.error().message().find(std::to_string(getpid())), std::string::npos);
}

TEST(ShmSegment, StaleSocketOfADeadProducerIsReportedAndReplaced) {
    const auto name = unique_segment_name("stale");
    const pid_t child = fork();
    if (child == 0) {
        auto seg = SegmentBuilder().name(name).create();
        if (!seg) _exit(3);
        seg->layout().header.state.store(std::uint32_t(SegmentState::kRunning));
        seg->layout().producer.heartbeat_ns.store(monotonic_ns());
        _exit(0);  // dies without removing its socket (no destructors run)
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_EQ(WEXITSTATUS(status), 0);
    auto left = SegmentBuilder().name(name).open();
    ASSERT_FALSE(left);
    EXPECT_EQ(left.error().code, IpcErrc::kProducerGone);
    EXPECT_NE(left.error().message().find("stale socket"), std::string::npos)
        << left.error().message();
    auto replaced = SegmentBuilder().name(name).create();
    ASSERT_TRUE(replaced) << replaced.error().message();
    EXPECT_EQ(replaced->layout().header.producer_pid, getpid());
    auto opened = SegmentBuilder().name(name).open();
    ASSERT_TRUE(opened) << opened.error().message();
}

TEST(ShmSegment, SomethingElseAtTheSocketPathIsNeverRemoved) {
    test::ScratchDir runtime;
    const auto name = unique_segment_name("notsock");
    ASSERT_EQ(mkdir(session_dir_of(runtime.path, name).c_str(), 0700), 0);
    const std::string path = session_socket_of(runtime.path, name);
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    ASSERT_GE(fd, 0);
    close(fd);
    auto seg = SegmentBuilder().name(name).runtime_dir(runtime.path).create();
    ASSERT_FALSE(seg);
    EXPECT_NE(seg.error().message().find("is not a socket"), std::string::npos)
        << seg.error().message();
    struct stat st {};
    EXPECT_EQ(stat(path.c_str(), &st), 0);
}

TEST(ShmSegment, AWorldWritableSessionFolderIsRefused) {
    test::ScratchDir runtime;
    const auto name = unique_segment_name("world");
    auto seg = SegmentBuilder().name(name).runtime_dir(runtime.path).create();
    ASSERT_TRUE(seg);
    ASSERT_EQ(chmod(session_dir_of(runtime.path, name).c_str(), 0777), 0);
    auto opened = SegmentBuilder().name(name).runtime_dir(runtime.path).open();
    ASSERT_FALSE(opened);
    EXPECT_EQ(opened.error().code, IpcErrc::kUntrusted);
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
    EXPECT_EQ(to_string(ProducerHealth::kStale), "stale");
}

}  // namespace
}  // namespace kerf::ipc
