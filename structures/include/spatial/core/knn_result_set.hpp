#pragma once
// knn_result_set: the k best candidates seen so far (the nanoflann "result set" idea: the
// search asks worst() to prune, and worst() is a cached member, not a heap inspection).
// Small k (<= 32, the common case): a sorted array with insertion, O(k) per accepted
// candidate but branch-friendly, held in the set itself: no allocation per query (a query on
// a cache-resident set costs well under a microsecond, and a malloc/free pair was a visible
// part of it: results/checks/knn_leaf_distances). Large k: a binary max-heap on the heap,
// O(log k); it orders equal distances arbitrarily. finish() returns the candidates sorted by
// increasing distance.
// Ties: a candidate equal to the current worst is not accepted (the first found is kept).

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "spatial/core/slot_storage.hpp"

namespace spatial {

template <class T>
struct neighbor_candidate {
    T distance_squared;
    slot_index slot;
    friend bool operator<(const neighbor_candidate& a, const neighbor_candidate& b) {
        return a.distance_squared < b.distance_squared;
    }
};

template <class T>
class knn_result_set {
public:
    static constexpr std::size_t sorted_array_limit = 32;

    // k >= 1 (containers answer k = 0 before searching).
    explicit knn_result_set(std::size_t k) : k_(k < 1 ? 1 : k) {
        if (k_ > sorted_array_limit) heap_.reserve(k_);
    }

    // Squared distance a candidate must beat to enter; +inf until k candidates are held.
    T worst() const { return worst_; }

    void add(T d2, slot_index s) {
        if (!(d2 < worst_)) return;
        if (k_ <= sorted_array_limit) {
            std::size_t i = held_;
            if (i == k_) --i;  // the current worst falls out
            else ++held_;
            while (i > 0 && sorted_[i - 1].distance_squared > d2) {
                sorted_[i] = sorted_[i - 1];
                --i;
            }
            sorted_[i] = {d2, s};
            if (held_ == k_) worst_ = sorted_[held_ - 1].distance_squared;
            return;
        }
        add_to_heap(d2, s);
    }

    std::size_t size() const { return k_ <= sorted_array_limit ? held_ : heap_.size(); }

    // Empty again, keeping k and the storage (a batch reuses one set for all its queries).
    void reset() {
        held_ = 0;
        heap_.clear();
        worst_ = std::numeric_limits<T>::infinity();
    }

    // Sorted by increasing distance; valid until the next add or reset.
    std::span<const neighbor_candidate<T>> finish() {
        if (k_ <= sorted_array_limit) return {sorted_.data(), held_};
        std::sort_heap(heap_.begin(), heap_.end());
        return heap_;
    }

private:
    void add_to_heap(T d2, slot_index s) {
        if (heap_.size() < k_) {
            heap_.push_back({d2, s});
            std::push_heap(heap_.begin(), heap_.end());
        } else {
            std::pop_heap(heap_.begin(), heap_.end());
            heap_.back() = {d2, s};
            std::push_heap(heap_.begin(), heap_.end());
        }
        if (heap_.size() == k_) worst_ = heap_.front().distance_squared;
    }

    std::size_t k_;
    T worst_ = std::numeric_limits<T>::infinity();
    std::size_t held_ = 0;                                            // k <= sorted_array_limit
    std::array<neighbor_candidate<T>, sorted_array_limit> sorted_;  // its first held_, sorted
    std::vector<neighbor_candidate<T>> heap_;                         // k > sorted_array_limit
};

}  // namespace spatial
