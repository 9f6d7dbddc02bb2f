#pragma once
// knn_result_set: the k best candidates seen so far (the nanoflann "result set" idea: the
// search asks worst() to prune, and worst() is a cached member, not a heap inspection).
// Small k (<= 32, the common case): a sorted array with insertion, O(k) per accepted
// candidate but branch-friendly and allocation-free after reserve. Large k: a binary
// max-heap, O(log k). finish() returns the candidates sorted by increasing distance.
// Ties: a candidate equal to the current worst is not accepted (the first found is kept).

#include <algorithm>
#include <cstddef>
#include <limits>
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
    explicit knn_result_set(std::size_t k) : k_(k < 1 ? 1 : k) { items_.reserve(k_); }

    // Squared distance a candidate must beat to enter; +inf until k candidates are held.
    T worst() const { return worst_; }

    void add(T d2, slot_index s) {
        if (!(d2 < worst_)) return;
        if (k_ <= sorted_array_limit) {
            std::size_t i = items_.size();
            if (i == k_) --i;  // the current worst falls out
            else items_.emplace_back();
            while (i > 0 && items_[i - 1].distance_squared > d2) {
                items_[i] = items_[i - 1];
                --i;
            }
            items_[i] = {d2, s};
            if (items_.size() == k_) worst_ = items_.back().distance_squared;
            return;
        }
        if (items_.size() < k_) {
            items_.push_back({d2, s});
            std::push_heap(items_.begin(), items_.end());
        } else {
            std::pop_heap(items_.begin(), items_.end());
            items_.back() = {d2, s};
            std::push_heap(items_.begin(), items_.end());
        }
        if (items_.size() == k_) worst_ = items_.front().distance_squared;
    }

    std::size_t size() const { return items_.size(); }

    // Empty again, keeping k and the storage (a batch reuses one set for all its queries).
    void reset() {
        items_.clear();
        worst_ = std::numeric_limits<T>::infinity();
    }

    // Sorted by increasing distance.
    std::vector<neighbor_candidate<T>>& finish() {
        if (k_ > sorted_array_limit) std::sort_heap(items_.begin(), items_.end());
        return items_;
    }

private:
    std::size_t k_;
    T worst_ = std::numeric_limits<T>::infinity();
    std::vector<neighbor_candidate<T>> items_;
};

}  // namespace spatial
