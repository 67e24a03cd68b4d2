// A stand-in for kerf-rt in the display's integration tests and benchmarks: creates a real
// session segment and journal with ProducerBuilder and publishes recorded events from a file of
// raw 128-byte EventRecords, heartbeating every millisecond (sleeping, never spinning).
//
//   display_test_producer --segment NAME --journal-dir DIR --records FILE
//                         [--hold-after K --go FILE] [--period-ms P] [--pose x,y,z]
//
// Publishes records [0, K), waits until FILE exists, publishes the rest (one every P ms), then
// keeps the session alive (heartbeat + a LatestState with the tool at --pose) until SIGTERM.
// Prints "ready" once the segment exists and "published N" after each phase.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "config/base/main_guard.hpp"
#include "rt_core/ipc/producer.hpp"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

std::uint64_t now_ns() {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                          std::chrono::steady_clock::now().time_since_epoch())
                                          .count());
}

}  // namespace

static int program_main(int argc, char** argv) {
    std::string segment, journal_dir = "/dev/shm", records_path, go_path;
    std::size_t hold_after = ~std::size_t{0};
    double period_ms = 2.0;
    double pose[3] = {0, 0, 0};
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--segment")
            segment = value;
        else if (key == "--journal-dir")
            journal_dir = value;
        else if (key == "--records")
            records_path = value;
        else if (key == "--hold-after")
            hold_after = std::stoul(value);
        else if (key == "--go")
            go_path = value;
        else if (key == "--period-ms")
            period_ms = std::stod(value);
        else if (key == "--pose")
            std::sscanf(value.c_str(), "%lf,%lf,%lf", &pose[0], &pose[1], &pose[2]);
        else {
            std::fprintf(stderr, "display_test_producer: unknown option %s\n", key.c_str());
            return 2;
        }
    }
    std::ifstream in(records_path, std::ios::binary);
    std::vector<kerf::ipc::EventRecord> records;
    kerf::ipc::EventRecord r;
    while (in.read(reinterpret_cast<char*>(&r), sizeof r)) records.push_back(r);
    if (segment.empty() || records.empty()) {
        std::fprintf(stderr, "display_test_producer: need --segment and a non-empty --records\n");
        return 2;
    }
    auto producer =
        kerf::ipc::ProducerBuilder().segment_name(segment).journal_dir(journal_dir).create();
    if (!producer) {
        std::fprintf(stderr, "display_test_producer: %s\n", producer.error().message().c_str());
        return 1;
    }
    std::signal(SIGTERM, on_signal);
    std::signal(SIGINT, on_signal);
    std::printf("ready\n");
    std::fflush(stdout);

    kerf::ipc::LatestState state{};
    state.tool_orientation_wxyz[0] = 1.0;
    for (int k = 0; k < 3; ++k) state.tool_position_m[k] = pose[k];
    std::uint64_t tick = 0;
    const auto beat = [&] {
        const std::uint64_t t = now_ns();
        producer->heartbeat(++tick, t);
        state.tick = tick;
        state.time_ns = t;
        producer->publish_state(state);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    };
    std::size_t next = 0;
    const auto publish_until = [&](std::size_t end) {
        auto due = std::chrono::steady_clock::now();
        while (next < end && !g_stop.load()) {
            if (std::chrono::steady_clock::now() >= due) {
                producer->publish_event(records[next++]);
                due += std::chrono::microseconds(static_cast<std::int64_t>(period_ms * 1000));
            }
            beat();
        }
        std::printf("published %zu\n", next);
        std::fflush(stdout);
    };
    publish_until(std::min(hold_after, records.size()));
    if (next < records.size()) {
        while (!g_stop.load() && !std::filesystem::exists(go_path)) beat();
        publish_until(records.size());
    }
    while (!g_stop.load()) beat();
    producer->stop();
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("display_test_producer", [&] { return program_main(argc, argv); });
}
