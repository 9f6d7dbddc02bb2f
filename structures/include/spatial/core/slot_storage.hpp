#pragma once
// slot_storage: the element store behind every container, giving STABLE handles.
//
// Elements live in a vector of slots addressed by a 32-bit index; an erased slot goes on a
// free list and is reused by a later insert. An iterator is (storage*, slot index), so it
// stays valid when OTHER elements are inserted or erased, even when the vector grows
// (indices survive reallocation where pointers would not). Each slot carries one word of
// container metadata (`meta`), e.g. the kd-tree's leaf bucket; `vacant` marks a free slot.
//
// Costs: insert/erase O(1) amortised; iteration visits every slot, O(capacity) — capacity is
// the peak size since the last clear(). Memory: sizeof(Value) + 4 bytes per slot.

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <mutex>
#include <limits>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "spatial/core/default_init_allocator.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/reserve_for_push.hpp"

namespace spatial {

using slot_index = std::uint32_t;
inline constexpr slot_index no_slot = std::numeric_limits<slot_index>::max();

template <class Value>
class slot_storage {
public:
    using value_type = Value;
    using meta_type = std::uint32_t;
    // The values' array (what assign takes): resize leaves new trivial values unwritten.
    using value_vector = std::vector<Value, detail::default_init_allocator<Value>>;
    using meta_vector = std::vector<meta_type, detail::default_init_allocator<meta_type>>;
    static constexpr meta_type vacant = std::numeric_limits<meta_type>::max();

    slot_storage() = default;
    slot_storage(const slot_storage&) = default;
    slot_storage& operator=(const slot_storage&) = default;
    // A moved-from storage is empty (not just "valid but unspecified").
    slot_storage(slot_storage&& o) noexcept
        : values_(std::move(o.values_)), meta_(std::move(o.meta_)), free_(std::move(o.free_)), live_(o.live_) {
        o.clear();
    }
    slot_storage& operator=(slot_storage&& o) noexcept {
        if (this != &o) {
            values_ = std::move(o.values_);
            meta_ = std::move(o.meta_);
            free_ = std::move(o.free_);
            live_ = o.live_;
            o.clear();
        }
        return *this;
    }

    slot_index allocate(const Value& v, meta_type meta) {
        assert(meta != vacant);
        if (!free_.empty()) {
            const slot_index s = free_.back();
            free_.pop_back();
            values_[s] = v;
            meta_[s] = meta;
            ++live_;
            return s;
        }
        if (values_.size() >= static_cast<std::size_t>(no_slot))
            throw std::length_error("spatial: more than 2^32-1 elements");
        // Grow both vectors before writing either, so a std::bad_alloc leaves them equal.
        if (values_.size() == values_.capacity()) reserve(values_.size() + 1);
        values_.push_back(v);
        meta_.push_back(meta);
        ++live_;
        return static_cast<slot_index>(values_.size() - 1);
    }

    // The free-list entry is made first: if it cannot be allocated, the slot stays occupied
    // (strong guarantee). After reserve_releases(m), the next m releases cannot throw.
    void release(slot_index s) {
        assert(occupied(s));
        free_.push_back(s);
        meta_[s] = vacant;
        --live_;
    }
    // Room on the free list for m more releases, so that a structure can release slots in its
    // no-fail commit step. Grows as m push_backs would (capacities, and so memory_bytes(), do
    // not change with the reservation).
    void reserve_releases(std::size_t m) { detail::reserve_for_push(free_, m); }
    // Undoes the latest allocate(x) (nothing else changed since), for a structure whose
    // insertion fails after the slot was taken: `reused` is what reuses_a_slot() said before
    // it. Cannot throw: a reused slot goes back where it came from, a new one is popped.
    bool reuses_a_slot() const noexcept { return !free_.empty(); }
    void undo_allocate(slot_index s, bool reused) noexcept {
        assert(occupied(s));
        if (reused) {
            free_.push_back(s);  // within capacity: allocate() popped it
            meta_[s] = vacant;
        } else {
            assert(s + 1 == values_.size());
            values_.pop_back();
            meta_.pop_back();
        }
        --live_;
    }
    // Undoes the latest release(s) (nothing else changed since), restoring its meta word.
    void undo_release(slot_index s, meta_type meta) noexcept {
        assert(!free_.empty() && free_.back() == s);
        free_.pop_back();
        meta_[s] = meta;
        ++live_;
    }

    // Stores values[0, m) in new slots capacity() + i, each with the meta word `meta`, unless
    // valid(values[i]) is false for some i: then nothing is stored and the first such i is
    // returned (m when all are stored). Reuses no free slot. Each value is read once, checked
    // and copied in the same pass: on every core of the parallel back end when `parallel` (a
    // bulk build's batch: on 1e6 triangles the check and the copy took 19 ms on one thread).
    // Strong guarantee; truncate(old capacity()) undoes it.
    template <class RandomIt, class Valid>
    std::size_t append(RandomIt values, std::size_t m, meta_type meta, bool parallel, Valid&& valid) {
        assert(meta != vacant);
        const std::size_t from = values_.size();
        if (m > static_cast<std::size_t>(no_slot) - from) throw std::length_error("spatial: more than 2^32-1 elements");
        reserve(from + m);  // the growth below then cannot throw
        auto value = [&](std::size_t i) -> const Value& { return values[static_cast<std::ptrdiff_t>(i)]; };
        if constexpr (!std::is_default_constructible_v<Value>) {
            for (std::size_t i = 0; i < m; ++i) {  // no slots to copy into: one at a time
                if (!valid(value(i))) [[unlikely]] {
                    truncate(from);
                    return i;
                }
                values_.push_back(value(i));
                meta_.push_back(meta);
                ++live_;
            }
            return m;
        } else {
            values_.resize(from + m);  // left unwritten (default_init_allocator) where Value allows
            meta_.resize(from + m);
            std::size_t first_bad = m;
            std::mutex bad_mutex;
            auto copy = [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) {
                    if (!valid(value(i))) [[unlikely]] {
                        const std::lock_guard<std::mutex> lock(bad_mutex);
                        first_bad = std::min(first_bad, i);
                        return;  // the chunk's first: later ones cannot be the batch's first
                    }
                    values_[from + i] = value(i);
                    meta_[from + i] = meta;
                }
            };
            if (parallel) detail::parallel_chunks(m, 16384, copy);
            else copy(0, m);
            live_ += m;
            if (first_bad != m) truncate(from);
            return first_bad;
        }
    }
    // Removes the slots [from, capacity()), all appended since capacity() was `from`.
    void truncate(std::size_t from) noexcept {
        assert(from <= values_.size());
        live_ -= values_.size() - from;
        values_.erase(values_.begin() + static_cast<std::ptrdiff_t>(from), values_.end());
        meta_.erase(meta_.begin() + static_cast<std::ptrdiff_t>(from), meta_.end());
    }

    // Replace all contents by `values` (slot i = values[i]); every old handle dies.
    // Strong guarantee: the new metadata is made before anything changes.
    void assign(value_vector values, meta_type meta) {
        meta_vector metas(values.size(), meta);
        values_ = std::move(values);
        meta_ = std::move(metas);
        free_.clear();
        live_ = values_.size();
    }

    // Renumbers the slots: new slot i holds what slot old_of_new[i] held, with its meta word.
    // Precondition: no free slot, and old_of_new a permutation of [0, capacity()). For a
    // container that has just built itself from a batch and wants its objects in its own
    // order (no iterator into them exists yet). Copies on every core when `parallel`. Strong
    // guarantee: the new arrays are made in full before they replace the old. O(n).
    void permute(const std::vector<slot_index>& old_of_new, bool parallel) {
        assert(free_.empty() && old_of_new.size() == values_.size());
        const std::size_t n = values_.size();
        value_vector values;
        meta_vector metas(n);
        auto copy = [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                if constexpr (std::is_default_constructible_v<Value>) values[i] = values_[old_of_new[i]];
                metas[i] = meta_[old_of_new[i]];
            }
        };
        if constexpr (std::is_default_constructible_v<Value>) {
            values.resize(n);  // left unwritten (default_init_allocator) where Value allows
        } else {
            values.reserve(n);
            for (std::size_t i = 0; i < n; ++i) values.push_back(values_[old_of_new[i]]);
        }
        if (parallel) detail::parallel_chunks(n, 16384, copy);
        else copy(0, n);
        values_ = std::move(values);
        meta_ = std::move(metas);
    }

    void clear() {
        values_.clear();
        meta_.clear();
        free_.clear();
        live_ = 0;
    }
    // Room for n slots, growing geometrically (so repeated small bulk inserts stay
    // amortised O(1) per element).
    void reserve(std::size_t n) {
        if (n <= values_.capacity() && n <= meta_.capacity()) return;
        n = std::max(n, 2 * values_.capacity());
        values_.reserve(n);
        meta_.reserve(n);
    }
    // Throws std::length_error if m more slots would exceed the 32-bit handle space.
    template <class Where>  // a call_site or a "name::operation" string
    void require_room_for(std::size_t m, Where where) const {
        if (m > static_cast<std::size_t>(no_slot) - values_.size())
            throw std::length_error(detail::site_text(where) + ": more than 2^32-1 elements");
    }

    bool occupied(slot_index s) const { return s < meta_.size() && meta_[s] != vacant; }
    const Value& value(slot_index s) const { return values_[s]; }
    // Replaces an occupied slot's value in place, keeping its meta word (for containers whose
    // metadata does not depend on the value, e.g. collision_grid's O(1) moves).
    void replace(slot_index s, const Value& v) {
        assert(occupied(s));
        values_[s] = v;
    }
    meta_type meta(slot_index s) const { return meta_[s]; }
    void set_meta(slot_index s, meta_type m) { meta_[s] = m; }

    std::size_t size() const { return live_; }
    std::size_t capacity() const { return values_.size(); }

    // First occupied slot at or after s, or capacity().
    slot_index next_occupied(slot_index s) const {
        const std::size_t n = meta_.size();
        while (s < n && meta_[s] == vacant) ++s;
        return static_cast<slot_index>(s);
    }

    std::size_t memory_bytes() const {
        return values_.capacity() * sizeof(Value) + meta_.capacity() * sizeof(meta_type) +
               free_.capacity() * sizeof(slot_index);
    }

    const Value* data() const { return values_.data(); }

private:
    value_vector values_;
    meta_vector meta_;
    std::vector<slot_index> free_;
    std::size_t live_ = 0;
};

// Forward iterator over the occupied slots of a slot_storage. Elements are read-only through
// it (as in std::set): changing a stored object's coordinates in place would break the
// structure's invariants; erase and re-insert instead. iterator == const_iterator.
template <class Value>
class slot_iterator {
public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Value;
    using difference_type = std::ptrdiff_t;
    using pointer = const Value*;
    using reference = const Value&;

    slot_iterator() = default;
    slot_iterator(const slot_storage<Value>* s, slot_index i) : storage_(s), slot_(i) {}

    reference operator*() const { return storage_->value(slot_); }
    pointer operator->() const { return &storage_->value(slot_); }
    slot_iterator& operator++() {
        slot_ = storage_->next_occupied(slot_ + 1);
        return *this;
    }
    slot_iterator operator++(int) {
        auto t = *this;
        ++*this;
        return t;
    }
    friend bool operator==(const slot_iterator& a, const slot_iterator& b) {
        return a.slot_ == b.slot_ && a.storage_ == b.storage_;
    }

    // The stable handle of the element (for containers and for users who need an id).
    slot_index slot() const { return slot_; }

private:
    const slot_storage<Value>* storage_ = nullptr;
    slot_index slot_ = 0;
};

}  // namespace spatial
