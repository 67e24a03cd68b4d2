// fuzz_shm_reader — random bytes as a segment image, fed to every validating reader: header
// check, producer health, event/telemetry ring consumers with record validation, the state
// seqlock, the mesh mailbox reader, and (same bytes as a file) the journal reader. Nothing may
// crash, hang or read out of bounds; rejections are the expected outcome.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "rt_core/ipc/journal_reader.hpp"
#include "rt_core/ipc/layout.hpp"
#include "rt_core/ipc/mesh_mailbox.hpp"
#include "rt_core/ipc/record_check.hpp"
#include "rt_core/ipc/shm_segment.hpp"

namespace {

using namespace kerf::ipc;

struct Region {
    std::size_t offset, bytes;
};

// The parts of the image the fuzzer controls; everything else stays zero.
constexpr std::size_t kSlot0 = offsetof(SegmentLayout, slots);
constexpr std::size_t kMailbox = offsetof(SegmentLayout, mailbox);
constexpr Region kRegions[] = {
    {0, offsetof(SegmentLayout, slots)},                      // header, producer, seqlock
    {kSlot0, 576},                                            // slot 0 control + ring indices
    {kSlot0 + offsetof(ConsumerSlot, events), 128 * 8},       // first event records
    {kSlot0 + offsetof(ConsumerSlot, telemetry), 128 * 8},    // first telemetry samples
    {kMailbox, 64 + 64 + sizeof(MeshBufferHeader)},           // latest word + buffer 0 header
    {kMailbox + 64 + offsetof(MeshBuffer, vertices_m), 256},  // some coordinates
    {kMailbox + 64 + offsetof(MeshBuffer, indices), 256},     // some indices
};

SegmentLayout* image() {
    static SegmentLayout* s = [] {
        void* p = mmap(nullptr, sizeof(SegmentLayout), PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        return static_cast<SegmentLayout*>(p);
    }();
    return s;
}

void load_image(const std::uint8_t* data, std::size_t size) {
    auto* base = reinterpret_cast<std::uint8_t*>(image());
    for (const Region& r : kRegions) {
        const std::size_t n = size < r.bytes ? size : r.bytes;
        std::memset(base + r.offset, 0, r.bytes);
        std::memcpy(base + r.offset, data, n);
        data += n;
        size -= n;
    }
}

void read_rings(SegmentLayout& s) {
    ConsumerSlot& slot = s.slots[0];
    auto events =
        SpscConsumerEnd<EventRecord, kEventCapacity>::resume(&slot.event_ring, slot.events);
    EventRecord r;
    for (int i = 0; i < 16 && events.try_pop(r) != PopResult::kEmpty; ++i) (void)validate_event(r);
    auto tel = SpscConsumerEnd<TelemetrySample, kTelemetryCapacity>::resume(&slot.telemetry_ring,
                                                                            slot.telemetry);
    TelemetrySample t;
    for (int i = 0; i < 16 && tel.try_pop(t) != PopResult::kEmpty; ++i) (void)validate_telemetry(t);
}

void read_journal(const std::uint8_t* data, std::size_t size) {
    char path[] = "/tmp/fuzz_shm_journal_XXXXXX";
    const int fd = mkstemp(path);
    if (fd < 0) return;
    if (::write(fd, data, size) == static_cast<ssize_t>(size)) {
        auto j = JournalReader::open(path, 0);
        if (j) {
            EventRecord r;
            for (std::uint64_t seq : {0ull, 1ull, 5ull, ~0ull}) (void)j->try_read(seq, r);
        }
    }
    ::close(fd);
    unlink(path);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    SegmentLayout* s = image();
    load_image(data, size);
    (void)check_header(s->header, sizeof(SegmentLayout));
    (void)journal_path_of(s->header);
    if (s->header.producer_pid <= 0) (void)producer_health(*s);  // no signals to real pids
    read_rings(*s);
    LatestState state;
    if (try_seqlock_read(s->state, state, 4) == SeqlockRead::kOk) (void)validate_state(state);
    static auto* mesh = new CollisionMesh();
    MeshMailboxReader reader(*s);
    (void)reader.try_take_newest(*mesh);
    read_journal(data, size);
    return 0;
}
