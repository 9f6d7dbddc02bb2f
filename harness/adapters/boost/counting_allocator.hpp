#pragma once
// An allocator that adds every allocation's bytes to a caller's counter (and subtracts them on
// deallocation), for the Boost.Geometry rtree adapters: memory_bytes() reports what the tree's
// nodes really take, without guessing Boost's node sizes. Shared by boost_rtree_adapter.cpp
// (the kNN peers) and boost_rtree_collide_index.cpp (the collision peer).

#include <cstddef>
#include <memory>

namespace harness::boost_adapters {

template <class U>
struct counting_allocator {
    using value_type = U;
    std::size_t* bytes;

    explicit counting_allocator(std::size_t* counter) noexcept : bytes(counter) {}
    template <class V>
    counting_allocator(const counting_allocator<V>& other) noexcept : bytes(other.bytes) {}

    U* allocate(std::size_t n) {
        *bytes += n * sizeof(U);
        return std::allocator<U>{}.allocate(n);
    }
    void deallocate(U* p, std::size_t n) noexcept {
        *bytes -= n * sizeof(U);
        std::allocator<U>{}.deallocate(p, n);
    }
    template <class V>
    bool operator==(const counting_allocator<V>& other) const noexcept {
        return bytes == other.bytes;
    }
};

}  // namespace harness::boost_adapters
