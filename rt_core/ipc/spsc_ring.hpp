// kerf::ipc::SpscRing — a single-producer single-consumer ring over memory both sides map
// (shared memory between processes, or plain memory between threads). The producer never blocks:
// when the ring is full the NEW record is dropped and counted. Indices are free-running 64-bit
// counters (never wrap in practice: 2^64 records at 1 GHz is 584 years); slot = index & (N - 1).
//
//   write_index (producer) ───────────────────────────┐
//   read_index  (consumer) ──────┐                    │
//                                ▼                    ▼
//     slots:  [ .. | r | r+1 | ... | w-1 | free | ... ]      used = w - r, 0 <= used <= N
//
//   overflow rule (used == N when a push comes):
//     try_push(x):  w - r_cached >= N ? reload r : ok
//                   w - r        >= N ? drop x, dropped_count += 1, return false   (never wait)
//     the consumer sees a sequence gap (seq jumps) and fetches the missing records elsewhere
//     (events: from the journal; telemetry: lost, counted).
//
// Each side caches the other's index and reloads it only when the cache says "full"/"empty".
// Every index lives on its own literal 64-byte line (two processes must agree on it; never
// std::hardware_destructive_interference_size). Memory order is spelled at every atomic access.
// Untrusted: the consumer treats write_index as input (a corrupt index resyncs and is reported);
// the producer keeps its own copy of write_index and only ever writes in bounds.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace kerf::ipc {

inline constexpr std::size_t kCacheLine = 64;  ///< literal: both processes must agree

/// One 64-bit counter alone on a 64-byte line.
struct alignas(kCacheLine) PaddedCounter {
    std::atomic<std::uint64_t> value;
    std::uint8_t pad[kCacheLine - sizeof(std::atomic<std::uint64_t>)];
};
static_assert(sizeof(PaddedCounter) == 64 && std::atomic<std::uint64_t>::is_always_lock_free);

/// Shared control block of one ring: four lines, each written by one side only.
struct RingControl {
    PaddedCounter write_index;    ///< producer: next index it will write (release)
    PaddedCounter read_index;     ///< consumer: next index it will read (release)
    PaddedCounter pushed_count;   ///< producer: records accepted since the slot was claimed
    PaddedCounter dropped_count;  ///< producer: records dropped (ring full) since claimed
};
static_assert(sizeof(RingControl) == 256);

/// Outcome of SpscConsumerEnd::try_pop.
enum class PopResult : std::uint8_t { kOk, kEmpty, kCorruptIndex };

/// The producer's end. Holds its own write index; real-time safe (noexcept, no allocation).
template <class T, std::uint32_t N>
class SpscProducerEnd {
    static_assert((N & (N - 1)) == 0 && N >= 2, "capacity must be a power of two");
    static_assert(std::is_trivially_copyable_v<T>);

public:
    SpscProducerEnd() = default;
    /// Starts writing at the ring's current write_index (the producer is the only writer of it).
    SpscProducerEnd(RingControl* control, T* slots) noexcept
        : control_(control),
          slots_(slots),
          write_(control->write_index.value.load(std::memory_order_relaxed)),
          cached_read_(control->read_index.value.load(std::memory_order_acquire)) {}

    /// Re-reads the consumer's index and zeroes the counters (a new consumer claimed the slot).
    void reset_for_new_consumer() noexcept {
        cached_read_ = control_->read_index.value.load(std::memory_order_acquire);
        pushed_ = dropped_ = 0;
        control_->pushed_count.value.store(0, std::memory_order_relaxed);
        control_->dropped_count.value.store(0, std::memory_order_relaxed);
    }

    /// Copies `item` in, or drops and counts it when full. Never blocks. Returns true if stored.
    bool try_push(const T& item) noexcept {
        if (write_ - cached_read_ >= N) {
            cached_read_ = control_->read_index.value.load(std::memory_order_acquire);
            if (write_ - cached_read_ >= N || cached_read_ > write_) {  // full, or garbage index
                control_->dropped_count.value.store(++dropped_, std::memory_order_relaxed);
                return false;
            }
        }
        std::memcpy(static_cast<void*>(&slots_[write_ & (N - 1)]), &item, sizeof(T));
        control_->write_index.value.store(++write_, std::memory_order_release);
        control_->pushed_count.value.store(++pushed_, std::memory_order_relaxed);
        return true;
    }

    /// True when a try_push now would drop (re-reads the consumer's index). Never blocks.
    bool full() noexcept {
        if (write_ - cached_read_ < N) return false;
        cached_read_ = control_->read_index.value.load(std::memory_order_acquire);
        return write_ - cached_read_ >= N || cached_read_ > write_;
    }

    std::uint64_t dropped() const noexcept { return dropped_; }
    std::uint64_t pushed() const noexcept { return pushed_; }

private:
    RingControl* control_ = nullptr;
    T* slots_ = nullptr;
    std::uint64_t write_ = 0;
    std::uint64_t cached_read_ = 0;
    std::uint64_t pushed_ = 0;
    std::uint64_t dropped_ = 0;
};

/// The consumer's end. Treats the shared write index as untrusted.
template <class T, std::uint32_t N>
class SpscConsumerEnd {
    static_assert((N & (N - 1)) == 0 && N >= 2, "capacity must be a power of two");

public:
    SpscConsumerEnd() = default;
    /// Starts at the producer's current write index: only records pushed from now on are seen.
    SpscConsumerEnd(RingControl* control, const T* slots) noexcept
        : control_(control), slots_(slots) {
        read_ = cached_write_ = control->write_index.value.load(std::memory_order_acquire);
        control_->read_index.value.store(read_, std::memory_order_release);
    }

    /// Resumes at the ring's shared read index (set by whoever claimed the slot).
    static SpscConsumerEnd resume(RingControl* control, const T* slots) noexcept {
        SpscConsumerEnd end;
        end.control_ = control;
        end.slots_ = slots;
        end.read_ = end.cached_write_ = control->read_index.value.load(std::memory_order_acquire);
        return end;
    }

    /// Copies the oldest record out. kCorruptIndex: the write index jumped by more than N or went
    /// backwards (someone scribbled over it); the reader resynced to it and lost what was between.
    PopResult try_pop(T& out) noexcept {
        if (read_ == cached_write_) {
            cached_write_ = control_->write_index.value.load(std::memory_order_acquire);
            if (read_ == cached_write_) return PopResult::kEmpty;
        }
        if (cached_write_ < read_ || cached_write_ - read_ > N) {
            read_ = cached_write_;
            control_->read_index.value.store(read_, std::memory_order_release);
            return PopResult::kCorruptIndex;
        }
        std::memcpy(static_cast<void*>(&out), &slots_[read_ & (N - 1)], sizeof(T));
        control_->read_index.value.store(++read_, std::memory_order_release);
        return PopResult::kOk;
    }

    /// Records pushed but not yet popped, as far as this side knows (a fresh acquire load).
    std::uint64_t lag() const noexcept {
        const auto w = control_->write_index.value.load(std::memory_order_acquire);
        return w >= read_ ? w - read_ : 0;
    }

private:
    RingControl* control_ = nullptr;
    const T* slots_ = nullptr;
    std::uint64_t read_ = 0;
    std::uint64_t cached_write_ = 0;
};

}  // namespace kerf::ipc
