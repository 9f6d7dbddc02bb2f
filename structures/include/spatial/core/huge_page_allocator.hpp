#pragma once
// spatial::huge_page_allocator<T> — a std::allocator for large, randomly accessed, read-mostly
// arrays (the ray layout's nodes and leaves): blocks of 2 MiB or more are 2 MiB-aligned and
// marked for transparent huge pages (madvise(MADV_HUGEPAGE)) before they are first touched.
//
// Why: an incoherent ray over ~1e6 triangles touches a handful of nodes and leaves spread over
// ~80 MB. With 4 KiB pages nearly every one of those reads also misses the TLB (a few
// thousand entries cover a few MB) and walks the page table; with 2 MiB pages the whole
// layout fits in the TLB. Embree allocates its BVH the same way. Where transparent huge
// pages are disabled (or not Linux) the advice is ignored and nothing changes but the
// alignment. Smaller blocks come from operator new as usual.

#include <cstddef>
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
        const std::size_t rounded = (bytes + huge_page_bytes - 1) / huge_page_bytes * huge_page_bytes;
        void* p = std::aligned_alloc(huge_page_bytes, rounded);
        if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        ::madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves 4 KiB pages
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < huge_page_bytes)
            ::operator delete (p, std::align_val_t{alignof(T)});
        else
            std::free(p);
    }
    template <class U>
    bool operator==(const huge_page_allocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace spatial
