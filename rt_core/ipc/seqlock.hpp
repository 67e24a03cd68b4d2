// kerf::ipc::Seqlock — latest-value cell for one writer and any number of readers in other
// processes. The writer never waits; a reader retries until it copies a value no write overlapped
// and never returns a torn value. The payload is held as 64-bit atomic words, so the protocol is
// data-race free (and ThreadSanitizer agrees); no standalone fences (TSan cannot model them):
//
//   writer: seq = odd (relaxed) ─ each word stored with release ─ seq = odd + 1 (release)
//   reader: s1 = seq (acquire), odd → retry ─ each word loaded with acquire ─ s2 = seq (relaxed)
//           s1 != s2 → retry.  A word the reader saw new was released after `seq = odd`, so
//           the acquire makes that odd (or later) value visible to the s2 load.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "rt_core/ipc/spsc_ring.hpp"

namespace kerf::ipc {

/// Shared cell: sequence on its own line, then the payload words.
template <class T>
struct SeqlockCell {
    static_assert(std::is_trivially_copyable_v<T> && sizeof(T) % 8 == 0);
    static constexpr std::size_t kWords = sizeof(T) / 8;
    PaddedCounter sequence;                    ///< even: stable; odd: write in progress
    std::atomic<std::uint64_t> words[kWords];  ///< the value, word by word
};

/// Why try_read gave up.
enum class SeqlockRead : std::uint8_t { kOk, kBusy, kNeverWritten };

/// Writes a new value. One writer only. noexcept, wait-free, allocation-free: real-time safe.
template <class T>
void seqlock_write(SeqlockCell<T>& cell, const T& value) noexcept {
    std::uint64_t words[SeqlockCell<T>::kWords];
    std::memcpy(words, &value, sizeof(T));
    const auto odd = cell.sequence.value.load(std::memory_order_relaxed) | 1u;
    cell.sequence.value.store(odd, std::memory_order_relaxed);
    for (std::size_t i = 0; i < SeqlockCell<T>::kWords; ++i) {
        cell.words[i].store(words[i], std::memory_order_release);
    }
    cell.sequence.value.store(odd + 1u, std::memory_order_release);
}

/// Copies the latest value out, retrying up to `max_attempts` times while a write overlaps.
/// kNeverWritten when the sequence is still 0. Lock-free; callable from any thread or process.
template <class T>
SeqlockRead try_seqlock_read(const SeqlockCell<T>& cell, T& out, int max_attempts = 64) noexcept {
    std::uint64_t words[SeqlockCell<T>::kWords];
    for (int attempt = 0; attempt < max_attempts; ++attempt) {
        const auto s1 = cell.sequence.value.load(std::memory_order_acquire);
        if (s1 == 0) return SeqlockRead::kNeverWritten;
        if (s1 & 1u) continue;
        for (std::size_t i = 0; i < SeqlockCell<T>::kWords; ++i) {
            words[i] = cell.words[i].load(std::memory_order_acquire);
        }
        if (cell.sequence.value.load(std::memory_order_relaxed) == s1) {
            std::memcpy(&out, words, sizeof(T));
            return SeqlockRead::kOk;
        }
    }
    return SeqlockRead::kBusy;
}

}  // namespace kerf::ipc
