#include "tools/kerf/soak_scribbler.hpp"

#include <chrono>
#include <cstring>
#include <random>
#include <thread>

#include "rt_core/ipc/consumer.hpp"
#include "rt_core/ipc/shm_segment.hpp"

namespace kerf::cli {
namespace {

/// Random bytes over `bytes` bytes at `at`.
void fill(void* at, std::size_t bytes, std::mt19937_64& rng) {
    auto* p = static_cast<unsigned char*>(at);
    for (std::size_t i = 0; i < bytes; ++i) p[i] = static_cast<unsigned char>(rng());
}

void scribble_once(ipc::SegmentLayout& seg, std::mt19937_64& rng) {
    // The display's slot most often; the monitor's event ring; the spare (tool) slots.
    const std::uint32_t pick =
        rng() % 2 ? ipc::kDisplaySlot
        : rng() % 2
            ? ipc::kMonitorSlot
            : ipc::kFirstToolSlot + std::uint32_t(rng() % (ipc::kSlotCount - ipc::kFirstToolSlot));
    ipc::ConsumerSlot& slot = seg.slots[pick];
    switch (rng() % 6) {
        case 0:
        case 1:  // a whole event record, one of the newest (what the consumer reads next)
            fill(&slot.events[(slot.event_ring.write_index.value.load() - 1 - rng() % 4) %
                              ipc::kEventCapacity],
                 sizeof(ipc::EventRecord), rng);
            break;
        case 2:  // a whole event record anywhere
            fill(&slot.events[rng() % ipc::kEventCapacity], sizeof(ipc::EventRecord), rng);
            break;
        case 3:  // an index of the event ring (not the monitor's: its telemetry shares the slot)
            if (pick != ipc::kMonitorSlot)
                (rng() % 2 ? slot.event_ring.write_index : slot.event_ring.read_index)
                    .value.store(rng() % (4 * ipc::kEventCapacity));
            break;
        case 4:  // the mailbox's newest-buffer word
            seg.mailbox.latest.value.store(rng());
            break;
        default: {  // 64 bytes somewhere in a mailbox buffer (header, vertices, indices)
            ipc::MeshBuffer& buffer = seg.mailbox.buffers[rng() % 2];
            const std::size_t at = rng() % (sizeof buffer - 64);
            fill(reinterpret_cast<unsigned char*>(&buffer) + at, 64, rng);
            break;
        }
    }
}

}  // namespace

Result<std::uint64_t, std::string> scribble_segment(const std::string& session, double seconds,
                                                    std::uint64_t seed,
                                                    const std::atomic<bool>& stop) {
    auto opened = ipc::SegmentBuilder().name(session).open();
    if (!opened) return Err{"scribbler: " + opened.error().message()};
    ipc::SegmentLayout& seg = opened->layout();
    std::mt19937_64 rng(seed);
    std::uint64_t scribbles = 0;
    const auto until =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(std::int64_t(seconds * 1000));
    while (!stop.load() && std::chrono::steady_clock::now() < until) {
        scribble_once(seg, rng);
        ++scribbles;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return scribbles;
}

}  // namespace kerf::cli
