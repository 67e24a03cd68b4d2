// Multi-process tests: real processes (ipc_test_peer, fork/exec from KERF_BIN_DIR) on a real
// POSIX shared-memory segment and journal. Label `integration`.
#include <fcntl.h>
#include <grp.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/session_socket.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

#ifdef KERF_SANITIZED
constexpr std::uint64_t kScale = 10;
#else
constexpr std::uint64_t kScale = 1;
#endif

/// A child process running ipc_test_peer with stdout captured to a file.
class Peer {
public:
    /// Runs `program` (a file in KERF_BIN_DIR: ipc_test_peer, or kerf itself) with `args`.
    Peer(const std::string& out_dir, const std::vector<std::string>& args,
         const std::string& program = "ipc_test_peer") {
        static int n = 0;
        stdout_path_ = out_dir + "/peer-" + std::to_string(n++) + ".out";
        pid_ = fork();
        if (pid_ == 0) {
            const int fd = ::open(stdout_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
            dup2(fd, 1);
            std::vector<char*> argv;
            std::string exe = std::string(KERF_BIN_DIR) + "/" + program;
            argv.push_back(exe.data());
            std::vector<std::string> copy = args;
            for (auto& a : copy) argv.push_back(a.data());
            argv.push_back(nullptr);
            execv(exe.c_str(), argv.data());
            _exit(127);
        }
    }
    ~Peer() {
        if (pid_ > 0 && !reaped_) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
    }
    pid_t pid() const { return pid_; }
    /// Waits for exit; returns the exit code (128+signal if killed).
    int wait() {
        int status = 0;
        waitpid(pid_, &status, 0);
        reaped_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    void kill_now(int sig = SIGKILL) { kill(pid_, sig); }
    std::string output() const {
        std::ifstream f(stdout_path_);
        std::stringstream ss;
        ss << f.rdbuf();
        return ss.str();
    }
    /// key=value pairs from the last line.
    std::map<std::string, std::uint64_t> values() const {
        std::map<std::string, std::uint64_t> out;
        std::istringstream in(output());
        std::string tok;
        while (in >> tok) {
            const auto eq = tok.find('=');
            if (eq != std::string::npos)
                out[tok.substr(0, eq)] = std::strtoull(tok.c_str() + eq + 1, nullptr, 10);
        }
        return out;
    }

private:
    pid_t pid_ = -1;
    bool reaped_ = false;
    std::string stdout_path_;
};

bool wait_for_segment(const std::string& name, int ms = 10'000) {
    for (int i = 0; i < ms / 2; ++i) {
        auto s = SegmentBuilder().name(name).open();
        if (s && s->layout().header.state.load() == std::uint32_t(SegmentState::kRunning))
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
}

/// Checks that `path` holds (seq, checksum) entries for 0..n-1 matching make_event.
void expect_identical_sequence(const std::string& path, std::uint64_t n) {
    std::ifstream g(path, std::ios::binary);
    std::uint64_t e[2];
    std::uint64_t i = 0;
    while (g.read(reinterpret_cast<char*>(e), sizeof e)) {
        ASSERT_EQ(e[0], i) << "entry " << i;
        EventRecord want = test::make_event(i);
        want.header.sequence = i;
        stamp_checksum(want);
        ASSERT_EQ(e[1], want.header.checksum) << "entry " << i;
        ++i;
    }
    EXPECT_EQ(i, n);
}

TEST(MultiProcess, ConsumerThatKeepsUpGetsEveryEventIdentically) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("mp");
    const std::uint64_t n = 100'000 / kScale;
    // Lockstep: the producer waits for the journal thread and the consumer whenever either is
    // half a queue behind (a loaded 2-core machine deschedules them for a second at times); the
    // point here is that nothing is lost or reordered, not the pace.
    Peer producer(dir.path,
                  {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                   std::to_string(n), "--per-tick", "50", "--hold-ms", "100", "--lockstep"});
    ASSERT_TRUE(wait_for_segment(name));
    Peer consumer(dir.path, {"consumer", "--name", name, "--out", dir.path + "/seq.bin", "--events",
                             std::to_string(n)});
    ASSERT_EQ(consumer.wait(), 0) << consumer.output();
    ASSERT_EQ(producer.wait(), 0) << producer.output();
    expect_identical_sequence(dir.path + "/seq.bin", n);
    const auto p = producer.values();
    const auto c = consumer.values();
    EXPECT_EQ(p.at("journal_dropped"), 0u);
    EXPECT_EQ(c.at("lost"), 0u);
    EXPECT_EQ(c.at("rejected_records"), 0u);
    // Push cost: reported only (figures belong to bench_ipc, never to a test's verdict).
    std::printf("producer push p50 %llu ns, p99.9 %llu ns, max %llu ns over %llu events\n",
                (unsigned long long)p.at("push_p50_ns"), (unsigned long long)p.at("push_p999_ns"),
                (unsigned long long)p.at("push_max_ns"), (unsigned long long)n);
}

TEST(MultiProcess, ConsumerKilledAtRandomMomentsReconstructsTheIdenticalSequence) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("kill");
    const std::uint64_t n = 60'000;  // not scaled: the producer must outlive ~8 kills (3 s)
    Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                             std::to_string(n), "--per-tick", "20", "--hold-ms", "20000"});
    ASSERT_TRUE(wait_for_segment(name));
    const std::string out = dir.path + "/seq.bin";
    std::mt19937 rng(12345);
    int kills = 0;
    for (;;) {
        Peer consumer(dir.path,
                      {"consumer", "--name", name, "--out", out, "--events", std::to_string(n)});
        if (kills < 8) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50 + rng() % 250));
            consumer.kill_now(SIGKILL);
            const int code = consumer.wait();
            if (code == 0) break;  // finished before the kill
            ASSERT_EQ(code, 128 + SIGKILL) << consumer.output();
            ++kills;
            // A kill can land mid-write of an entry: drop a torn tail, as a real consumer would.
            struct stat st {};
            ASSERT_EQ(stat(out.c_str(), &st), 0);
            ASSERT_EQ(truncate(out.c_str(), st.st_size - st.st_size % 16), 0);
            continue;
        }
        ASSERT_EQ(consumer.wait(), 0) << consumer.output();
        break;
    }
    producer.kill_now(SIGTERM);
    ASSERT_EQ(producer.wait(), 0);
    std::printf("consumer SIGKILLed %d times\n", kills);
    EXPECT_GE(kills, 3);
    expect_identical_sequence(out, n);
}

TEST(MultiProcess, ConsumerDetectsAKilledOrStoppedProducerThroughItsHeartbeat) {
    for (int sig : {SIGKILL, SIGSTOP}) {
        test::ScratchDir dir;
        const auto name = test::unique_segment_name("hb");
        Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                                 "100000000", "--per-tick", "1"});
        ASSERT_TRUE(wait_for_segment(name));
        // The producer's first ticks can come late on a loaded machine (it looks stale until
        // then): attach once it is ticking.
        auto c =
            ConsumerBuilder().segment_name(name).from_sequence(ConsumerBuilder::kFromNow).attach();
        for (int i = 0; i < 2500 && !c; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            c = ConsumerBuilder()
                    .segment_name(name)
                    .from_sequence(ConsumerBuilder::kFromNow)
                    .attach();
        }
        ASSERT_TRUE(c) << c.error().message();
        // Alive before the kill (a loaded machine may pause the producer past 40 ms: wait for
        // a fresh beat rather than asserting on one moment).
        bool alive = false;
        for (int i = 0; i < 2500 && !alive; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            alive = c->producer_health() == ProducerHealth::kAlive;
        }
        ASSERT_TRUE(alive);
        const auto t0 = std::chrono::steady_clock::now();
        producer.kill_now(sig);
        ProducerHealth h = ProducerHealth::kAlive;
        while (h == ProducerHealth::kAlive &&
               std::chrono::steady_clock::now() - t0 < std::chrono::seconds(2)) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            h = c->producer_health();
        }
        const auto ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        std::printf("signal %d: producer reported %s after %.1f ms\n", sig,
                    std::string(to_string(h)).c_str(), ms);
        // Detected (within the 2 s bound of the loop above). How soon is printed, not asserted:
        // it is the 40 ms staleness limit plus however long a loaded machine paused this test.
        EXPECT_NE(h, ProducerHealth::kAlive);
        if (sig == SIGSTOP) {
            EXPECT_EQ(h, ProducerHealth::kStale);
            producer.kill_now(SIGKILL);
        }
        producer.wait();
        remove_stale_socket(default_runtime_dir(), name);  // a killed producer leaves its socket
    }
}

struct TelemetryRun {
    std::map<std::string, std::uint64_t> producer, consumer;
};

TelemetryRun run_telemetry(std::uint64_t count, bool pace, std::uint64_t slow_every) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("tel");
    std::vector<std::string> pargs = {"telemetry-producer", "--name", name,
                                      "--journal-dir",      dir.path, "--count",
                                      std::to_string(count)};
    if (pace) pargs.push_back("--pace");
    Peer producer(dir.path, pargs);
    EXPECT_TRUE(wait_for_segment(name));
    Peer consumer(dir.path, {"telemetry-consumer", "--name", name, "--count", std::to_string(count),
                             "--slow-every", std::to_string(slow_every)});
    EXPECT_EQ(consumer.wait(), 0) << consumer.output();
    producer.kill_now(SIGTERM);
    EXPECT_EQ(producer.wait(), 0) << producer.output();
    return {producer.values(), consumer.values()};
}

TEST(MultiProcess, MillionRecordsWithChecksumsAndZeroLossWhenTheConsumerKeepsUp) {
    const std::uint64_t n = 1'000'000 / kScale;
    const auto t0 = std::chrono::steady_clock::now();
    const TelemetryRun r = run_telemetry(n, true, 0);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.consumer.at("received"), n);
    EXPECT_EQ(r.consumer.at("bad"), 0u);
    EXPECT_EQ(r.consumer.at("gaps"), 0u);
    EXPECT_EQ(r.producer.at("telemetry_dropped"), 0u);
    std::printf("%llu records in %.2f s (%.1f M/s incl. process start)\n", (unsigned long long)n, s,
                double(n) / s / 1e6);
}

TEST(MultiProcess, DISABLED_HundredMillionRecordsWithChecksumsAndZeroLoss) {  // label manual
    const std::uint64_t n = 100'000'000;
    const TelemetryRun r = run_telemetry(n, true, 0);
    EXPECT_EQ(r.consumer.at("received"), n);
    EXPECT_EQ(r.consumer.at("bad"), 0u);
    EXPECT_EQ(r.consumer.at("gaps"), 0u);
    EXPECT_EQ(r.producer.at("telemetry_dropped"), 0u);
}

TEST(MultiProcess, SlowConsumerDropsAreAccountedExactly) {
    const std::uint64_t n = 200'000 / kScale;
    const TelemetryRun r = run_telemetry(n, false, 500);
    const auto received = r.consumer.at("received");
    const auto dropped = r.consumer.at("slot_dropped");
    const auto trailing = n - 1 - r.consumer.at("last");  // dropped after the last one received
    std::printf("received %llu, dropped %llu (gaps %llu + trailing %llu)\n",
                (unsigned long long)received, (unsigned long long)dropped,
                (unsigned long long)r.consumer.at("gaps"), (unsigned long long)trailing);
    EXPECT_GT(dropped, 0u);
    EXPECT_EQ(received + dropped, n);
    EXPECT_EQ(r.consumer.at("slot_pushed"), received);
    EXPECT_EQ(r.consumer.at("gaps") + trailing, dropped);
    EXPECT_EQ(r.producer.at("telemetry_dropped"), dropped);
    EXPECT_EQ(r.consumer.at("bad"), 0u);
}

TEST(MultiProcess, ScribblerOverHeaderRingsAndMailboxCausesCountedRejectionsNeverACrash) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("scrib");
    const std::uint64_t n = 3000;
    Peer producer(dir.path,
                  {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                   std::to_string(n), "--per-tick", "2", "--read-mailbox", "--linger-ms", "200"});
    ASSERT_TRUE(wait_for_segment(name));
    Peer c1(dir.path, {"consumer", "--name", name, "--out", dir.path + "/a.bin", "--events",
                       std::to_string(n), "--tolerant", "--max-ms", "20000"});
    Peer c2(dir.path, {"consumer", "--name", name, "--out", dir.path + "/b.bin", "--events",
                       std::to_string(n), "--tolerant", "--max-ms", "20000"});
    Peer mesh(dir.path, {"mesh-writer", "--name", name, "--ms", "1500"});
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    Peer scribbler(dir.path, {"scribbler", "--name", name, "--ms", "1200", "--seed", "7"});
    EXPECT_EQ(scribbler.wait(), 0) << scribbler.output();
    EXPECT_EQ(mesh.wait(), 0) << mesh.output();
    const int pc = producer.wait();
    const int r1 = c1.wait(), r2 = c2.wait();
    EXPECT_EQ(pc, 0) << producer.output();  // exit codes >= 128 would be a crash (signal)
    EXPECT_EQ(r1, 0) << c1.output();
    EXPECT_EQ(r2, 0) << c2.output();
    auto p = producer.values(), a = c1.values(), b = c2.values();
    const auto rejections = a["rejected_records"] + a["rejected_indices"] + b["rejected_records"] +
                            b["rejected_indices"] + p["mesh_rejected"];
    std::printf("scribbler writes %s; producer: %s; consumers:\n  %s  %s",
                scribbler.output().c_str(), producer.output().c_str(), c1.output().c_str(),
                c2.output().c_str());
    EXPECT_GT(rejections, 0u);
}

// Issue 9 item 3: `truncate -s 0` on a live segment killed the producer and `kerf shm tail` with
// SIGBUS. The segment is now a sealed memfd served over the session socket: an adversary sharing
// the session tries every resize it can reach, and both keep working.
TEST(MultiProcess, NoProcessSharingTheSessionCanResizeTheSegmentUnderProducerOrTail) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("trunc");
    const std::uint64_t n = 1500;
    Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                             std::to_string(n), "--per-tick", "1", "--hold-ms", "300"});
    ASSERT_TRUE(wait_for_segment(name));
    Peer tail(dir.path, {"shm", "tail", name, "--from", "0", "--count", std::to_string(n)}, "kerf");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    Peer adversary(dir.path, {"truncator", "--name", name, "--producer-pid",
                              std::to_string(producer.pid()), "--ms", "600"});
    EXPECT_EQ(adversary.wait(), 0) << adversary.output();
    const auto a = adversary.values();
    EXPECT_GT(a.at("attempts"), 10u);
    EXPECT_EQ(a.at("refused"), a.at("attempts"));
    EXPECT_EQ(tail.wait(), 0) << tail.output();  // 135 would be SIGBUS
    EXPECT_EQ(producer.wait(), 0) << producer.output();
    const std::string out = tail.output();
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), std::ptrdiff_t(n)) << out;
    EXPECT_NE(out.find("\n" + std::to_string(n - 1) + " "), std::string::npos);
    // Only a socket (and the journal folder) exist; /dev/shm holds no file for the session.
    struct stat st {};
    EXPECT_NE(stat(("/dev/shm/" + name).c_str(), &st), 0);
    std::printf("adversary: %s", adversary.output().c_str());
}

/// Runs `body` in a forked child that has become `nobody` (uid/gid 65534, no supplementary
/// groups); returns the child's exit code, or -1 when the identity could not be changed.
template <class Body>
int as_nobody(Body body) {
    const pid_t pid = fork();
    if (pid == 0) {
        if (setgroups(0, nullptr) != 0 || setresgid(65534, 65534, 65534) != 0 ||
            setresuid(65534, 65534, 65534) != 0) {
            _exit(255);
        }
        _exit(body());
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) == 255) return -1;
    return WEXITSTATUS(status);
}

// Issue 9, item 6: another user on the machine can neither attach to a session (`kerf shm tail`
// run as nobody against root's runtime folder) nor reach the producer's descriptors to resize or
// write the segment; the producer and its consumers carry on. Needs root (CI runs as root).
TEST(MultiProcess, AnotherUserCanNeitherAttachToNorTamperWithASession) {
    if (geteuid() != 0) GTEST_SKIP() << "changing to another user needs root";
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("foreign");
    const std::uint64_t n = 200;
    Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                             std::to_string(n), "--per-tick", "1", "--hold-ms", "30000"});
    ASSERT_TRUE(wait_for_segment(name));
    const std::string runtime = default_runtime_dir();
    const std::string socket = session_socket_of(runtime, name);
    const std::string out = dir.path + "/nobody.out";
    ASSERT_EQ(chmod(dir.path.c_str(), 0777), 0);  // so nobody can write its output there

    // Attach as a user would: the real `kerf shm tail`, pointed at root's runtime folder.
    const int tail = as_nobody([&] {
        setenv("KERF_RUNTIME_DIR", runtime.c_str(), 1);
        const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
        dup2(fd, 1);
        dup2(fd, 2);
        std::string exe = std::string(KERF_BIN_DIR) + "/kerf";
        std::vector<std::string> args = {exe, "shm", "tail", name, "--from", "0", "--count", "1"};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        execv(exe.c_str(), argv.data());
        return 127;
    });
    ASSERT_NE(tail, -1) << "could not become nobody";
    std::ifstream f(out);
    const std::string said((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_EQ(tail, 1) << said;
    EXPECT_NE(said.find(name), std::string::npos) << said;
    EXPECT_EQ(said.find("cut_begin"), std::string::npos) << said;  // no event reached nobody

    // Tamper: every descriptor of the producer (the memfd, the journal) and the socket itself.
    const int reached = as_nobody([&] {
        int opened = 0;
        for (int fd = 0; fd < 256; ++fd) {
            const std::string p =
                "/proc/" + std::to_string(producer.pid()) + "/fd/" + std::to_string(fd);
            const int h = ::open(p.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
            if (h >= 0) {
                ++opened;
                (void)ftruncate(h, 0);
                ::close(h);
            }
        }
        const int c = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", socket.c_str());
        if (::connect(c, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) ++opened;
        return opened;
    });
    EXPECT_EQ(reached, 0) << "nobody opened " << reached << " of root's session descriptors";

    // Root's own consumer still gets every event; the producer ends cleanly.
    Peer consumer(dir.path, {"consumer", "--name", name, "--out", dir.path + "/c.bin", "--events",
                             std::to_string(n), "--max-ms", "20000"});
    EXPECT_EQ(consumer.wait(), 0) << consumer.output();
    producer.kill_now(SIGTERM);  // it holds the session open until told
    EXPECT_EQ(producer.wait(), 0) << producer.output();
}

std::string run_kerf(const std::string& args, int& exit_code) {
    const std::string cmd = std::string(KERF_BIN_DIR) + "/kerf " + args + " 2>&1";
    FILE* f = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    while (f != nullptr && std::fgets(buf, sizeof buf, f) != nullptr) out += buf;
    const int status = f != nullptr ? pclose(f) : -1;
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

TEST(KerfShmCommand, LsStatsAndTailShowALiveSession) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("cli");
    Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                             "100", "--per-tick", "10", "--hold-ms", "30000"});
    ASSERT_TRUE(wait_for_segment(name));
    int code = -1;
    std::string out = run_kerf("shm tail " + name + " --from 0 --count 5", code);
    EXPECT_EQ(code, 0) << out;
    EXPECT_NE(out.find("cut_begin"), std::string::npos) << out;
    EXPECT_NE(out.find("\n4 "), std::string::npos) << out;  // sequence 4 came (from the journal)
    out = run_kerf("shm ls", code);
    EXPECT_EQ(code, 0) << out;
    EXPECT_NE(out.find(name), std::string::npos) << out;
    // "alive" means a heartbeat within the last 40 ms. On a loaded machine the producer (which
    // beats every millisecond) can be descheduled for longer than that, so a reading of "stale"
    // is retried, for as long as the producer holds the session; every reading must show it.
    const std::uint64_t give_up = monotonic_ns() + 20'000'000'000ull;
    bool alive = false;
    int readings = 0;
    while (!alive && monotonic_ns() < give_up) {
        out = run_kerf("shm stats " + name + " --json", code);
        ++readings;
        ASSERT_EQ(code, 0) << out;
        const auto stats = nlohmann::json::parse(out);
        EXPECT_EQ(stats["name"], name);
        EXPECT_EQ(stats["events"], 100);
        ASSERT_TRUE(stats["health"] == "alive" || stats["health"] == "stale") << out;
        alive = stats["health"] == "alive";
    }
    EXPECT_TRUE(alive) << readings << " readings over 20 s all found the producer stale:\n" << out;
    producer.kill_now(SIGTERM);
    EXPECT_EQ(producer.wait(), 0);
}

// Issue 9 items 9 and 10: any session name is listed (not only kerf.*), and every --json output
// parses as JSON with nothing else on stdout (logs go to stderr).
TEST(KerfShmCommand, JsonOutputsParseAndAnyNameIsListed) {
    test::ScratchDir dir;
    const std::string name = "plain-" + std::to_string(getpid());  // no "kerf." prefix
    Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", dir.path, "--events",
                             "50", "--per-tick", "5", "--hold-ms", "5000"});
    ASSERT_TRUE(wait_for_segment(name));
    const auto stdout_of = [&](const std::string& args) {
        int code = -1;
        const std::string out = run_kerf(args + " 2>/dev/null", code);
        EXPECT_EQ(code, 0) << args;
        return out;
    };
    const auto ls = nlohmann::json::parse(stdout_of("shm ls --json"));
    bool listed = false;
    for (const auto& row : ls) listed = listed || row["name"] == name;
    EXPECT_TRUE(listed) << ls.dump();
    const auto stats = nlohmann::json::parse(stdout_of("shm stats " + name + " --json"));
    EXPECT_EQ(stats["health"], "alive");
    std::istringstream lines(stdout_of("shm tail " + name + " --from 0 --count 10 --json"));
    std::string line;
    int events = 0;
    while (std::getline(lines, line)) {
        const auto event = nlohmann::json::parse(line);
        EXPECT_EQ(event["sequence"], events);
        ++events;
    }
    EXPECT_EQ(events, 10);
    producer.kill_now(SIGTERM);
    EXPECT_EQ(producer.wait(), 0);
}

// Issue 9, item 7: a string in the segment (here the journal path, which the producer copies
// from its journal folder's name) full of escape sequences reaches the terminal as visible \xNN
// escapes, never as raw control bytes; --json carries it exactly, JSON-escaped.
TEST(KerfShmCommand, HostileStringsFromTheSegmentArePrintedEscaped) {
    test::ScratchDir dir;
    const std::string hostile = dir.path + "/j\x1b]0;pwned\x07\x1b[2J";
    ASSERT_EQ(mkdir(hostile.c_str(), 0700), 0);
    const auto name = test::unique_segment_name("hostile");
    Peer producer(dir.path, {"producer", "--name", name, "--journal-dir", hostile, "--events", "20",
                             "--per-tick", "5", "--hold-ms", "30000"});
    ASSERT_TRUE(wait_for_segment(name));
    int code = -1;
    const std::string text = run_kerf("shm stats " + name, code);
    EXPECT_EQ(code, 0) << text;
    EXPECT_EQ(text.find('\x1b'), std::string::npos) << text;
    EXPECT_EQ(text.find('\x07'), std::string::npos) << text;
    EXPECT_NE(text.find("j\\x1b]0;pwned\\x07\\x1b[2J"), std::string::npos) << text;
    const std::string json = run_kerf("shm stats " + name + " --json 2>/dev/null", code);
    EXPECT_EQ(code, 0) << json;
    EXPECT_EQ(json.find('\x1b'), std::string::npos) << json;
    const auto doc = nlohmann::json::parse(json);
    EXPECT_NE(doc["journal"].get<std::string>().find("pwned"), std::string::npos) << json;
    producer.kill_now(SIGTERM);
    EXPECT_EQ(producer.wait(), 0) << producer.output();
}

TEST(KerfShmCommand, MissingSessionIsAClearErrorWithExitCode1) {
    int code = -1;
    const std::string out = run_kerf("shm stats kerf.no-such-session", code);
    EXPECT_EQ(code, 1);
    EXPECT_NE(out.find("kerf shm stats: cannot open segment: session kerf.no-such-session: no such "
                       "session"),
              std::string::npos)
        << out;
    const std::string bad = run_kerf("shm tail 'bad/name'", code);
    EXPECT_EQ(code, 1);
    EXPECT_NE(bad.find("invalid"), std::string::npos) << bad;
}

}  // namespace
}  // namespace kerf::ipc
