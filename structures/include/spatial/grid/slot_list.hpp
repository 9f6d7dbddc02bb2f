#pragma once
// spatial::detail::slot_list — one grid cell's list of slots: up to four slot indices stored in
// the list itself, more in one heap block (the small-buffer optimisation of LLVM's SmallVector
// and Boost.Container's small_vector). With 32-bit size and capacity it takes 24 bytes, as the
// std::vector it replaced did, so the inline slots cost no memory; but a cell of at most four
// objects (the grids aim at two per cell) allocates nothing. Building a grid then costs no
// allocation per cell, and reading a cell's slots no pointer chase.
//
// Guarantees: reserve and push_back have the strong guarantee (the new block is allocated
// before anything changes); remove, clear, moves, swap and the destructor do not allocate or
// throw. Order: remove moves the last slot into the removed one's place, as the grids did.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <utility>

#include "spatial/core/reserve_for_push.hpp"  // reserve_for_push works on a slot_list too
#include "spatial/core/slot_storage.hpp"

namespace spatial::detail {

class slot_list {
public:
    static constexpr std::uint32_t inline_slots = 4;

    slot_list() noexcept {}
    slot_list(const slot_list& o) {
        reserve(o.size_);
        std::copy(o.begin(), o.end(), data());
        size_ = o.size_;
    }
    slot_list(slot_list&& o) noexcept { take(o); }
    slot_list& operator=(const slot_list& o) {
        if (this != &o) {
            slot_list copy(o);
            swap(copy);
        }
        return *this;
    }
    slot_list& operator=(slot_list&& o) noexcept {
        if (this != &o) {
            delete_block();
            take(o);
        }
        return *this;
    }
    ~slot_list() { delete_block(); }

    void swap(slot_list& o) noexcept {
        slot_list tmp(std::move(o));
        o = std::move(*this);
        *this = std::move(tmp);
    }

    std::size_t size() const noexcept { return size_; }
    bool empty() const noexcept { return size_ == 0; }
    std::size_t capacity() const noexcept { return capacity_; }
    // Bytes of the heap block (0 while the slots fit in the list itself).
    std::size_t heap_bytes() const noexcept { return on_heap() ? capacity_ * sizeof(slot_index) : 0; }
    const slot_index* begin() const noexcept { return data(); }
    const slot_index* end() const noexcept { return data() + size_; }
    slot_index operator[](std::size_t i) const noexcept { return data()[i]; }

    // Room for n slots (exactly n when it grows). O(size).
    void reserve(std::size_t n) {
        if (n <= capacity_) return;
        if (n > std::numeric_limits<std::uint32_t>::max()) throw std::bad_array_new_length();
        slot_index* block = new slot_index[n];  // the only step that can fail
        std::copy(begin(), end(), block);
        delete_block();
        heap_ = block;
        capacity_ = static_cast<std::uint32_t>(n);
    }
    // Amortised O(1): a full list doubles its capacity.
    void push_back(slot_index s) {
        if (size_ == capacity_) reserve(std::size_t(capacity_) * 2);
        data()[size_++] = s;
    }
    // Removes the first occurrence of s, if any (the last slot takes its place). O(size).
    void remove(slot_index s) noexcept {
        slot_index* d = data();
        for (std::uint32_t i = 0; i < size_; ++i)
            if (d[i] == s) {
                d[i] = d[--size_];
                return;
            }
    }
    void clear() noexcept { size_ = 0; }

private:
    bool on_heap() const noexcept { return capacity_ > inline_slots; }
    slot_index* data() noexcept { return on_heap() ? heap_ : inline_; }
    const slot_index* data() const noexcept { return on_heap() ? heap_ : inline_; }
    void delete_block() noexcept {
        if (on_heap()) delete[] heap_;
    }
    // *this holds no block (a new list, or its block was just deleted): takes o's slots (its
    // block, or a copy of its inline slots) and leaves o empty.
    void take(slot_list& o) noexcept {
        if (o.on_heap()) heap_ = o.heap_;
        else std::copy(o.inline_, o.inline_ + o.size_, inline_);
        size_ = o.size_;
        capacity_ = o.capacity_;
        o.size_ = 0;
        o.capacity_ = inline_slots;
    }

    std::uint32_t size_ = 0;
    std::uint32_t capacity_ = inline_slots;
    union {
        slot_index inline_[inline_slots];
        slot_index* heap_;
    };
};
static_assert(sizeof(slot_list) == 24, "slot_list: as small as the std::vector it replaced");

}  // namespace spatial::detail
