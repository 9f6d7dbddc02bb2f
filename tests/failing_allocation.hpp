#pragma once
// Fault injection for the allocation-failure tests: the test binary replaces the global
// operator new (every overload, failing_allocation.cpp) with a counting version, and a test
// can arm it so that the k-th allocation from now fails — std::bad_alloc from the throwing
// forms, nullptr from the nothrow forms, as a real out-of-memory would. The technique of
// libc++'s test suite (count_new.h) and Boost.Container's allocation tests.
//
// Only code that allocates through operator new is counted: std::allocator, and the library's
// huge_page_allocator below 2 MiB (the tests stay far below that size).

#include <cstddef>

namespace spatial_test::failing_allocation {

// Allocations (through any operator new) since the last reset_count().
std::size_t count() noexcept;
void reset_count() noexcept;
// The k-th allocation from now (k >= 1) fails, and every later one succeeds.
void fail_at(std::size_t k) noexcept;
// No allocation fails (the default).
void disarm() noexcept;
// Whether the armed failure happened since the last fail_at.
bool fired() noexcept;

// Arms fail_at(k) for its lifetime: disarmed on every exit, so the checks that follow
// allocate freely.
class armed {
public:
    explicit armed(std::size_t k) noexcept { fail_at(k); }
    ~armed() { disarm(); }
    armed(const armed&) = delete;
    armed& operator=(const armed&) = delete;
};

}  // namespace spatial_test::failing_allocation
