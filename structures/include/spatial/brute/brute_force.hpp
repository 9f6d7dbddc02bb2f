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
class brute_force {
public:
    using value_type = O;
    using point_type = point_type_of<O>;
    using scalar_type = typename O::scalar_type;
    using size_type = std::size_t;
    using iterator = slot_iterator<O>;
    using const_iterator = iterator;
    using info_type = intersect_info<point_type>;
    static constexpr std::size_t dimension = O::dimension;

    brute_force() = default;
    template <class InputIt>
    brute_force(InputIt first, InputIt last) { insert(first, last); }

    // ---- insertion -------------------------------------------------------------------
    iterator insert(const O& x) {
        detail::require_finite_object(x, "brute_force::insert");
        return make(slots_.allocate(x, 1));
    }
    // The hint cannot help an unordered array; accepted for interface uniformity.
    iterator insert(const_iterator, const O& x) { return insert(x); }
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        std::vector<O> batch(first, last);  // validate all before storing any
        for (const O& x : batch) detail::require_finite_object(x, "brute_force::insert(first, last)");
        slots_.require_room_for(batch.size(), "brute_force::insert(first, last)");
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
        detail::require_finite_object(x, "brute_force::erase");
        size_type n = 0;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (slots_.value(s) == x) {
                slots_.release(s);
                ++n;
            }
        return n;
    }
    void erase(const_iterator first, const_iterator last) {
        while (first != last) first = erase(first);
    }
    void clear() { slots_.clear(); }

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x) {
        detail::require_finite_object(x, "brute_force::find");
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (slots_.value(s) == x) return make(s);
        return end();
    }
    size_type count(const O& x) const {
        detail::require_finite_object(x, "brute_force::count");
        size_type n = 0;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            n += slots_.value(s) == x;
        return n;
    }

    // ---- ray cast ----------------------------------------------------------------------
    bool intersect(const point_type& origin, const point_type& direction, info_type& info) const {
        return intersect_object(origin, direction, ray_thickness_, info) != end();
    }
    bool intersect(const point_type& origin, const point_type& direction, scalar_type thickness, info_type& info) const {
        return intersect_object(origin, direction, thickness, info) != end();
    }
    // The nearest object hit before info.hit_time, or end().
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const {
        detail::require_finite(origin, "brute_force::intersect", "ray origin");
        detail::require_nonzero_direction(direction, "brute_force::intersect");
        detail::require_nonnegative(thickness, "brute_force::intersect", "ray thickness");
        slot_index hit = no_slot;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (slots_.value(s).intersect(origin, direction, thickness, info)) hit = s;
        return hit == no_slot ? end() : make(hit);
    }
    scalar_type ray_thickness() const { return ray_thickness_; }
    void set_ray_thickness(scalar_type t) {
        detail::require_nonnegative(t, "brute_force::set_ray_thickness", "thickness");
        ray_thickness_ = t;
    }

    // ---- nearest neighbours and ranges ---------------------------------------------------
    std::vector<iterator> find_nearest(const point_type& x, size_type k) const { return find_nearest(x, k, 0); }
    // eps is accepted for interface uniformity; the oracle is always exact.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps) const {
        detail::require_finite(x, "brute_force::find_nearest", "query point");
        detail::require_nonnegative(eps, "brute_force::find_nearest", "eps");
        std::vector<iterator> out;
        if (k == 0 || empty()) return out;
        knn_result_set<scalar_type> best(std::min(k, size()));
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            best.add(object_squared_distance(slots_.value(s), x), s);
        for (const auto& c : best.finish()) out.push_back(make(c.slot));
        return out;
    }
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const {
        detail::require_finite(center, "brute_force::find_in_ball", "center");
        detail::require_nonnegative(radius, "brute_force::find_in_ball", "radius");
        std::vector<iterator> out;
        const scalar_type r2 = radius * radius;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
        return out;
    }
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        detail::require_finite(lo, "brute_force::find_in_box", "box corner lo");
        detail::require_finite(hi, "brute_force::find_in_box", "box corner hi");
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
    size_type size() const { return slots_.size(); }
    bool empty() const { return slots_.size() == 0; }
    iterator begin() const { return make(slots_.next_occupied(0)); }
    iterator end() const { return make(static_cast<slot_index>(slots_.capacity())); }
    std::size_t memory_bytes() const { return sizeof(*this) + slots_.memory_bytes(); }

private:
    iterator make(slot_index s) const { return iterator(&slots_, s); }

    slot_storage<O> slots_;
    scalar_type ray_thickness_ = 0;
};

}  // namespace spatial

#include "spatial/core/point.hpp"
static_assert(spatial::spatial_container<spatial::brute_force<spatial::point<double, 3>>>);
