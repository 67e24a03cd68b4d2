// In-process concurrency: one producer thread, consumer threads, no sleeps on the producer side.
// Labelled `concurrent` so the ThreadSanitizer CI build runs exactly these.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>
#include <thread>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/seqlock.hpp"
#include "rt_core/ipc/shm_segment.hpp"
#include "rt_core/ipc/spsc_ring.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace kerf::ipc {
namespace {

#ifdef KERF_SANITIZED
constexpr std::uint64_t kScale = 10;  // sanitizers are ~10x slower
#else
constexpr std::uint64_t kScale = 1;
#endif

struct Rec64 {
    std::uint64_t seq;
    std::uint64_t payload[6];
    std::uint64_t check;
};

TEST(ConcurrentRing, TwoThreadsPassAMillionRecordsWithoutLossOrCorruption) {
    constexpr std::uint32_t kCap = 1024;
    const std::uint64_t n = 1'000'000 / kScale;
    auto control = std::make_unique<RingControl>();
    auto slots = std::make_unique<Rec64[]>(kCap);
    SpscConsumerEnd<Rec64, kCap> consumer(control.get(), slots.get());
    std::thread producer_thread([&] {
        SpscProducerEnd<Rec64, kCap> producer(control.get(), slots.get());
        for (std::uint64_t i = 0; i < n;) {
            Rec64 r{i, {i, i * 3, i ^ 0x55, i + 7, i * i, ~i}, i * 0x9E3779B97F4A7C15ull};
            if (producer.try_push(r))
                ++i;  // test harness retries; the ring itself never waits
            else
                std::this_thread::yield();
        }
    });
    std::uint64_t expected = 0;
    Rec64 out{};
    while (expected < n) {
        if (consumer.try_pop(out) != PopResult::kOk) {
            std::this_thread::yield();
            continue;
        }
        ASSERT_EQ(out.seq, expected);
        ASSERT_EQ(out.check, expected * 0x9E3779B97F4A7C15ull);
        ASSERT_EQ(out.payload[4], expected * expected);
        ++expected;
    }
    producer_thread.join();
    EXPECT_EQ(control->pushed_count.value.load(), n);  // every record stored exactly once
    // dropped_count counts the harness's refused attempts (full ring), retried above.
}

TEST(ConcurrentSeqlock, ReadersNeverSeeATornValue) {
    auto cell = std::make_unique<SeqlockCell<LatestState>>();
    std::atomic<bool> done{false};
    std::atomic<std::uint64_t> reads{0};
    // The writer goes on until the reader has had its share of successful reads, however the
    // scheduler treats the two threads (on a loaded 2-core machine the writer can otherwise
    // finish before the reader first runs).
    constexpr std::uint64_t kMinWrites = 200'000 / kScale, kMinReads = 1'000;
    std::thread writer([&] {
        LatestState s{};
        for (std::uint64_t t = 1;
             t <= kMinWrites || (reads.load() < kMinReads && t <= 1000 * kMinWrites); ++t) {
            s.tick = t;
            s.time_ns = t * 1000;
            for (int k = 0; k < 3; ++k) s.force_n[k] = double(t) + k;
            s.compute_ns_max = std::uint32_t(t);
            seqlock_write(*cell, s);
            if (t % 4096 == 0) std::this_thread::yield();
        }
        done.store(true);
    });
    std::uint64_t last_tick = 0;
    LatestState out{};
    while (!done.load()) {
        if (try_seqlock_read(*cell, out) != SeqlockRead::kOk) continue;
        reads.fetch_add(1);
        ASSERT_EQ(out.time_ns, out.tick * 1000);
        ASSERT_EQ(out.force_n[2], double(out.tick) + 2);
        ASSERT_EQ(out.compute_ns_max, std::uint32_t(out.tick));
        ASSERT_GE(out.tick, last_tick);
        last_tick = out.tick;
    }
    writer.join();
    EXPECT_GE(reads.load(), kMinReads);
}

TEST(ConcurrentSession, ConsumersOnThreadsSeeTheIdenticalSequenceDespiteDrops) {
    test::ScratchDir dir;
    const auto name = test::unique_segment_name("conc");
    auto producer = ProducerBuilder()
                        .segment_name(name)
                        .journal_dir(dir.path)
                        .journal_flush_period_ns(2'000'000)
                        .create();
    ASSERT_TRUE(producer) << producer.error().message();
    producer->heartbeat(0, monotonic_ns());
    const std::uint64_t n = 40'000 / kScale;
    std::atomic<int> attach_tries{0};
    auto run_consumer = [&](bool slow, std::uint64_t& drops_seen, bool& ok) {
        // A heartbeat limit fit for a loaded machine: this thread may first run long after the
        // producer's last beat.
        auto c = ConsumerBuilder()
                     .segment_name(name)
                     .telemetry(true)
                     .stale_after_ns(test::kLoadedMachineStaleAfter_ns)
                     .attach();
        ok = bool(c);
        attach_tries.fetch_add(1);
        if (!c) return;
        EventRecord r;
        std::uint64_t got = 0;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (got < n && std::chrono::steady_clock::now() < deadline) {
            if (c->try_next(r) != Poll::kEvent) {
                std::this_thread::sleep_for(std::chrono::microseconds(100));
                continue;
            }
            EventRecord want = test::make_event(got);
            want.header.sequence = got;
            stamp_checksum(want);
            if (std::memcmp(&want, &r, sizeof r) != 0) {
                ok = false;
                return;
            }
            ++got;
            if (slow && got % 2000 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        ok = ok && got == n && c->stats().lost == 0;
        drops_seen = c->stats().from_journal;
        TelemetrySample t;
        while (c->try_next_telemetry(t) == Poll::kEvent) {
        }
    };
    std::uint64_t fast_journal = 0, slow_journal = 0;
    bool fast_ok = false, slow_ok = false;
    std::thread fast([&] { run_consumer(false, fast_journal, fast_ok); });
    std::thread slow([&] { run_consumer(true, slow_journal, slow_ok); });
    // Lockstep: beat, as a ticking producer would, until both consumers have tried to attach.
    const auto attach_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (attach_tries.load() < 2 && std::chrono::steady_clock::now() < attach_deadline) {
        producer->heartbeat(0, monotonic_ns());
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    for (std::uint64_t i = 0; i < n; ++i) {
        EventRecord r = test::make_event(i);
        producer->publish_event(r);
        TelemetrySample t = test::make_sample(i);
        producer->publish_telemetry(t);
        producer->heartbeat(i, monotonic_ns());
    }
    fast.join();
    slow.join();
    EXPECT_TRUE(fast_ok);
    EXPECT_TRUE(slow_ok);
    std::printf("events %llu; from journal: fast consumer %llu, slow consumer %llu\n",
                static_cast<unsigned long long>(n), static_cast<unsigned long long>(fast_journal),
                static_cast<unsigned long long>(slow_journal));
}

TEST(ConcurrentMailbox, ReaderOnlyEverTakesCompleteValidGenerations) {
    auto seg = SegmentBuilder().name(test::unique_segment_name("cmbox")).create();
    ASSERT_TRUE(seg);
    std::atomic<bool> done{false};
    std::thread writer([&] {
        MeshMailboxWriter w(seg->layout());
        auto m = std::make_unique<CollisionMesh>();
        m->body_count = 1;
        m->bodies[0] = MeshBodyEntry{};
        for (int i = 0; i < 16; ++i) m->bodies[0].world_from_body[i] = (i % 5 == 0) ? 1.f : 0.f;
        for (std::uint32_t g = 1; g <= 300 / kScale; ++g) {
            const std::uint32_t verts = 3 + (g % 50) * 100;
            m->vertex_count = verts;
            m->index_count = 3 * (verts - 2);
            for (std::uint32_t v = 0; v < 3 * verts; ++v) m->vertices_m[v] = 0.001f * float(g % 7);
            for (std::uint32_t t = 0; t < verts - 2; ++t) {
                m->indices[3 * t] = 0;
                m->indices[3 * t + 1] = t + 1;
                m->indices[3 * t + 2] = t + 2;
            }
            m->bodies[0].vertex_count = verts;
            m->bodies[0].index_count = m->index_count;
            ASSERT_TRUE(w.publish(*m));
        }
        done.store(true);
    });
    MeshMailboxReader reader(seg->layout());
    auto out = std::make_unique<CollisionMesh>();
    std::uint64_t last = 0, taken = 0;
    for (;;) {
        const bool finished = done.load();
        const MailboxRead r = reader.try_take_newest(*out);
        ASSERT_NE(r, MailboxRead::kRejected) << reader.last_rejection();
        if (r == MailboxRead::kNew) {
            ASSERT_GT(out->generation, last);
            ASSERT_EQ(out->vertex_count, 3 + (out->generation % 50) * 100);
            last = out->generation;
            ++taken;
        }
        if (finished && r == MailboxRead::kNothingNew) break;
    }
    writer.join();
    EXPECT_EQ(last, 300 / kScale);
    EXPECT_GT(taken, 0u);
}

}  // namespace
}  // namespace kerf::ipc
