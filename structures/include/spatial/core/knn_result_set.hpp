#pragma once
// knn_result_set: the k best candidates seen so far, as a bounded max-heap on squared
// distance (the nanoflann "result set" idea: the search asks worst() to prune).
// add() is O(log k); finish() sorts ascending, O(k log k). Ties keep the first found.

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
    explicit knn_result_set(std::size_t k) : k_(k) { heap_.reserve(k); }

    // Squared distance a candidate must beat to enter; +inf until k candidates are held.
    T worst() const {
        return heap_.size() < k_ ? std::numeric_limits<T>::infinity() : heap_.front().distance_squared;
    }
    void add(T d2, slot_index s) {
        if (heap_.size() < k_) {
            heap_.push_back({d2, s});
            std::push_heap(heap_.begin(), heap_.end());
        } else if (d2 < heap_.front().distance_squared) {
            std::pop_heap(heap_.begin(), heap_.end());
            heap_.back() = {d2, s};
            std::push_heap(heap_.begin(), heap_.end());
        }
    }
    // Sorted by increasing distance.
    std::vector<neighbor_candidate<T>>& finish() {
        std::sort_heap(heap_.begin(), heap_.end());
        return heap_;
    }

private:
    std::size_t k_;
    std::vector<neighbor_candidate<T>> heap_;
};

}  // namespace spatial
