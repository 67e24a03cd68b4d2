// A hostile process for the display's integration tests: maps a live session segment read-write
// and, for --seconds, overwrites event records, ring indices and the mesh mailbox's words with
// random bytes (one scribble per millisecond, deterministic for a --seed). The display must
// reject what it reads, catch up from the journal and end with the same mesh as without it.
//
//   display_test_scribbler --segment NAME [--seconds S] [--seed N]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <thread>

#include "config/base/main_guard.hpp"
#include "rt_core/ipc/shm_segment.hpp"

static int program_main(int argc, char** argv) {
    std::string segment;
    double seconds = 2.0;
    std::uint64_t seed = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string key = argv[i], value = argv[i + 1];
        if (key == "--segment")
            segment = value;
        else if (key == "--seconds")
            seconds = std::stod(value);
        else if (key == "--seed")
            seed = std::stoull(value);
    }
    auto opened = kerf::ipc::SegmentBuilder().name(segment).open();
    if (!opened) {
        std::fprintf(stderr, "display_test_scribbler: %s\n", opened.error().message().c_str());
        return 1;
    }
    kerf::ipc::SegmentLayout& seg = opened->layout();
    std::mt19937_64 rng(seed);
    std::uint64_t scribbles = 0;
    const auto until =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(std::int64_t(seconds * 1000));
    while (std::chrono::steady_clock::now() < until) {
        // Mostly the slots in use (the display's among them), sometimes any slot.
        std::uint32_t pick = static_cast<std::uint32_t>(rng() % kerf::ipc::kSlotCount);
        for (std::uint32_t k = 0; k < kerf::ipc::kSlotCount && rng() % 4 != 0; ++k) {
            const std::uint32_t i = (pick + k) % kerf::ipc::kSlotCount;
            if (seg.slots[i].control.consumer_pid.load() != 0) {
                pick = i;
                break;
            }
        }
        auto& slot = seg.slots[pick];
        switch (rng() % 4) {
            case 0:
            case 1: {  // a whole event record
                auto& rec = slot.events[rng() % kerf::ipc::kEventCapacity];
                unsigned char bytes[sizeof rec];
                for (auto& b : bytes) b = static_cast<unsigned char>(rng());
                std::memcpy(static_cast<void*>(&rec), bytes, sizeof rec);
                break;
            }
            case 2:  // a ring index
                (rng() % 2 ? slot.event_ring.write_index : slot.event_ring.read_index)
                    .value.store(rng() % (4 * kerf::ipc::kEventCapacity));
                break;
            default:  // the mailbox's latest word
                seg.mailbox.latest.value.store(rng());
                break;
        }
        ++scribbles;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    std::printf("scribbles %llu\n", static_cast<unsigned long long>(scribbles));
    return 0;
}

// Nothing escapes: an unexpected exception is a message and exit 1, never an abort.
int main(int argc, char** argv) {
    return kerf::guarded_main("display_test_scribbler", [&] { return program_main(argc, argv); });
}
