// kerf_file_io: regular files only with a cap; atomic single and multi-file writes (all or
// nothing), outputs that are inputs refused, stale files of an earlier set removed.
#include "config/file_io/file_io.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

namespace kerf::files {
namespace {

namespace fs = std::filesystem;

class FileIo : public ::testing::Test {
protected:
    void SetUp() override {
        char tmpl[] = "/tmp/kerf-file-io-XXXXXX";
        dir_ = mkdtemp(tmpl);
    }
    void TearDown() override { fs::remove_all(dir_); }
    void put(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
    std::string get(const fs::path& p) {
        std::ifstream in(p);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }
    std::size_t entries() {
        return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
    }
    fs::path dir_;
};

TEST_F(FileIo, ReadsARegularFileAndFollowsALinkToOne) {
    put(dir_ / "a.txt", "hello");
    fs::create_symlink(dir_ / "a.txt", dir_ / "link.txt");
    auto bytes = read_regular_file(dir_ / "link.txt", 100);
    ASSERT_TRUE(bytes) << bytes.error().message();
    EXPECT_EQ(bytes->size(), 5u);
}

TEST_F(FileIo, RefusesDevicesFifosDirectoriesAndLinksToThemWithoutBlocking) {
    fs::create_symlink("/dev/zero", dir_ / "z.stl");
    ASSERT_EQ(mkfifo((dir_ / "f.stl").c_str(), 0600), 0);
    for (const fs::path& p : {dir_ / "z.stl", fs::path("/dev/urandom"), dir_ / "f.stl", dir_}) {
        auto bytes = read_regular_file(p, kDefaultMaxInputBytes);
        ASSERT_FALSE(bytes) << p;
        EXPECT_NE(bytes.error().what.find("not a regular file"), std::string::npos)
            << bytes.error().message();
    }
    EXPECT_NE(read_regular_file(dir_ / "f.stl", 10).error().what.find("FIFO"), std::string::npos);
}

TEST_F(FileIo, AFileAboveTheCapIsAClearError) {
    put(dir_ / "big", std::string(1000, 'x'));
    auto bytes = read_regular_file(dir_ / "big", 999);
    ASSERT_FALSE(bytes);
    EXPECT_NE(bytes.error().what.find("1000 bytes, more than the 999-byte limit"),
              std::string::npos)
        << bytes.error().what;
    EXPECT_TRUE(read_regular_file(dir_ / "big", 1000));
}

// RegularFile: open() refuses what read_regular_file refuses, with the same error; read() gives
// the file piece by piece, short only at its end; read_whole() gives the whole file wherever
// reading stopped.
TEST_F(FileIo, ARegularFileReadsInPiecesAndWhole) {
    put(dir_ / "a.txt", "0123456789");
    auto file = RegularFile::open(dir_ / "a.txt", 100);
    ASSERT_TRUE(file) << file.error().message();
    EXPECT_EQ(file->size(), 10u);
    std::byte piece[4];
    std::string got;
    for (;;) {
        auto n = file->read(piece);
        ASSERT_TRUE(n) << n.error().message();
        got.append(reinterpret_cast<const char*>(piece), *n);
        if (*n < sizeof piece) break;
        EXPECT_EQ(*n, sizeof piece);
    }
    EXPECT_EQ(got, "0123456789");
    auto whole = file->read_whole();
    ASSERT_TRUE(whole) << whole.error().message();
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(whole->data()), whole->size()),
              "0123456789");
    for (const auto& [path, cap] : {std::pair{dir_ / "a.txt", std::uint64_t{9}},
                                    std::pair{fs::path("/dev/zero"), kDefaultMaxInputBytes},
                                    std::pair{dir_ / "absent", kDefaultMaxInputBytes}}) {
        auto refused = RegularFile::open(path, cap);
        ASSERT_FALSE(refused) << path;
        EXPECT_EQ(refused.error().message(), read_regular_file(path, cap).error().message());
    }
}

// A file longer than fstat said (one that grew, or a /proc file, whose size reads 0) is read
// past its stated size, byte for byte, and one that runs past the cap that way is refused.
TEST_F(FileIo, AFileLongerThanItsStatedSizeIsReadWholeWithinTheCap) {
    const fs::path proc = "/proc/self/cmdline";  // regular, size 0, this process's arguments
    const std::string expected = get(proc);
    ASSERT_GT(expected.size(), 4u);
    auto bytes = read_regular_file(proc, kDefaultMaxInputBytes);
    ASSERT_TRUE(bytes) << bytes.error().message();
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size()), expected);
    auto capped = read_regular_file(proc, 4);
    ASSERT_FALSE(capped);
    EXPECT_EQ(capped.error().code, FileErrc::kTooLarge);
    EXPECT_NE(capped.error().what.find("grew past the 4-byte limit while being read"),
              std::string::npos)
        << capped.error().what;
}

TEST_F(FileIo, AMultiFileSetAppearsWholeOrNotAtAll) {
    put(dir_ / "out_1.txt", "old 1");
    fs::create_directory(dir_ / "out_2.txt");  // the second target cannot be written
    AtomicFileSet set;
    set.add(dir_ / "out_1.txt", "new 1");
    set.add(dir_ / "out_2.txt", "new 2");
    auto r = set.commit();
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().what.find("directory"), std::string::npos) << r.error().what;
    EXPECT_EQ(get(dir_ / "out_1.txt"), "old 1");  // untouched
    EXPECT_EQ(entries(), 2u);                     // no temp file left behind
}

// More files than the writer holds open at once (it writes in batches of 64): every file in
// place with its contents, no temp and no descriptor left; a failure in the last batch removes
// the temps of the batches before it and puts no target in place.
TEST_F(FileIo, ASetLargerThanABatchIsWholeOrNotAtAllAndLeavesNoDescriptorOpen) {
    auto open_fds = [] {
        return std::distance(fs::directory_iterator("/proc/self/fd"), fs::directory_iterator());
    };
    auto piece = [&](int i) { return dir_ / ("p_" + std::to_string(i) + ".txt"); };
    auto text = [](int i) { return "piece " + std::to_string(i); };
    const auto fds_before = open_fds();
    constexpr int kFiles = 150;
    {
        AtomicFileSet set;
        for (int i = 0; i < kFiles; ++i) set.add(piece(i), text(i));
        set.add(dir_ / "missing-folder" / "last.txt", "x");  // its temp cannot be created
        auto r = set.commit();
        ASSERT_FALSE(r);
        EXPECT_NE(r.error().what.find("cannot create a temporary file"), std::string::npos);
        EXPECT_EQ(entries(), 0u) << "temps of the earlier batches were left behind";
    }
    EXPECT_EQ(open_fds(), fds_before);
    AtomicFileSet set;
    for (int i = 0; i < kFiles; ++i) set.add(piece(i), text(i));
    ASSERT_TRUE(set.commit());
    EXPECT_EQ(entries(), std::size_t{kFiles});
    for (int i = 0; i < kFiles; ++i) EXPECT_EQ(get(piece(i)), text(i));
    EXPECT_EQ(open_fds(), fds_before);
}

TEST_F(FileIo, AnOutputThatIsAnInputIsRefusedWhateverThePath) {
    put(dir_ / "x_1.stl", "bone");
    fs::create_symlink(dir_ / "x_1.stl", dir_ / "alias.stl");
    AtomicFileSet set;
    set.add(dir_ / "x_1.stl", "piece");
    auto r = set.refuse_inputs({dir_ / "alias.stl"});
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().what.find("is the input"), std::string::npos);
    EXPECT_EQ(get(dir_ / "x_1.stl"), "bone");
}

TEST_F(FileIo, StaleFilesOfAnEarlierSetGoOnlyAfterTheNewSetIsInPlace) {
    put(dir_ / "p_3.txt", "old 3");
    AtomicFileSet set;
    set.add(dir_ / "p_1.txt", "1");
    set.add(dir_ / "p_2.txt", "2");
    set.remove_after_commit(dir_ / "p_3.txt");
    ASSERT_TRUE(set.commit());
    EXPECT_EQ(get(dir_ / "p_1.txt"), "1");
    EXPECT_EQ(get(dir_ / "p_2.txt"), "2");
    EXPECT_FALSE(fs::exists(dir_ / "p_3.txt"));
    EXPECT_EQ(entries(), 2u);
}

TEST_F(FileIo, AnUnwritableFolderLeavesNothingAndSaysSo) {
    auto r = write_file_atomically(dir_ / "missing-folder" / "a.txt", "x");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().what.find("cannot create a temporary file"), std::string::npos);
}

}  // namespace
}  // namespace kerf::files
