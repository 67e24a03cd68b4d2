// JournalReader over files that are not what they claim: each bad input is refused with a
// message naming the file and the field, or a bad record is reported corrupt, never a crash.
#include "rt_core/ipc/journal_reader.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "rt_core/ipc/layout.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

std::string write_journal(const std::string& dir, JournalFileHeader h,
                          const std::vector<EventRecord>& records, std::size_t truncate_to = 0) {
    const std::string path = dir + "/j.kjournal";
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(&h), sizeof h);
    for (const auto& r : records) f.write(reinterpret_cast<const char*>(&r), sizeof r);
    f.close();
    if (truncate_to != 0) (void)truncate(path.c_str(), static_cast<off_t>(truncate_to));
    return path;
}

JournalFileHeader good_header() {
    JournalFileHeader h{};
    h.magic = kJournalMagic;
    h.version = kJournalVersion;
    h.record_bytes = sizeof(EventRecord);
    h.session_id = 77;
    h.layout_hash = kLayoutHash;
    return h;
}

std::vector<EventRecord> records(std::initializer_list<std::uint64_t> seqs) {
    std::vector<EventRecord> out;
    for (auto s : seqs) {
        EventRecord r = test::make_event(s);
        r.header.sequence = s;
        stamp_checksum(r);
        out.push_back(r);
    }
    return out;
}

TEST(JournalReader, BadHeadersAreRefusedNamingTheField) {
    test::ScratchDir dir;
    struct Case {
        const char* field;
        void (*edit)(JournalFileHeader&);
    };
    const Case cases[] = {
        {"magic", [](JournalFileHeader& h) { h.magic = 1; }},
        {"version", [](JournalFileHeader& h) { h.version = 9; }},
        {"record bytes", [](JournalFileHeader& h) { h.record_bytes = 64; }},
        {"layout hash", [](JournalFileHeader& h) { h.layout_hash = 5; }},
        {"session id", [](JournalFileHeader& h) { h.session_id = 78; }},
    };
    for (const Case& c : cases) {
        JournalFileHeader h = good_header();
        c.edit(h);
        const auto path = write_journal(dir.path, h, {});
        auto r = JournalReader::open(path, 77);
        ASSERT_FALSE(r) << c.field;
        EXPECT_EQ(r.error().code, IpcErrc::kJournal);
        EXPECT_NE(r.error().message().find(c.field), std::string::npos) << r.error().message();
        EXPECT_NE(r.error().message().find(path), std::string::npos);
    }
    auto missing = JournalReader::open(dir.path + "/nope", 0);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, IpcErrc::kNotFound);
    const auto short_path = write_journal(dir.path, good_header(), {}, 10);
    EXPECT_FALSE(JournalReader::open(short_path, 0));
}

// Issue 9, item 5: a journal found by path is opened only when it is a regular file this user
// (or root) owns and others cannot write — a FIFO does not hang the open, a link is not followed,
// a file another user planted is refused before its header is read.
TEST(JournalReader, OpenByPathRefusesAFifoALinkAForeignOwnerAndAWorldWritableFile) {
    test::ScratchDir dir;
    // The error message of opening `path`, "" when it opened.
    const auto refusal = [](const std::string& path) {
        auto r = JournalReader::open(path, 77);
        return r ? std::string() : r.error().message();
    };
    const std::string fifo = dir.path + "/fifo.kjournal";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    // Would block forever without O_NONBLOCK.
    EXPECT_NE(refusal(fifo).find("not a regular file"), std::string::npos) << refusal(fifo);

    const std::string good = write_journal(dir.path, good_header(), records({1, 2}));
    EXPECT_EQ(refusal(good), "");
    const std::string link = dir.path + "/link.kjournal";
    ASSERT_EQ(symlink(good.c_str(), link.c_str()), 0);
    EXPECT_NE(refusal(link).find("symbolic link"), std::string::npos) << refusal(link);

    ASSERT_EQ(chmod(good.c_str(), 0666), 0);
    EXPECT_NE(refusal(good).find("writable by every user (mode 666)"), std::string::npos)
        << refusal(good);
    ASSERT_EQ(chmod(good.c_str(), 0644), 0);

    if (geteuid() != 0) GTEST_SKIP() << "giving the file to another user needs root";
    ASSERT_EQ(chown(good.c_str(), 65534, 65534), 0);  // nobody
    EXPECT_NE(refusal(good).find("owned by uid 65534, not by this user"), std::string::npos)
        << refusal(good);
}

TEST(JournalReader, FindsRecordsAcrossDroppedSequences) {
    test::ScratchDir dir;
    const auto path = write_journal(dir.path, good_header(), records({0, 1, 2, 5, 6, 9}));
    auto j = JournalReader::open(path, 77);
    ASSERT_TRUE(j) << j.error().message();
    EventRecord r;
    ASSERT_EQ(j->try_read(2, r), JournalRead::kOk);
    EXPECT_EQ(r.header.sequence, 2u);
    ASSERT_EQ(j->try_read(3, r), JournalRead::kOk);  // 3 and 4 were never journalled
    EXPECT_EQ(r.header.sequence, 5u);
    ASSERT_EQ(j->try_read(7, r), JournalRead::kOk);
    EXPECT_EQ(r.header.sequence, 9u);
    EXPECT_EQ(j->try_read(10, r), JournalRead::kNotYet);
}

TEST(JournalReader, CorruptRecordIsReportedAndAPartialTailIsNotYetThere) {
    test::ScratchDir dir;
    auto recs = records({0, 1, 2});
    recs[1].cut.plane_point_m[0] = 3.0f;  // changed after stamping
    const auto path = write_journal(dir.path, good_header(), recs,
                                    sizeof(JournalFileHeader) + 2 * sizeof(EventRecord) + 50);
    auto j = JournalReader::open(path, 0);
    ASSERT_TRUE(j);
    EXPECT_EQ(j->record_count(), 2u);
    EventRecord r;
    EXPECT_EQ(j->try_read(1, r), JournalRead::kCorrupt);
    EXPECT_EQ(j->try_read(2, r), JournalRead::kNotYet);
}

}  // namespace
}  // namespace kerf::ipc
