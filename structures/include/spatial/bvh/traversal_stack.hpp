#pragma once
// traversal_stack<E, N>: the BVH's traversal stack. The first N entries live inline (no
// allocation for the depths that balanced trees reach: 64 covers 2^64 leaves), deeper ones
// spill to a std::vector, so a degenerate tree (incremental inserts along a line, a skewed SAH
// build) can never overflow it. pbrt-v4 and many ray tracers use a fixed int[64] without a
// check; the cost of the check is one compare per push. push/pop O(1) amortised.

#include <array>
#include <cstddef>
#include <vector>

namespace spatial::bvh_detail {

template <class E, std::size_t N = 64>
class traversal_stack {
public:
    void push(const E& e) {
        if (size_ < N) inline_[size_] = e;
        else spill_.push_back(e);
        ++size_;
    }
    E pop() {
        --size_;
        if (size_ < N) return inline_[size_];
        E e = spill_.back();
        spill_.pop_back();
        return e;
    }
    bool empty() const { return size_ == 0; }
    std::size_t size() const { return size_; }

private:
    std::array<E, N> inline_;  // not value-initialised: zeroing it would cost every query
    std::vector<E> spill_;
    std::size_t size_ = 0;
};

}  // namespace spatial::bvh_detail
