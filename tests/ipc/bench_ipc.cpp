// bench_ipc — two processes, 64-byte records: kerf's SpscRing (drop accounting on) against
// boost::lockfree::spsc_queue, both placed in the same MAP_SHARED memory and driven by the same
// harness; plus the full kerf Producer path (checksum, fan-out over slots, journal enqueue, drop
// accounting) against a boost push of the same 128-byte record. Prints ratios at the end.
//
//   build/bin/bench_ipc --benchmark_counters_tabular=true [--producer-cpu=0 --consumer-cpu=1]
//
// Pinned: the producer (this process) and the consumer (each forked child) run on the CPUs given
// (default 0 and 1; the summary says which). Unpinned, both may share one CPU and both then run
// several times faster, which says nothing about two cores. Five repetitions unless the command
// line says otherwise; every summary figure is the median with its min-max over them.
#include <benchmark/benchmark.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <boost/lockfree/spsc_queue.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "config/base/main_guard.hpp"
#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/producer.hpp"
#include "rt_core/ipc/spsc_ring.hpp"
#include "tests/ipc/ipc_test_support.hpp"

namespace {

using namespace kerf::ipc;

int g_producer_cpu = 0;  ///< --producer-cpu: this process
int g_consumer_cpu = 1;  ///< --consumer-cpu: every forked consumer

/// Pins the calling process to `cpu`; false when the machine has no such CPU.
bool pin_to(int cpu) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    return sched_setaffinity(0, sizeof(set), &set) == 0;
}

constexpr std::uint32_t kCap = 4096;
constexpr std::uint32_t kMaxLatencySamples = 200'000;
constexpr int kBurst = 16;  ///< pushes timed together (clock cost amortised)

struct Rec64 {
    std::uint64_t seq;
    std::uint64_t stamp_ns;
    std::uint64_t payload[6];
};
static_assert(sizeof(Rec64) == 64);

using BoostQueue = boost::lockfree::spsc_queue<Rec64, boost::lockfree::capacity<kCap>>;

struct Shared {
    RingControl ring;
    Rec64 slots[kCap];
    alignas(64) BoostQueue boost_queue;
    alignas(64) std::atomic<std::uint64_t> consumer_ready;
    std::uint64_t received;
    std::uint64_t checksum;
    std::uint32_t latency_ns[kMaxLatencySamples];
};

Shared* shared() {
    static Shared* s = [] {
        void* p = mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS,
                       -1, 0);
        if (p == MAP_FAILED) std::abort();
        return static_cast<Shared*>(p);
    }();
    return s;
}

void reset() {
    Shared* s = shared();
    new (&s->ring) RingControl{};
    s->boost_queue.~BoostQueue();
    new (&s->boost_queue) BoostQueue();
    s->consumer_ready.store(0);
    s->received = s->checksum = 0;
}

struct KerfRing {
    static constexpr const char* kName = "kerf";
    SpscProducerEnd<Rec64, kCap> producer{&shared()->ring, shared()->slots};
    bool push(const Rec64& r) { return producer.try_push(r); }  // full: drop counted, retried
    static bool pop(SpscConsumerEnd<Rec64, kCap>& c, Rec64& out) {
        return c.try_pop(out) == PopResult::kOk;
    }
};

struct BoostRing {
    static constexpr const char* kName = "boost";
    bool push(const Rec64& r) { return shared()->boost_queue.push(r); }
};

// Child: pops `count` records, checks order, stores latencies (latency mode), exits.
template <class Ring>
pid_t start_consumer(std::uint64_t count, bool latency) {
    const pid_t pid = fork();
    if (pid != 0) return pid;
    pin_to(g_consumer_cpu);
    Shared* s = shared();
    SpscConsumerEnd<Rec64, kCap> kerf_end(&s->ring, s->slots);
    s->consumer_ready.store(1, std::memory_order_release);
    Rec64 r{};
    std::uint64_t got = 0, sum = 0;
    while (got < count) {
        bool ok;
        if constexpr (std::is_same_v<Ring, KerfRing>)
            ok = KerfRing::pop(kerf_end, r);
        else
            ok = s->boost_queue.pop(r);
        if (!ok) {
            if (!latency) sched_yield();  // 2 shared cores: let the producer run
            continue;
        }
        if (latency && got < kMaxLatencySamples) {
            s->latency_ns[got] =
                std::uint32_t(std::min<std::uint64_t>(monotonic_ns() - r.stamp_ns, ~0u));
        }
        if (r.seq != got) _exit(3);
        sum += r.payload[0];
        ++got;
    }
    s->received = got;
    s->checksum = sum;
    _exit(0);
}

std::map<std::string, std::vector<double>> g_runs;  // per repetition; medians printed at the end

template <class Ring>
void BM_Throughput64(benchmark::State& state) {
    reset();
    const std::uint64_t n = std::uint64_t(state.max_iterations);
    const pid_t child = start_consumer<Ring>(n, false);
    while (shared()->consumer_ready.load(std::memory_order_acquire) == 0) {
    }
    Ring ring;
    std::uint64_t seq = 0, full = 0;
    for (auto _ : state) {
        Rec64 r{seq, 0, {seq, 1, 2, 3, 4, 5}};
        while (!ring.push(r)) {
            ++full;
            sched_yield();
        }
        ++seq;
    }
    int status = 0;
    waitpid(child, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || shared()->received != n) {
        state.SkipWithError("consumer failed");
    }
    state.SetItemsProcessed(std::int64_t(n));
    state.counters["full_retries"] = double(full);
}

template <class Ring>
void BM_Latency64(benchmark::State& state) {
    const std::uint64_t n = std::uint64_t(state.range(0));
    for (auto _ : state) {
        reset();
        const pid_t child = start_consumer<Ring>(n, true);
        while (shared()->consumer_ready.load(std::memory_order_acquire) == 0) {
        }
        Ring ring;
        for (std::uint64_t i = 0; i < n; ++i) {
            // one in flight at a time: wait until the previous one was taken (harness pacing)
            while (shared()->ring.read_index.value.load(std::memory_order_acquire) < i &&
                   std::is_same_v<Ring, KerfRing>) {
            }
            if constexpr (std::is_same_v<Ring, BoostRing>) {
                while (shared()->boost_queue.read_available() != 0) {
                }
            }
            Rec64 r{i, monotonic_ns(), {i, 1, 2, 3, 4, 5}};
            while (!ring.push(r)) {
            }
        }
        waitpid(child, nullptr, 0);
    }
    std::vector<std::uint32_t> v(
        shared()->latency_ns,
        shared()->latency_ns + std::min<std::uint64_t>(n, kMaxLatencySamples));
    std::sort(v.begin(), v.end());
    auto pct = [&](double p) {
        return double(v[std::min(v.size() - 1, std::size_t(p * double(v.size())))]);
    };
    state.counters["p50_ns"] = pct(0.5);
    state.counters["p99_ns"] = pct(0.99);
    state.counters["p999_ns"] = pct(0.999);
    const std::string k = Ring::kName;
    g_runs[k + "_lat_p50"].push_back(pct(0.5));
    g_runs[k + "_lat_p99"].push_back(pct(0.99));
    g_runs[k + "_lat_p999"].push_back(pct(0.999));
}

// Full producer path: 128-byte event, checksum, fan-out, journal enqueue, drop accounting; one
// consumer process attached and draining; pushes into a ring that is not full (the 1 kHz case).
// Median over bursts of kBurst pushes timed together.
void BM_ProducerPublishEvent(benchmark::State& state) {
    kerf::ipc::test::ScratchDir dir;
    const std::string name = kerf::ipc::test::unique_segment_name("bench");
    auto p = ProducerBuilder().segment_name(name).journal_dir(dir.path).create();
    if (!p) return state.SkipWithError(p.error().message().c_str());
    p->heartbeat(0, monotonic_ns());
    const pid_t child = fork();
    if (child == 0) {
        pin_to(g_consumer_cpu);
        auto c =
            ConsumerBuilder().segment_name(name).from_sequence(ConsumerBuilder::kFromNow).attach();
        if (!c) _exit(2);
        EventRecord r;
        for (;;) {
            if (c->try_next(r) == Poll::kEvent) continue;
            if (c->producer_health() == ProducerHealth::kStopped) _exit(0);
        }
    }
    for (int i = 0; i < 2000 && (p->layout().slots[0].control.claim_word.load() & 3u) != 2u; ++i)
        usleep(1000);
    std::vector<double> ns;
    ns.reserve(1 << 20);
    EventRecord r = kerf::ipc::test::make_event(1);
    std::uint64_t tick = 0;
    const auto& ring = p->layout().slots[0].event_ring;
    for (auto _ : state) {  // one iteration = a burst of kBurst events, timed together
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < kBurst; ++k) p->publish_event(r);
        const auto t1 = std::chrono::steady_clock::now();
        ns.push_back(double((t1 - t0).count()) / kBurst);
        p->heartbeat(++tick, monotonic_ns());
        state.PauseTiming();  // let the consumer drain: measure pushes into a non-full ring
        while (ring.read_index.value.load() + 64 < ring.write_index.value.load()) {
        }
        state.ResumeTiming();
    }
    std::sort(ns.begin(), ns.end());
    const double median = ns[ns.size() / 2];
    state.counters["push_median_ns"] = median;
    state.counters["push_p999_ns"] = ns[std::min(ns.size() - 1, ns.size() * 999 / 1000)];
    state.counters["ring_drops"] = double(p->layout().producer.events_dropped.load());
    state.counters["journal_drops"] = double(p->layout().journal_dropped.value.load());
    g_runs["kerf_push_median"].push_back(median);
    p->stop();
    waitpid(child, nullptr, 0);
}

// Reference for the push cost: boost push of the same 128-byte record into a queue drained by a
// consumer process (no journal, no fan-out).
void BM_BoostPush128(benchmark::State& state) {
    using Q = boost::lockfree::spsc_queue<EventRecord, boost::lockfree::capacity<kCap>>;
    void* mem =
        mmap(nullptr, sizeof(Q) + 64, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    auto* q = new (mem) Q();
    auto* stop = new (static_cast<char*>(mem) + sizeof(Q)) std::atomic<int>(0);
    const pid_t child = fork();
    if (child == 0) {
        pin_to(g_consumer_cpu);
        EventRecord r;
        while (stop->load(std::memory_order_acquire) == 0) q->pop(r);
        _exit(0);
    }
    std::vector<double> ns;
    ns.reserve(1 << 20);
    EventRecord r = kerf::ipc::test::make_event(1);
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < kBurst; ++k) q->push(r);
        const auto t1 = std::chrono::steady_clock::now();
        ns.push_back(double((t1 - t0).count()) / kBurst);
        state.PauseTiming();
        while (q->read_available() > 64) {
        }
        state.ResumeTiming();
    }
    stop->store(1, std::memory_order_release);
    waitpid(child, nullptr, 0);
    std::sort(ns.begin(), ns.end());
    const double median = ns[ns.size() / 2];
    state.counters["push_median_ns"] = median;
    g_runs["boost_push_median"].push_back(median);
    munmap(mem, sizeof(Q) + 64);
}

class RatioReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs) {
            if (r.run_name.function_name.find("Throughput64") != std::string::npos &&
                !r.error_occurred && r.run_type == Run::RT_Iteration) {
                const auto it = r.counters.find("items_per_second");
                if (it != r.counters.end()) {
                    const bool kerf =
                        r.run_name.function_name.find("KerfRing") != std::string::npos;
                    g_runs[kerf ? "kerf_mps" : "boost_mps"].push_back(double(it->second) / 1e6);
                }
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }
};

BENCHMARK_TEMPLATE(BM_Throughput64, KerfRing)->MinTime(0.5)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Throughput64, BoostRing)->MinTime(0.5)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Latency64, KerfRing)->Arg(20'000)->Iterations(1)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Latency64, BoostRing)->Arg(20'000)->Iterations(1)->UseRealTime();
BENCHMARK(BM_ProducerPublishEvent)->Iterations(10'000)->UseRealTime();
BENCHMARK(BM_BoostPush128)->Iterations(10'000)->UseRealTime();

}  // namespace

static int program_main(int argc, char** argv) {
    std::vector<char*> args;
    bool repetitions_given = false;
    for (int i = 0; i < argc; ++i) {
        const std::string_view a(argv[i]);
        if (a.rfind("--producer-cpu=", 0) == 0) {
            g_producer_cpu = std::atoi(argv[i] + 15);
        } else if (a.rfind("--consumer-cpu=", 0) == 0) {
            g_consumer_cpu = std::atoi(argv[i] + 15);
        } else {
            repetitions_given = repetitions_given || a.rfind("--benchmark_repetitions", 0) == 0;
            args.push_back(argv[i]);
        }
    }
    std::string reps = "--benchmark_repetitions=5";
    if (!repetitions_given) args.push_back(reps.data());
    argc = static_cast<int>(args.size());
    argv = args.data();
    benchmark::Initialize(&argc, argv);
    const bool pinned = pin_to(g_producer_cpu) && g_consumer_cpu < CPU_SETSIZE &&
                        g_consumer_cpu < static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN));
    RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    struct Spread {
        double median = 0, min = 0, max = 0;
        std::size_t n = 0;
    };
    std::map<std::string, Spread> results;
    for (auto& [k, v] : g_runs) {  // median, min and max over repetitions
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
        results[k] = Spread{median, v.front(), v.back(), n};
    }
    auto get = [&](const std::string& k) { return results[k]; };
    // Ratio of medians, and the widest range the repetitions allow.
    auto ratio = [&](const std::string& a, const std::string& b) {
        const Spread sa = get(a), sb = get(b);
        char text[96];
        if (sb.median <= 0 || sb.min <= 0) return std::string("n/a");
        std::snprintf(text, sizeof text, "%.2f (%.2f-%.2f)", sa.median / sb.median, sa.min / sb.max,
                      sa.max / sb.min);
        return std::string(text);
    };
    auto fig = [&](const std::string& k, int decimals) {  // "median (min-max)"
        const Spread s = get(k);
        char text[96];
        std::snprintf(text, sizeof text, "%.*f (%.*f-%.*f)", decimals, s.median, decimals, s.min,
                      decimals, s.max);
        return std::string(text);
    };
    std::printf("\n== kerf vs boost::lockfree::spsc_queue, same run, same harness ==\n");
    std::printf("pinned: %s (producer cpu %d, consumer cpu %d); median (min-max) of %zu runs\n",
                pinned ? "yes" : "NO (pinning failed)", g_producer_cpu, g_consumer_cpu,
                get("kerf_mps").n);
    std::printf("throughput 64 B: kerf %s M/s, boost %s M/s, kerf/boost = %s\n",
                fig("kerf_mps", 1).c_str(), fig("boost_mps", 1).c_str(),
                ratio("kerf_mps", "boost_mps").c_str());
    for (const char* p : {"p50", "p99", "p999"}) {
        const std::string k = std::string("kerf_lat_") + p, b = std::string("boost_lat_") + p;
        std::printf("one-way latency %-4s: kerf %s ns, boost %s ns, kerf/boost = %s\n", p,
                    fig(k, 0).c_str(), fig(b, 0).c_str(), ratio(k, b).c_str());
    }
    std::printf(
        "push median: kerf Producer::publish_event (128 B, journal+drops on) %s ns, "
        "boost push 128 B %s ns, kerf/boost = %s\n",
        fig("kerf_push_median", 0).c_str(), fig("boost_push_median", 0).c_str(),
        ratio("kerf_push_median", "boost_push_median").c_str());
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("bench_ipc", [&] { return program_main(argc, argv); });
}
