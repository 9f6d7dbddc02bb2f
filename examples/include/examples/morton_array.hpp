#pragma once
// examples::morton_array<O> — a structure that is NOT part of the library, added to the
// harness exactly as docs/adding-a-structure.md says (this header, one registry line, one
// typed-test line, docs). It is the proof that a researcher's own structure enters every
// suite, scene and plot in a few files, so it is kept small and plain rather than fast.
//
// Idea: a one-level bounding-box hierarchy over a space-filling curve. The objects are sorted
// by the Morton (Z-order) code of their bounding-box centres (Morton 1966; the ordering of
// linear BVHs, Lauterbach et al. 2009) and cut into blocks of `block` consecutive objects;
// each block keeps the bounding box of its objects' full extents. A query tests the block
// boxes and scans only the blocks it cannot rule out. Insertions go to an unsorted tail that
// every query scans; when the tail outgrows an eighth of the size, or erasures leave a
// quarter of the array as holes, everything is re-sorted.
//
// Complexity (n objects, B = block): build O(n log n); insert O(log n) amortised (a re-sort of
// O(n log n) every n/8 insertions); erase O(1) plus the amortised re-sort; kNN, ball, box,
// ray and find O(n/B + tail + objects in the blocks not ruled out) — linear in n with a small
// constant, which the complexity plots show. Iterators: slot handles (container_base), valid
// until their element is erased.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

#include "spatial/collide/pairs.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/morton_order.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/octree/ray_cell_clip.hpp"

namespace examples {

template <spatial::stored_object O, std::size_t Block = 16>
class morton_array : public spatial::container_base<morton_array<O, Block>, O> {
    using contract_base = spatial::container_base<morton_array<O, Block>, O>;
    friend contract_base;

public:
    static constexpr const char* structure_name = "morton_array";
    static constexpr std::size_t block = Block;
    SPATIAL_CONTAINER_BASE_MEMBERS(contract_base);

    morton_array() = default;
    template <class InputIt>
    morton_array(InputIt first, InputIt last) {
        insert(first, last);
    }

    // ---- insertion -------------------------------------------------------------------
    iterator insert(const O& x) {
        spatial::detail::require_finite_object(x, site("insert"));
        const spatial::slot_index s = add_to_tail(x);
        if (tail_.size() > tail_limit()) resort();
        return make(s);
    }
    // An array has no position a hint could save searching for.
    iterator insert(const_iterator, const O& x) { return insert(x); }
    // Bulk: validates everything first, then sorts once, O((n + m) log(n + m)).
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        const std::vector<O> batch(first, last);
        for (const O& x : batch) spatial::detail::require_finite_object(x, site("insert(first, last)"));
        slots_.require_room_for(batch.size(), site("insert(first, last)"));
        slots_.reserve(slots_.capacity() + batch.size());
        for (const O& x : batch) add_to_tail(x);
        if (tail_.size() > tail_limit()) resort();
    }

    // ---- erasure ---------------------------------------------------------------------
    iterator erase(const_iterator pos) {
        const spatial::slot_index s = pos.slot();
        remove(s);
        after_erase();
        return make(slots_.next_occupied(s + 1));
    }
    size_type erase(const O& x) {
        spatial::detail::require_finite_object(x, site("erase"));
        const std::vector<spatial::slot_index> hits = equal_to(x, false);
        for (spatial::slot_index s : hits) remove(s);
        if (!hits.empty()) after_erase();
        return hits.size();
    }
    void clear() {
        slots_.clear();
        order_.clear();
        boxes_.clear();
        tail_.clear();
        holes_ = 0;
    }

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x) {
        spatial::detail::require_finite_object(x, site("find"));
        const auto hits = equal_to(x, true);
        return hits.empty() ? end() : make(hits.front());
    }
    size_type count(const O& x) const {
        spatial::detail::require_finite_object(x, site("count"));
        return equal_to(x, false).size();
    }

    // ---- ray cast --------------------------------------------------------------------
    // The nearest object hit before info.hit_time, or end(). A block is scanned when the
    // (thick) ray meets its box grown conservatively (octree/ray_cell_clip.hpp).
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const {
        spatial::detail::require_finite(origin, site("intersect"), "ray origin");
        spatial::detail::require_nonzero_direction(direction, site("intersect"));
        spatial::detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
        spatial::slot_index hit = spatial::no_slot;
        auto test = [&](spatial::slot_index s) {
            if (slots_.value(s).intersect(origin, direction, thickness, info)) hit = s;
        };
        std::array<T, D> o, v;
        for (std::size_t i = 0; i < D; ++i) o[i] = origin[i], v[i] = direction[i];
        for (std::size_t b = 0; b < boxes_.size(); ++b) {
            T t0 = 0, t1 = info.hit_time;
            if (spatial::detail::clip_box<T, D>(o, v, boxes_[b].lo, boxes_[b].hi, thickness, t0, t1))
                for_each_in_block(b, test);
        }
        for (spatial::slot_index s : tail_) test(s);
        return hit == spatial::no_slot ? end() : make(hit);
    }

    // ---- nearest neighbours and ranges -------------------------------------------------
    // Blocks in order of their boxes' distance lower bound; stops when (1 + eps) times the
    // next bound reaches the k-th distance. Sorted by increasing distance.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps) const {
        spatial::detail::require_finite(x, site("find_nearest"), "query point");
        spatial::detail::require_nonnegative(eps, site("find_nearest"), "eps");
        std::vector<iterator> out;
        if (k == 0 || slots_.size() == 0) return out;
        spatial::knn_result_set<T> best(std::min<std::size_t>(k, slots_.size()));
        for (spatial::slot_index s : tail_) best.add(spatial::object_squared_distance(slots_.value(s), x), s);
        std::vector<std::pair<T, std::size_t>> by_bound(boxes_.size());
        for (std::size_t b = 0; b < boxes_.size(); ++b) by_bound[b] = {bound_squared(b, x), b};
        std::sort(by_bound.begin(), by_bound.end());
        const T factor = (1 + eps) * (1 + eps);
        for (const auto& [bound, b] : by_bound) {
            if (!(bound * bound_slack * factor < best.worst())) break;
            for_each_in_block(b, [&](spatial::slot_index s) {
                best.add(spatial::object_squared_distance(slots_.value(s), x), s);
            });
        }
        for (const auto& c : best.finish()) out.push_back(make(c.slot));
        return out;
    }
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const {
        spatial::detail::require_finite(center, site("find_in_ball"), "center");
        spatial::detail::require_nonnegative(radius, site("find_in_ball"), "radius");
        std::vector<iterator> out;
        const T r2 = radius * radius;
        auto keep = [&](spatial::slot_index s) {
            if (spatial::object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
        };
        for (std::size_t b = 0; b < boxes_.size(); ++b)
            if (bound_squared(b, center) * bound_slack <= r2) for_each_in_block(b, keep);
        for (spatial::slot_index s : tail_) keep(s);
        return out;
    }
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        spatial::detail::require_finite(lo, site("find_in_box"), "box corner lo");
        spatial::detail::require_finite(hi, site("find_in_box"), "box corner hi");
        std::vector<iterator> out;
        auto keep = [&](spatial::slot_index s) {
            if (spatial::object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
        };
        for (std::size_t b = 0; b < boxes_.size(); ++b)
            if (box_overlaps(b, lo, hi)) for_each_in_block(b, keep);
        for (spatial::slot_index s : tail_) keep(s);
        return out;
    }

    // ---- collision pairs: the library's generic joins over find_in_box -----------------
    std::vector<std::pair<iterator, iterator>> self_pairs(spatial::pair_filter filter = spatial::pair_filter::exact) const {
        return spatial::self_pairs_by_queries(*this, filter);
    }
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(
        const Other& other, spatial::pair_filter filter = spatial::pair_filter::exact) const {
        return spatial::pairs_between(*this, other, filter);
    }

    std::size_t memory_bytes() const {
        return sizeof(*this) + slots_.memory_bytes() + order_.capacity() * sizeof(spatial::slot_index) +
               boxes_.capacity() * sizeof(block_box) + tail_.capacity() * sizeof(spatial::slot_index);
    }

private:
    using T = scalar_type;
    static constexpr std::size_t D = O::dimension;
    // Distances to a box can round a few ulps above an object's exact distance (a sphere's).
    static constexpr T bound_slack = 1 - 16 * std::numeric_limits<T>::epsilon();
    // Slot meta: the position in order_, or in_tail | position in tail_.
    static constexpr std::uint32_t in_tail = 1u << 31;
    struct block_box {
        std::array<T, D> lo, hi;
    };

    std::size_t tail_limit() const { return std::max<std::size_t>(32, slots_.size() / 8); }

    spatial::slot_index add_to_tail(const O& x) {
        const auto s = slots_.allocate(x, in_tail | static_cast<std::uint32_t>(tail_.size()));
        tail_.push_back(s);
        return s;
    }
    // Takes slot s out of the index (the caller releases the slot).
    void remove(spatial::slot_index s) {
        const std::uint32_t m = slots_.meta(s);
        if (m & in_tail) {
            const std::uint32_t i = m & ~in_tail;
            tail_[i] = tail_.back();
            slots_.set_meta(tail_[i], in_tail | i);
            tail_.pop_back();
        } else {
            order_[m] = spatial::no_slot;
            ++holes_;
        }
        slots_.release(s);
    }
    void after_erase() {
        if (holes_ * 4 > order_.size()) resort();
    }
    // The range-erase hooks of container_base.
    void erase_slots(std::span<const spatial::slot_index> doomed) {
        for (spatial::slot_index s : doomed) remove(s);
        after_erase();
    }
    void rebuild_survivors() { resort(); }

    // Sorts every stored object by the Morton code of its box centre, quantised in the box of
    // all centres (spatial::morton_encoder: 63 / D bits per axis), and recomputes the blocks' boxes. O(n log n).
    void resort() {
        std::vector<spatial::slot_index> all;
        all.reserve(slots_.size());
        for (auto s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) all.push_back(s);
        std::array<T, D> lo, hi;
        lo.fill(std::numeric_limits<T>::max());
        hi.fill(std::numeric_limits<T>::lowest());
        for (auto s : all)
            for (std::size_t i = 0; i < D; ++i) {
                lo[i] = std::min(lo[i], spatial::object_center(slots_.value(s), i));
                hi[i] = std::max(hi[i], spatial::object_center(slots_.value(s), i));
            }
        const spatial::morton_encoder<T, D> encoder(lo, hi);
        std::vector<std::pair<std::uint64_t, spatial::slot_index>> keyed;
        keyed.reserve(all.size());
        for (auto s : all) {
            std::array<T, D> centre;
            for (std::size_t i = 0; i < D; ++i) centre[i] = spatial::object_center(slots_.value(s), i);
            keyed.emplace_back(encoder.code(centre), s);
        }
        std::sort(keyed.begin(), keyed.end());
        order_.resize(keyed.size());
        for (std::size_t p = 0; p < keyed.size(); ++p) {
            order_[p] = keyed[p].second;
            slots_.set_meta(order_[p], static_cast<std::uint32_t>(p));
        }
        boxes_.assign((order_.size() + block - 1) / block, block_box{});
        for (std::size_t b = 0; b < boxes_.size(); ++b) {
            boxes_[b].lo.fill(std::numeric_limits<T>::max());
            boxes_[b].hi.fill(std::numeric_limits<T>::lowest());
            for_each_in_block(b, [&](spatial::slot_index s) {
                for (std::size_t i = 0; i < D; ++i) {
                    boxes_[b].lo[i] = std::min(boxes_[b].lo[i], spatial::object_lower(slots_.value(s), i));
                    boxes_[b].hi[i] = std::max(boxes_[b].hi[i], spatial::object_upper(slots_.value(s), i));
                }
            });
        }
        tail_.clear();
        holes_ = 0;
    }

    template <class F>
    void for_each_in_block(std::size_t b, F&& f) const {
        const std::size_t stop = std::min(order_.size(), (b + 1) * block);
        for (std::size_t p = b * block; p < stop; ++p)
            if (order_[p] != spatial::no_slot) f(order_[p]);
    }
    // Squared distance from x to block b's box (a lower bound on its objects' distances).
    T bound_squared(std::size_t b, const point_type& x) const {
        T d2 = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const T d = std::max({boxes_[b].lo[i] - x[i], T(0), x[i] - boxes_[b].hi[i]});
            d2 += d * d;
        }
        return d2;
    }
    bool box_overlaps(std::size_t b, const point_type& lo, const point_type& hi) const {
        for (std::size_t i = 0; i < D; ++i)
            if (boxes_[b].hi[i] < lo[i] || hi[i] < boxes_[b].lo[i]) return false;
        return true;
    }
    // Stored objects equal to x: only blocks whose box holds x's box can hold them.
    std::vector<spatial::slot_index> equal_to(const O& x, bool first_only) const {
        std::vector<spatial::slot_index> hits;
        auto holds_x = [&](std::size_t b) {
            for (std::size_t i = 0; i < D; ++i)
                if (spatial::object_lower(x, i) < boxes_[b].lo[i] || boxes_[b].hi[i] < spatial::object_upper(x, i))
                    return false;
            return true;
        };
        auto check = [&](spatial::slot_index s) {
            if ((!first_only || hits.empty()) && slots_.value(s) == x) hits.push_back(s);
        };
        for (std::size_t b = 0; b < boxes_.size(); ++b)
            if (holds_x(b)) for_each_in_block(b, check);
        for (spatial::slot_index s : tail_) check(s);
        return hits;
    }

    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;

    std::vector<spatial::slot_index> order_;  // Morton order; no_slot marks an erased entry
    std::vector<block_box> boxes_;            // one per `block` entries of order_
    std::vector<spatial::slot_index> tail_;   // inserted since the last sort
    std::size_t holes_ = 0;                   // no_slot entries in order_
};

}  // namespace examples
