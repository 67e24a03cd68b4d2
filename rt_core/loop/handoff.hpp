// kerf::rt::Handoff — a wait-free hand-off of heap objects (a new collision world, a new force
// profile) from a non-real-time thread to the real-time thread, and of the objects the real-time
// thread stopped using back to the non-real-time side, which frees them. The real-time side never
// allocates, frees, locks or waits.
//
//   non-RT  offer(unique_ptr)    pending_ <- new; an offer the loop never took is freed here
//   RT      try_take()           pending_ -> nullptr, returns it (only while a retire slot is free)
//   RT      retire(p)            p into a free retired_[i] (kRetireSlots, checked by try_take)
//   non-RT  collect()            retired_[i] -> nullptr, deleted
//
// Memory order: offer/try_take exchange with acq_rel, so everything the builder wrote into the
// object happens-before the loop reads it; retire stores with release, collect exchanges with
// acquire, so the loop's last reads happen-before the delete.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>

namespace kerf::rt {

template <class T>
class Handoff {
public:
    static constexpr std::uint32_t kRetireSlots = 8;

    Handoff() = default;
    Handoff(const Handoff&) = delete;
    Handoff& operator=(const Handoff&) = delete;
    ~Handoff() {
        delete pending_.load(std::memory_order_acquire);
        collect();
    }

    /// Non-RT: makes `next` the object the loop takes at its next tick boundary.
    void offer(std::unique_ptr<T> next) {
        delete pending_.exchange(next.release(), std::memory_order_acq_rel);
    }

    /// Non-RT: takes back the offered object the loop has not taken yet (nullptr: it took it, or
    /// nothing was offered). Lets the offering side merge a superseded offer into the next one.
    std::unique_ptr<T> reclaim() {
        return std::unique_ptr<T>(pending_.exchange(nullptr, std::memory_order_acq_rel));
    }

    /// RT: the newest offered object, or nullptr (nothing new, or no retire slot free yet).
    /// noexcept, wait-free.
    T* try_take() noexcept {
        if (free_retire_slot() == kRetireSlots) return nullptr;
        if (pending_.load(std::memory_order_relaxed) == nullptr) return nullptr;
        return pending_.exchange(nullptr, std::memory_order_acq_rel);
    }

    /// RT: gives back an object the loop no longer uses (nullptr is ignored). Returns false only
    /// if every retire slot is full, which try_take() prevents. noexcept, wait-free.
    bool retire(T* old) noexcept {
        if (old == nullptr) return true;
        const std::uint32_t i = free_retire_slot();
        if (i == kRetireSlots) return false;
        retired_[i].store(old, std::memory_order_release);
        return true;
    }

    /// Non-RT: frees every retired object; returns how many.
    std::uint32_t collect() {
        std::uint32_t n = 0;
        for (auto& slot : retired_) {
            if (slot.load(std::memory_order_relaxed) == nullptr) continue;
            delete slot.exchange(nullptr, std::memory_order_acquire);
            ++n;
        }
        return n;
    }

    /// Whether an offer is waiting for the loop (tests, shutdown).
    bool pending() const noexcept { return pending_.load(std::memory_order_acquire) != nullptr; }

private:
    std::uint32_t free_retire_slot() const noexcept {
        for (std::uint32_t i = 0; i < kRetireSlots; ++i) {
            if (retired_[i].load(std::memory_order_acquire) == nullptr) return i;
        }
        return kRetireSlots;
    }

    std::atomic<T*> pending_{nullptr};
    std::array<std::atomic<T*>, kRetireSlots> retired_{};
};

}  // namespace kerf::rt
