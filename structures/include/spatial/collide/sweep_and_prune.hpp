#pragma once
// spatial::sweep_and_prune<O> — the baseline broad phase of the collision issue: sort and
// sweep (Baraff 1992, "Dynamic simulation of non-penetrating rigid bodies"; Cohen, Lin,
// Manocha & Ponamgi 1995, "I-COLLIDE"), a structure of its own with stable handles.
//
// Each object's interval on one sweep axis is kept in an array sorted by its lower end. A
// pair query sweeps it once: object i is paired with every later object whose interval
// starts before i's ends, when their boxes also overlap on the other axes (candidates);
// `exact` adds the narrow phase (collide/narrow_phase.hpp).
//  * Axis: the one along which the objects' centres spread most, chosen at each query (a
//    poor axis makes the sweep quadratic: everything overlaps along it).
//  * Temporal coherence: the sorted order is kept between queries; after objects moved a
//    little, an insertion sort repairs it in O(n + swaps) instead of O(n log n).
// Costs: insert / erase / update O(1) (the order is repaired at the next query); a query
// O(n + s + c) with s swaps of the repair and c interval overlaps on the axis, O(n log n)
// when the axis changes. Memory: one (lo, hi, slot) entry per object.
// Queries are const but repair the cached order (a mutable member): like the other
// structures' statistics, concurrent queries on one object race (here on the order).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spatial/collide/pairs.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial {

template <stored_object O>
class sweep_and_prune {
public:
    using value_type = O;
    using scalar_type = typename O::scalar_type;
    using point_type = point_type_of<O>;
    using size_type = std::size_t;
    using iterator = slot_iterator<O>;
    using const_iterator = iterator;
    static constexpr std::size_t dimension = O::dimension;

    sweep_and_prune() = default;
    template <class InputIt>
    sweep_and_prune(InputIt first, InputIt last) { insert(first, last); }

    // O(1); the object joins the sweep order at the next query.
    iterator insert(const O& x) {
        detail::require_finite_object(x, "sweep_and_prune::insert");
        return make(slots_.allocate(x, 1));
    }
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        const std::vector<O> batch(first, last);
        for (const O& x : batch) detail::require_finite_object(x, "sweep_and_prune::insert(first, last)");
        slots_.require_room_for(batch.size(), "sweep_and_prune::insert(first, last)");
        slots_.reserve(slots_.capacity() + batch.size());  // storing the batch cannot then fail half-way
        for (const O& x : batch) slots_.allocate(x, 1);
    }
    // O(1); the slot leaves the sweep order at the next query.
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        if (pos == end() || !slots_.occupied(s)) throw std::invalid_argument("sweep_and_prune::erase: not a stored element");
        slots_.release(s);
        return make(slots_.next_occupied(s + 1));
    }
    // Replaces the object at pos (same handle). O(1); the order is repaired at the next query.
    iterator update(const_iterator pos, const O& x) {
        detail::require_finite_object(x, "sweep_and_prune::update");
        const slot_index s = pos.slot();
        if (pos == end() || !slots_.occupied(s)) throw std::invalid_argument("sweep_and_prune::update: not a stored element");
        slots_.replace(s, x);  // cannot fail: the next pair search re-sorts it
        return make(s);
    }
    void clear() {
        slots_.clear();
        order_.clear();
    }

    size_type size() const { return slots_.size(); }
    bool empty() const { return slots_.size() == 0; }
    iterator begin() const { return make(slots_.next_occupied(0)); }
    iterator end() const { return make(static_cast<slot_index>(slots_.capacity())); }
    std::size_t memory_bytes() const {
        return sizeof(*this) + slots_.memory_bytes() + order_.capacity() * sizeof(entry);
    }
    // Every stored object overlapping the closed box (object_overlaps_box): a linear scan —
    // the sweep structure has no spatial index beyond its sorted axis. O(n).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        std::vector<iterator> out;
        for (auto it = begin(); it != end(); ++it)
            if (object_overlaps_box(*it, lo, hi)) out.push_back(it);
        return out;
    }

    // Pairs of distinct stored objects (collide/pairs.hpp): sorted by slots, each once as
    // (lower, higher). Candidates: boxes overlapping on every axis.
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
        std::vector<std::pair<iterator, iterator>> out;
        refresh_order();
        const std::size_t n = order_.size();
        for (std::size_t i = 0; i < n; ++i) {
            const entry& a = order_[i];
            const O& x = slots_.value(a.slot);
            for (std::size_t j = i + 1; j < n && order_[j].lo <= a.hi; ++j) {
                const O& y = slots_.value(order_[j].slot);
                if (!object_boxes_overlap(x, y)) continue;
                if (filter == pair_filter::exact && !collide::narrow_phase(x, y)) continue;
                slot_index s = a.slot, t = order_[j].slot;
                if (s > t) std::swap(s, t);
                out.emplace_back(make(s), make(t));
            }
        }
        sort_pairs(out);
        return out;
    }
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        return pairs_between(*this, other, filter);
    }
    // Swaps made by the last query's order repair (how coherent the motion was).
    std::size_t last_repair_swaps() const { return swaps_; }

private:
    struct entry {
        scalar_type lo, hi;
        slot_index slot;
    };
    iterator make(slot_index s) const { return iterator(&slots_, s); }
    // Brings order_ up to date: drops erased slots, adds new ones, refreshes every interval
    // on the (possibly new) sweep axis, and restores the sort by insertion sort.
    void refresh_order() const {
        const std::size_t axis = widest_axis();
        std::vector<char> listed(slots_.capacity(), 0);
        std::size_t kept = 0;
        for (const entry& e : order_)
            if (e.slot < slots_.capacity() && slots_.occupied(e.slot) && !listed[e.slot]) {
                listed[e.slot] = 1;
                order_[kept++] = e;
            }
        order_.resize(kept);
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (!listed[s]) order_.push_back({0, 0, s});
        for (entry& e : order_) {
            e.lo = object_lower(slots_.value(e.slot), axis);
            e.hi = object_upper(slots_.value(e.slot), axis);
        }
        swaps_ = 0;
        if (axis != axis_) {
            std::sort(order_.begin(), order_.end(), [](const entry& a, const entry& b) { return a.lo < b.lo; });
            axis_ = axis;
            return;
        }
        for (std::size_t i = 1; i < order_.size(); ++i) {  // insertion sort: O(n + swaps)
            const entry e = order_[i];
            std::size_t j = i;
            for (; j > 0 && order_[j - 1].lo > e.lo; --j) order_[j] = order_[j - 1];
            swaps_ += i - j;
            order_[j] = e;
        }
    }
    std::size_t widest_axis() const {
        std::size_t best = 0;
        scalar_type best_spread = -1;
        for (std::size_t i = 0; i < dimension; ++i) {
            scalar_type lo = 0, hi = 0;
            bool first = true;
            for (auto it = begin(); it != end(); ++it) {
                const scalar_type c = object_center(*it, i);
                if (first) lo = hi = c, first = false;
                lo = std::min(lo, c);
                hi = std::max(hi, c);
            }
            if (hi - lo > best_spread) best_spread = hi - lo, best = i;
        }
        return best;
    }

    slot_storage<O> slots_;
    mutable std::vector<entry> order_;
    mutable std::size_t axis_ = static_cast<std::size_t>(-1);
    mutable std::size_t swaps_ = 0;
};

}  // namespace spatial
