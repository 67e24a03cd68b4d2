// kerf::cut::detail::HugePageAllocator — a std::allocator for large arrays read at random (the
// face tree's boxes): blocks of kHugeThresholdBytes or more are fresh mappings of their own,
// aligned to 2 MiB and, on Linux, marked MADV_HUGEPAGE before their first touch, so that the
// kernel backs them with transparent huge pages where it can.
// A query that touches a few hundred random boxes of a 100 MB array then misses the TLB a few
// times instead of once a box (with 4 KiB pages each miss is a page walk the prefetch waits on).
// Smaller blocks are plain allocations. Library-internal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace kerf::cut::detail {

/// Blocks at least this large get huge pages.
inline constexpr std::size_t kHugeThresholdBytes = std::size_t{4} << 20;
/// The huge page size blocks are aligned and rounded to, bytes.
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Advises the whole 2 MiB pages inside [p, p + bytes) for huge pages (Linux; a no-op elsewhere
/// and for blocks below kHugeThresholdBytes): for a large scratch array from the ordinary heap,
/// whose pages are then first touched 2 MiB at a time and which, freed, stays in the heap for
/// the allocations that follow (a HugePageAllocator block is unmapped when freed).
inline void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes < kHugeThresholdBytes) return;
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t begin = (at + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    const std::uintptr_t end = (at + bytes) / kHugePageBytes * kHugePageBytes;
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)p, (void)bytes;
#endif
}

/// A fresh mapping of `bytes` (rounded up to whole huge pages), 2 MiB-aligned and, on Linux,
/// advised for huge pages before any page of it is touched. Mapped here rather than taken from
/// malloc: glibc serves blocks under its mmap threshold (raised up to 32 MiB by every large
/// free) from heap pages an earlier array already touched as 4 KiB pages, which the advice no
/// longer changes (measured: 4 MiB of a 4M-face tree's 60 MiB on huge pages that way).
inline void* map_huge(std::size_t bytes) {
    const std::size_t rounded = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
#if defined(__linux__)
    // Map one huge page more, then unmap the ends that are not 2 MiB-aligned.
    const std::size_t span = rounded + kHugePageBytes;
    void* const raw =
        ::mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto at = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t begin = (at + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    if (begin > at) ::munmap(raw, begin - at);
    if (at + span > begin + rounded)
        ::munmap(reinterpret_cast<void*>(begin + rounded), at + span - (begin + rounded));
#if defined(MADV_HUGEPAGE)
    ::madvise(reinterpret_cast<void*>(begin), rounded, MADV_HUGEPAGE);  // advice only
#endif
    return reinterpret_cast<void*>(begin);
#else
    void* p = std::aligned_alloc(kHugePageBytes, rounded);
    if (p == nullptr) throw std::bad_alloc();
    return p;
#endif
}

/// Releases what map_huge(bytes) returned.
inline void unmap_huge(void* p, std::size_t bytes) noexcept {
#if defined(__linux__)
    ::munmap(p, (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes);
#else
    (void)bytes;
    std::free(p);
#endif
}

template <class T>
struct HugePageAllocator {
    using value_type = T;

    HugePageAllocator() noexcept = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    /// Room for n elements: 2 MiB-aligned and advised for huge pages when large.
    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kHugeThresholdBytes) {
            // A small block still honours T's alignment (the face tree's 64-byte groups).
            if constexpr (alignof(T) > __STDCPP_DEFAULT_NEW_ALIGNMENT__)
                return static_cast<T*>(::operator new (bytes, std::align_val_t{alignof(T)}));
            else
                return static_cast<T*>(::operator new(bytes));
        }
        return static_cast<T*>(map_huge(bytes));
    }

    /// Frees what allocate(n) returned.
    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < kHugeThresholdBytes) {
            if constexpr (alignof(T) > __STDCPP_DEFAULT_NEW_ALIGNMENT__)
                ::operator delete (p, std::align_val_t{alignof(T)});
            else
                ::operator delete(p);
        } else
            unmap_huge(p, n * sizeof(T));
    }

    /// Default-initialises: a resize() leaves trivial elements unwritten (the face tree writes
    /// every item it sizes for), so pages are first touched where they are filled.
    template <class U>
    void construct(U* p) noexcept(noexcept(::new (static_cast<void*>(p)) U)) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    template <class U>
    friend bool operator==(const HugePageAllocator&, const HugePageAllocator<U>&) noexcept {
        return true;
    }
};

}  // namespace kerf::cut::detail
