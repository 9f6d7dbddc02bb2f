// The replaced global operator new and delete of the allocation-failure test binary
// (failing_allocation.hpp). Memory comes from malloc/aligned_alloc, so AddressSanitizer and
// its leak checker still see every block.

#include "failing_allocation.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace spatial_test::failing_allocation {
namespace {
// Relaxed atomics: a parallel build may allocate on worker threads; only the counts matter.
std::atomic<std::size_t> allocations{0};
// Allocations still to succeed before the armed one fails; 0 = disarmed.
std::atomic<std::size_t> countdown{0};
std::atomic<bool> failure_happened{false};

// Counts one allocation; true if it is the armed one.
bool should_fail() noexcept {
    allocations.fetch_add(1, std::memory_order_relaxed);
    std::size_t left = countdown.load(std::memory_order_relaxed);
    while (left != 0) {
        if (countdown.compare_exchange_weak(left, left - 1, std::memory_order_relaxed)) {
            if (left != 1) return false;
            failure_happened.store(true, std::memory_order_relaxed);
            return true;
        }
    }
    return false;
}
}  // namespace

std::size_t count() noexcept { return allocations.load(std::memory_order_relaxed); }
void reset_count() noexcept { allocations.store(0, std::memory_order_relaxed); }
void fail_at(std::size_t k) noexcept {
    failure_happened.store(false, std::memory_order_relaxed);
    countdown.store(k, std::memory_order_relaxed);
}
void disarm() noexcept { countdown.store(0, std::memory_order_relaxed); }
bool fired() noexcept { return failure_happened.load(std::memory_order_relaxed); }

}  // namespace spatial_test::failing_allocation

namespace {
namespace fa = spatial_test::failing_allocation;

void* allocate(std::size_t n) noexcept {
    if (fa::should_fail()) return nullptr;
    return std::malloc(n == 0 ? 1 : n);
}
void* allocate(std::size_t n, std::align_val_t a) noexcept {
    if (fa::should_fail()) return nullptr;
    const std::size_t al = static_cast<std::size_t>(a) < sizeof(void*) ? sizeof(void*) : static_cast<std::size_t>(a);
    // aligned_alloc wants a non-zero size that is a multiple of the alignment.
    const std::size_t rounded = n == 0 ? al : (n + al - 1) / al * al;
    return std::aligned_alloc(al, rounded);
}
void* allocate_or_throw(std::size_t n) {
    void* p = allocate(n);
    if (!p) throw std::bad_alloc();
    return p;
}
void* allocate_or_throw(std::size_t n, std::align_val_t a) {
    void* p = allocate(n, a);
    if (!p) throw std::bad_alloc();
    return p;
}
}  // namespace

void* operator new(std::size_t n) { return allocate_or_throw(n); }
void* operator new[](std::size_t n) { return allocate_or_throw(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void* operator new(std::size_t n, std::align_val_t a) { return allocate_or_throw(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return allocate_or_throw(n, a); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept { return allocate(n, a); }
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept { return allocate(n, a); }

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
