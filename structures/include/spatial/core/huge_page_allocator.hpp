#pragma once
// spatial::huge_page_allocator<T> — a std::allocator for large, randomly accessed, read-mostly
// arrays (the ray layout's nodes and leaves): blocks of 2 MiB or more are 2 MiB-aligned and
// marked for transparent huge pages (madvise(MADV_HUGEPAGE)) before they are first touched.
//
// Why: an incoherent ray over ~1e6 triangles touches a handful of nodes and leaves spread over
// ~80 MB. With 4 KiB pages nearly every one of those reads also misses the TLB (a few
// thousand entries cover a few MB) and walks the page table; with 2 MiB pages the whole
// layout fits in the TLB. Embree allocates its BVH the same way (its own mmap). Where transparent huge
// pages are disabled (or not Linux) the advice is ignored and nothing changes but the
// alignment. Smaller blocks come from operator new as usual.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace spatial {

template <class T>
struct huge_page_allocator {
    using value_type = T;
    static constexpr std::size_t huge_page_bytes = std::size_t(2) << 20;

    huge_page_allocator() noexcept = default;
    template <class U>
    huge_page_allocator(const huge_page_allocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = n * sizeof(T);
        if (bytes < huge_page_bytes) return static_cast<T*>(::operator new (bytes, std::align_val_t{alignof(T)}));
        const std::size_t rounded = rounded_bytes(bytes);
#if defined(__linux__)
        // Straight from the kernel, 2 MiB-aligned (map a huge page more, unmap the slack):
        // freshly mapped pages take the huge-page advice on their first touch. A block from
        // malloc's heap may be memory it kept after a free (harness/allocator_policy.hpp keeps
        // all of it), already faulted in as 4 KiB pages, which the advice does not change: the
        // 1e6-triangle incoherent ray figures were 1.6-1.7x slower so (2026-11-28).
        void* raw =
            ::mmap(nullptr, rounded + huge_page_bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        const auto base = reinterpret_cast<std::uintptr_t>(raw);
        const std::uintptr_t aligned = (base + huge_page_bytes - 1) & ~std::uintptr_t(huge_page_bytes - 1);
        if (aligned != base) ::munmap(raw, aligned - base);
        if (const std::size_t tail = base + huge_page_bytes - aligned; tail != 0)
            ::munmap(reinterpret_cast<void*>(aligned + rounded), tail);
        void* p = reinterpret_cast<void*>(aligned);
#if defined(MADV_HUGEPAGE)
        ::madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves 4 KiB pages
#endif
#else
        void* p = std::aligned_alloc(huge_page_bytes, rounded);
        if (!p) throw std::bad_alloc();
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < huge_page_bytes)
            ::operator delete (p, std::align_val_t{alignof(T)});
        else
#if defined(__linux__)
            ::munmap(p, rounded_bytes(bytes));
#else
            std::free(p);
#endif
    }
    static constexpr std::size_t rounded_bytes(std::size_t bytes) {
        return (bytes + huge_page_bytes - 1) / huge_page_bytes * huge_page_bytes;
    }
    template <class U>
    bool operator==(const huge_page_allocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace spatial
