#pragma once
// spatial::brute_force<O> — the oracle: a plain array of objects, every query a linear scan.
// O is a point (point_object) or an object with extent (bounded_object); queries take
// points of point_type_of<O> and ask the objects through object_geometry.hpp, the same
// functions every structure uses, so exact answers compare bit for bit.
//
// It is deliberately simple so that it is obviously right; every other structure is tested
// against it. Complexity: insert/erase(iterator) O(1); find/count/erase(value), kNN
// O(n log k), ball/box O(n), ray cast O(n). Iterators: see slot_storage.hpp (stable under
// other insertions and erasures; clear() invalidates all).

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <limits>
#include <vector>

#include "spatial/core/container_base.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/collide/pairs.hpp"

namespace spatial {

template <stored_object O>
class brute_force : public container_base<brute_force<O>, O> {
    using contract_base = container_base<brute_force<O>, O>;
    friend contract_base;

public:
    static constexpr const char* structure_name = "brute_force";
    SPATIAL_CONTAINER_BASE_MEMBERS(contract_base);

    brute_force() = default;
    template <class InputIt>
    brute_force(InputIt first, InputIt last) { insert(first, last); }

    // ---- insertion -------------------------------------------------------------------
    iterator insert(const O& x) {
        detail::require_finite_object(x, site("insert"));
        return make(slots_.allocate(x, 1));
    }
    // The hint cannot help an unordered array; accepted for interface uniformity.
    iterator insert(const_iterator, const O& x) { return insert(x); }
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        std::vector<O> batch(first, last);  // validate all before storing any
        for (const O& x : batch) detail::require_finite_object(x, site("insert(first, last)"));
        slots_.require_room_for(batch.size(), site("insert(first, last)"));
        slots_.reserve(slots_.capacity() + batch.size());
        for (const O& x : batch) slots_.allocate(x, 1);
    }

    // ---- erasure ---------------------------------------------------------------------
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        slots_.release(s);
        return make(slots_.next_occupied(s + 1));
    }
    size_type erase(const O& x) {
        detail::require_finite_object(x, site("erase"));
        slots_.reserve_releases(count(x));  // the only allocation, before the first release
        size_type n = 0;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (slots_.value(s) == x) {
                slots_.release(s);
                ++n;
            }
        return n;
    }
    void clear() { slots_.clear(); }

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x) {
        detail::require_finite_object(x, site("find"));
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (slots_.value(s) == x) return make(s);
        return end();
    }
    size_type count(const O& x) const {
        detail::require_finite_object(x, site("count"));
        size_type n = 0;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            n += slots_.value(s) == x;
        return n;
    }

    // ---- ray cast ----------------------------------------------------------------------
    // The nearest object hit before info.hit_time, or end().
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const {
        detail::require_finite(origin, site("intersect"), "ray origin");
        detail::require_nonzero_direction(direction, site("intersect"));
        detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
        slot_index hit = no_slot;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (slots_.value(s).intersect(origin, direction, thickness, info)) hit = s;
        return hit == no_slot ? end() : make(hit);
    }

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // eps is accepted for interface uniformity; the oracle is always exact.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps) const {
        detail::require_finite(x, site("find_nearest"), "query point");
        detail::require_nonnegative(eps, site("find_nearest"), "eps");
        std::vector<iterator> out;
        if (k == 0 || empty()) return out;
        knn_result_set<scalar_type> best(std::min(k, size()));
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            best.add(object_squared_distance(slots_.value(s), x), s);
        for (const auto& c : best.finish()) out.push_back(make(c.slot));
        return out;
    }
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const {
        detail::require_finite(center, site("find_in_ball"), "center");
        detail::require_nonnegative(radius, site("find_in_ball"), "radius");
        std::vector<iterator> out;
        const scalar_type r2 = radius * radius;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
        return out;
    }
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        detail::require_finite(lo, site("find_in_box"), "box corner lo");
        detail::require_finite(hi, site("find_in_box"), "box corner hi");
        std::vector<iterator> out;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
        return out;
    }

    // ---- collision pairs (collide/pairs.hpp) ---------------------------------------------
    // The O(n^2) oracle. Candidates: the pairs whose objects' bounding boxes overlap; exact:
    // those the narrow phase confirms. Sorted by slots, self pairs as (lower, higher).
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
        std::vector<std::pair<iterator, iterator>> out;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            for (slot_index t = slots_.next_occupied(s + 1); t < slots_.capacity(); t = slots_.next_occupied(t + 1))
                if (object_boxes_overlap(slots_.value(s), slots_.value(t)) &&
                    (filter == pair_filter::candidates || collide::narrow_phase(slots_.value(s), slots_.value(t))))
                    out.emplace_back(make(s), make(t));
        return out;
    }
    // Pairs (object of *this, object of other), O(n m), any container `other`.
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        std::vector<std::pair<iterator, typename Other::iterator>> out;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            for (auto it = other.begin(); it != other.end(); ++it)
                if (object_boxes_overlap(slots_.value(s), *it) &&
                    (filter == pair_filter::candidates || collide::narrow_phase(slots_.value(s), *it)))
                    out.emplace_back(make(s), it);
        sort_pairs(out);
        return out;
    }

    // ---- STL basics --------------------------------------------------------------------
    std::size_t memory_bytes() const { return sizeof(*this) + slots_.memory_bytes(); }

private:
    // The range-erase hooks of container_base: the array has no index to repair or rebuild.
    void erase_slots(std::span<const slot_index> doomed) {
        for (slot_index s : doomed) this->slots_.release(s);
    }
    void rebuild_survivors() {}

    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;
};

}  // namespace spatial

#include "spatial/core/point.hpp"
static_assert(spatial::spatial_container<spatial::brute_force<spatial::point<double, 3>>>);
