// ipc_test_peer — the other processes of the multi-process ipc tests, started by fork/exec from
// KERF_BIN_DIR. One role per run; each prints one line of `key=value` results on stdout and exits
// 0 when its own checks passed (nonzero says which check failed).
//
//   producer          --name N --journal-dir D --events E --per-tick K [--hold-ms H] [--lockstep]
//   [--read-mailbox] telemetry-producer --name N --journal-dir D --count C [--pace] [--hold-ms H]
//   consumer          --name N --out FILE --events E [--tolerant] [--max-ms T]
//   telemetry-consumer --name N --count C [--slow-every K]
//   scribbler         --name N --ms T --seed S
//   mesh-writer       --name N --ms T
//   truncator         --name N --producer-pid P --ms T   (every way to resize the segment; each
//                     must be refused: prints attempts= refused=; exit 4 if one succeeded)
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "config/base/main_guard.hpp"
#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/journal_writer.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/session_socket.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace {

using namespace kerf::ipc;

volatile sig_atomic_t g_stop = 0;

struct Args {
    std::map<std::string, std::string> kv;
    std::string get(const std::string& k, const std::string& d = "") const {
        auto it = kv.find(k);
        return it == kv.end() ? d : it->second;
    }
    std::uint64_t num(const std::string& k, std::uint64_t d = 0) const {
        auto it = kv.find(k);
        return it == kv.end() ? d : std::strtoull(it->second.c_str(), nullptr, 10);
    }
    bool flag(const std::string& k) const { return kv.count(k) != 0; }
};

void sleep_ns(std::uint64_t ns) {
    timespec ts{time_t(ns / 1'000'000'000u), long(ns % 1'000'000'000u)};
    nanosleep(&ts, nullptr);
}

// Sleeps until the next 1 ms tick boundary after `start + tick * 1 ms`.
void wait_tick(std::uint64_t start_ns, std::uint64_t tick) {
    const std::uint64_t target = start_ns + tick * 1'000'000u;
    const std::uint64_t now = monotonic_ns();
    if (target > now) sleep_ns(target - now);
}

int fail(const char* what) {
    std::printf("error=%s\n", what);
    std::fflush(stdout);
    return 3;
}

std::uint64_t percentile(std::vector<std::uint32_t>& v, double p) {
    if (v.empty()) return 0;
    const std::size_t k = std::min(v.size() - 1, std::size_t(p * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}

void hold(Producer& p, std::uint64_t hold_ms, std::uint64_t& tick) {
    const std::uint64_t until = monotonic_ns() + hold_ms * 1'000'000u;
    while (!g_stop && monotonic_ns() < until) {
        p.heartbeat(++tick, monotonic_ns());
        sleep_ns(1'000'000);
    }
}

// --lockstep: before each tick, waits (heart still beating) until the journal thread and every
// attached consumer are within half a queue of the producer, so a test whose point is
// correctness ("a consumer that keeps up gets everything") holds on a loaded machine where
// either may be descheduled for a second. Never used by kerf-rt: its loop drops and counts.
void wait_for_readers(Producer& p, std::uint64_t published, std::uint64_t per_tick,
                      std::uint64_t& tick) {
    const SegmentLayout& l = p.layout();
    const std::uint64_t give_up = monotonic_ns() + 60'000'000'000u;  // a dead reader: go on, lose
    while (monotonic_ns() < give_up) {
        bool behind =
            published + per_tick > l.journal_next_sequence.value.load() + kJournalQueueCapacity / 2;
        for (const ConsumerSlot& slot : l.slots) {
            if (slot.control.consumer_pid.load() == 0) continue;
            behind =
                behind || published + per_tick > slot.control.delivered.load() + kEventCapacity / 2;
        }
        if (!behind || g_stop) return;
        p.heartbeat(++tick, monotonic_ns());
        sleep_ns(1'000'000);
    }
}

int run_producer(const Args& a) {
    auto p = ProducerBuilder()
                 .segment_name(a.get("--name"))
                 .journal_dir(a.get("--journal-dir", ""))
                 .journal_flush_period_ns(5'000'000)
                 .create();
    if (!p) return std::printf("error=%s\n", p.error().message().c_str()), 2;
    const std::uint64_t events = a.num("--events"), per_tick = a.num("--per-tick", 10);
    std::optional<MeshMailboxReader> mailbox;
    std::unique_ptr<CollisionMesh> mesh;
    if (a.flag("--read-mailbox")) {
        mailbox.emplace(p->layout());
        mesh = std::make_unique<CollisionMesh>();
    }
    std::vector<std::uint32_t> push_ns;
    push_ns.reserve(events);
    std::uint64_t tick = 0, published = 0, meshes = 0;
    const std::uint64_t start = monotonic_ns();
    const bool lockstep = a.flag("--lockstep");
    while (published < events && !g_stop) {
        if (lockstep) wait_for_readers(*p, published, per_tick, tick);
        wait_tick(start, tick);
        p->heartbeat(++tick, monotonic_ns());
        for (std::uint64_t k = 0; k < per_tick && published < events; ++k, ++published) {
            EventRecord r = test::make_event(published);
            const std::uint64_t t0 = monotonic_ns();
            p->publish_event(r);
            push_ns.push_back(std::uint32_t(std::min<std::uint64_t>(monotonic_ns() - t0, ~0u)));
        }
        LatestState s{};
        s.tick = tick;
        s.tool_orientation_wxyz[0] = 1.0;
        p->publish_state(s);
        TelemetrySample t = test::make_sample(tick);
        p->publish_telemetry(t);
        if (mailbox && mailbox->try_take_newest(*mesh) == MailboxRead::kNew) ++meshes;
    }
    hold(*p, a.num("--hold-ms", 0), tick);
    p->stop();
    const std::uint64_t max_ns =
        push_ns.empty() ? 0 : *std::max_element(push_ns.begin(), push_ns.end());
    const std::uint64_t p50 = percentile(push_ns, 0.5), p999 = percentile(push_ns, 0.999);
    std::printf("published=%" PRIu64 " push_p50_ns=%" PRIu64 " push_p999_ns=%" PRIu64
                " push_max_ns=%" PRIu64 " events_dropped=%" PRIu64 " journal_dropped=%" PRIu64
                " meshes=%" PRIu64 " mesh_rejected=%" PRIu64 "\n",
                published, p50, p999, max_ns, p->layout().producer.events_dropped.load(),
                p->layout().journal_dropped.value.load(), meshes,
                mailbox ? mailbox->rejected() : 0);
    hold(*p, a.num("--linger-ms", 300), tick);  // consumers finish reading the rings
    return 0;
}

int run_telemetry_producer(const Args& a) {
    auto p = ProducerBuilder()
                 .segment_name(a.get("--name"))
                 .journal_dir(a.get("--journal-dir", ""))
                 .create();
    if (!p) return std::printf("error=%s\n", p.error().message().c_str()), 2;
    const std::uint64_t count = a.num("--count");
    const bool pace = a.flag("--pace");
    std::uint64_t tick = 0;
    p->heartbeat(tick, monotonic_ns());
    // Wait for the consumer to attach (the test starts it right after us).
    const std::uint64_t attach_deadline = monotonic_ns() + 10'000'000'000u;
    auto any_slot_active = [&] {
        for (const auto& s : p->layout().slots) {
            if ((s.control.claim_word.load() & 3u) == 2u) return true;
        }
        return false;
    };
    while (!any_slot_active() && monotonic_ns() < attach_deadline) hold(*p, 1, tick);
    for (std::uint64_t i = 0; i < count && !g_stop; ++i) {
        if (pace) {  // test-only backpressure: the real loop never does this
            for (;;) {
                bool roomy = true;
                for (const auto& s : p->layout().slots) {
                    const auto w =
                        s.telemetry_ring.write_index.value.load(std::memory_order_acquire);
                    const auto r =
                        s.telemetry_ring.read_index.value.load(std::memory_order_acquire);
                    if ((s.control.claim_word.load() & 3u) == 2u && w - r > kTelemetryCapacity / 2)
                        roomy = false;
                }
                if (roomy || g_stop) break;
                sched_yield();
            }
        }
        TelemetrySample t = test::make_sample(i);
        p->publish_telemetry(t);
        if ((i & 1023u) == 0) p->heartbeat(++tick, monotonic_ns());
    }
    p->stop();
    std::printf("published=%" PRIu64 " telemetry_dropped=%" PRIu64 "\n", count,
                p->layout().producer.telemetry_dropped.load());
    std::fflush(stdout);
    hold(*p, a.num("--hold-ms", 2000), tick);
    return 0;
}

int run_consumer(const Args& a) {
    const std::string out_path = a.get("--out");
    const int fd = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);
    if (fd < 0) return fail("open out");
    struct stat st {};
    fstat(fd, &st);
    const std::uint64_t from = std::uint64_t(st.st_size) / 16;  // resume after what we have
    const std::uint64_t events = a.num("--events");
    const bool tolerant = a.flag("--tolerant");
    std::optional<Consumer> c;
    const std::uint64_t deadline = monotonic_ns() + a.num("--max-ms", 60'000) * 1'000'000u;
    while (!c && monotonic_ns() < deadline) {
        auto attached = ConsumerBuilder()
                            .segment_name(a.get("--name"))
                            .from_sequence(from)
                            .telemetry(true)
                            .stale_after_ns(1'000'000'000)
                            .attach();
        if (attached)
            c.emplace(std::move(*attached));
        else
            sleep_ns(2'000'000);
    }
    if (!c) return fail("attach");
    std::uint64_t next = from, mismatches = 0, telemetry = 0, states = 0;
    EventRecord r;
    TelemetrySample t;
    LatestState s;
    while (next < events && monotonic_ns() < deadline && !g_stop) {
        while (c->try_next_telemetry(t) == Poll::kEvent) ++telemetry;
        if (c->try_read_state(s) == SeqlockRead::kOk) ++states;
        if (c->try_next(r) != Poll::kEvent) {
            if (c->producer_health() == ProducerHealth::kDead) break;
            if (tolerant && c->producer_health() == ProducerHealth::kStopped) break;
            sleep_ns(200'000);
            continue;
        }
        EventRecord want = test::make_event(r.header.sequence);
        want.header.sequence = r.header.sequence;
        stamp_checksum(want);
        if (r.header.sequence != next || std::memcmp(&want, &r, sizeof r) != 0) {
            ++mismatches;
            if (!tolerant) return fail("sequence or content mismatch");
        }
        next = r.header.sequence + 1;
        const std::uint64_t entry[2] = {r.header.sequence, r.header.checksum};
        if (::write(fd, entry, sizeof entry) != sizeof entry) return fail("write out");
    }
    const auto& st2 = c->stats();
    std::printf("delivered=%" PRIu64 " next=%" PRIu64 " from_journal=%" PRIu64 " lost=%" PRIu64
                " rejected_records=%" PRIu64 " rejected_indices=%" PRIu64 " mismatches=%" PRIu64
                " telemetry=%" PRIu64 " states=%" PRIu64 "\n",
                st2.delivered, next, st2.from_journal, st2.lost, st2.rejected_records,
                st2.rejected_indices, mismatches, telemetry, states);
    ::close(fd);
    return (tolerant || next >= events) ? 0 : fail("incomplete");
}

int run_telemetry_consumer(const Args& a) {
    auto c = ConsumerBuilder()
                 .segment_name(a.get("--name"))
                 .telemetry(true)
                 .stale_after_ns(2'000'000'000)
                 .attach();
    if (!c) return std::printf("error=%s\n", c.error().message().c_str()), 2;
    const std::uint64_t count = a.num("--count"), slow_every = a.num("--slow-every", 0);
    std::uint64_t received = 0, last = 0, bad = 0;
    TelemetrySample t;
    auto take = [&] {
        TelemetrySample want = test::make_sample(t.header.sequence);
        want.header.sequence = t.header.sequence;
        stamp_checksum(want);
        if (std::memcmp(&want, &t, sizeof t) != 0) ++bad;
        last = t.header.sequence;
        ++received;
    };
    while (received < count) {
        if (c->try_next_telemetry(t) == Poll::kEvent) {
            take();
            if (slow_every != 0 && received % slow_every == 0) sleep_ns(1'000'000);
            continue;
        }
        const ProducerHealth h = c->producer_health();
        if (h == ProducerHealth::kStopped || h == ProducerHealth::kDead) {
            while (c->try_next_telemetry(t) == Poll::kEvent) take();  // drain the rest
            break;
        }
        sched_yield();
    }
    const auto& ring = c->layout().slots[c->slot()].telemetry_ring;
    std::printf("received=%" PRIu64 " last=%" PRIu64 " gaps=%" PRIu64 " bad=%" PRIu64
                " slot_pushed=%" PRIu64 " slot_dropped=%" PRIu64 "\n",
                received, last, c->stats().telemetry_gaps, bad, ring.pushed_count.value.load(),
                ring.dropped_count.value.load());
    return bad == 0 ? 0 : fail("telemetry content mismatch");
}

int run_scribbler(const Args& a) {
    std::optional<ShmSegment> seg;
    const std::uint64_t deadline = monotonic_ns() + a.num("--ms", 1000) * 1'000'000u;
    while (!seg && monotonic_ns() < deadline) {
        auto s = SegmentBuilder().name(a.get("--name")).open();
        if (s)
            seg.emplace(std::move(*s));
        else
            sleep_ns(2'000'000);
    }
    if (!seg) return fail("open");
    auto* base = reinterpret_cast<unsigned char*>(&seg->layout());
    std::mt19937_64 rng(a.num("--seed", 1));
    // Regions: header+producer+journal counters+seqlock, each slot's control/rings/records,
    // the mailbox's latest word and buffer headers/indices.
    struct Region {
        std::size_t offset, bytes;
    };
    std::vector<Region> regions = {{0, offsetof(SegmentLayout, slots)}};
    for (std::uint32_t i = 0; i < kSlotCount; ++i) {
        const std::size_t slot = offsetof(SegmentLayout, slots) + i * sizeof(ConsumerSlot);
        regions.push_back({slot, 576});                                    // control + ring indices
        regions.push_back({slot + 576, 128 * 64});                         // first event records
        regions.push_back({slot + 576 + 128 * kEventCapacity, 128 * 64});  // telemetry records
    }
    const std::size_t mbox = offsetof(SegmentLayout, mailbox);
    regions.push_back({mbox, 64 + 64 + sizeof(MeshBufferHeader)});
    regions.push_back(
        {mbox + offsetof(MeshMailbox, buffers) + offsetof(MeshBuffer, indices), 4096});
    regions.push_back({mbox + offsetof(MeshMailbox, buffers) + sizeof(MeshBuffer),
                       64 + sizeof(MeshBufferHeader)});
    std::uint64_t writes = 0;
    while (monotonic_ns() < deadline && !g_stop) {
        const Region& r = regions[rng() % regions.size()];
        const std::size_t at = r.offset + rng() % r.bytes;
        const std::size_t n = 1 + rng() % 8;
        for (std::size_t k = 0; k < n && at + k < sizeof(SegmentLayout); ++k) {
            __atomic_store_n(base + at + k, static_cast<unsigned char>(rng()), __ATOMIC_RELAXED);
        }
        ++writes;
        if ((writes & 63u) == 0) sleep_ns(50'000);
    }
    std::printf("writes=%" PRIu64 "\n", writes);
    return 0;
}

int run_mesh_writer(const Args& a) {
    std::optional<ShmSegment> seg;
    const std::uint64_t deadline = monotonic_ns() + a.num("--ms", 1000) * 1'000'000u;
    while (!seg && monotonic_ns() < deadline) {
        auto s = SegmentBuilder().name(a.get("--name")).open();
        if (s)
            seg.emplace(std::move(*s));
        else
            sleep_ns(2'000'000);
    }
    if (!seg) return fail("open");
    MeshMailboxWriter w(seg->layout());
    auto m = std::make_unique<CollisionMesh>();
    m->body_count = 1;
    m->vertex_count = 300;
    m->index_count = 3 * 298;
    m->bodies[0] =
        MeshBodyEntry{0, 300, 0, 3 * 298, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    for (std::uint32_t v = 0; v < 900; ++v) m->vertices_m[v] = 0.0001f * float(v);
    for (std::uint32_t t = 0; t < 298; ++t) {
        m->indices[3 * t] = 0;
        m->indices[3 * t + 1] = t + 1;
        m->indices[3 * t + 2] = t + 2;
    }
    std::uint64_t published = 0;
    while (monotonic_ns() < deadline && !g_stop) {
        if (w.publish(*m)) ++published;
        sleep_ns(2'000'000);
    }
    std::printf("meshes_published=%" PRIu64 "\n", published);
    return 0;
}

// Tries to resize the live segment every way an attacker sharing the session could: through the
// descriptor the producer serves, and through the producer's own descriptors in /proc.
int run_truncator(const Args& a) {
    const std::uint64_t deadline = monotonic_ns() + a.num("--ms", 500) * 1'000'000u;
    std::uint64_t attempts = 0, refused = 0, succeeded = 0;
    auto attempt = [&](bool ok) {
        ++attempts;
        ok ? ++succeeded : ++refused;
    };
    const std::string proc = "/proc/" + a.get("--producer-pid") + "/fd";
    while (monotonic_ns() < deadline && !g_stop) {
        auto fds = fetch_session(default_runtime_dir(), a.get("--name"));
        if (!fds) return fail("fetch_session");
        const int fd = fds->segment_fd;
        for (off_t size : {off_t(0), off_t(4096), off_t(sizeof(SegmentLayout) / 2),
                           off_t(2 * sizeof(SegmentLayout))}) {
            attempt(ftruncate(fd, size) == 0);
        }
        attempt(fallocate(fd, 0, 0, off_t(2 * sizeof(SegmentLayout))) == 0);
        close(fd);
        if (fds->journal_fd >= 0) close(fds->journal_fd);
        // truncate(1) on the producer's descriptors through /proc (the path a shell would use).
        if (DIR* d = opendir(proc.c_str())) {
            while (dirent* e = readdir(d)) {
                const std::string path = proc + "/" + e->d_name;
                char target[256] = {};
                if (readlink(path.c_str(), target, sizeof target - 1) <= 0) continue;
                if (std::strncmp(target, "/memfd:kerf:", 12) != 0) continue;
                attempt(truncate(path.c_str(), 0) == 0);
                const int rw = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
                if (rw >= 0) {
                    attempt(ftruncate(rw, 0) == 0);
                    close(rw);
                }
            }
            closedir(d);
        }
        sleep_ns(5'000'000);
    }
    std::printf("attempts=%" PRIu64 " refused=%" PRIu64 " succeeded=%" PRIu64 "\n", attempts,
                refused, succeeded);
    return succeeded == 0 ? 0 : 4;
}

}  // namespace

static int program_main(int argc, char** argv) {
    if (argc < 2) return std::fprintf(stderr, "usage: ipc_test_peer <role> [--key value]...\n"), 2;
    signal(SIGTERM, [](int) { g_stop = 1; });
    Args a;
    for (int i = 2; i < argc; ++i) {
        std::string k = argv[i];
        if (i + 1 < argc && std::strncmp(argv[i + 1], "--", 2) != 0)
            a.kv[k] = argv[++i];
        else
            a.kv[k] = "1";
    }
    const std::string role = argv[1];
    setvbuf(stdout, nullptr, _IOLBF, 0);
    spdlog::set_default_logger(spdlog::stderr_logger_st("ipc_test_peer"));  // stdout = results
    if (role == "producer") return run_producer(a);
    if (role == "telemetry-producer") return run_telemetry_producer(a);
    if (role == "consumer") return run_consumer(a);
    if (role == "telemetry-consumer") return run_telemetry_consumer(a);
    if (role == "scribbler") return run_scribbler(a);
    if (role == "mesh-writer") return run_mesh_writer(a);
    if (role == "truncator") return run_truncator(a);
    return std::fprintf(stderr, "ipc_test_peer: unknown role '%s'\n", role.c_str()), 2;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("ipc_test_peer", [&] { return program_main(argc, argv); });
}
