#pragma once
// spatial::collision_grid<O> — a broad-phase structure for scenes where most objects move
// every step: it stores the objects with stable handles and answers each pair query with a
// grid REBUILT from scratch by counting sort (collide/cell_sort_grid.hpp). No index is
// maintained between queries, so moving an object is O(1) and the whole pair query is
// O(n + e + k) on boxes of similar size (e cell entries, k overlapping pairs) — cheaper than
// repairing any dynamic index when a sizeable fraction of the objects moved.
//
// Moving sets (collide/fat_box_pairs.hpp): a sequential self-pair query that follows update()s
// of the same objects keeps the pairs of the boxes grown by a measured margin, and the next
// queries re-test only those candidates while every object stays inside its grown box: most
// steps of a simulation then cost three linear passes (gather, containment, candidates)
// instead of a grid. The answers are the same pairs. A query with no update() since the
// previous one answers from a live list but never builds one (a static set runs the grid at
// every query); the parallel and bipartite queries run the grid as before.
//
// Semantics as every structure's pair queries (collide/pairs.hpp): each pair once, self
// pairs as (lower slot, higher slot), sorted by slot; candidates = closed bounding boxes
// overlap; exact adds collide::narrow_phase. Box range queries are a linear scan (this is a
// collision structure, not a general index). Queries are const but reuse mutable scratch
// buffers: concurrent queries on one object race.

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/collide/cell_sort_grid.hpp"
#include "spatial/collide/fat_box_pairs.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/objects/box.hpp"

namespace spatial {

template <stored_object O>
class collision_grid {
public:
    using value_type = O;
    using scalar_type = typename O::scalar_type;
    using point_type = point_type_of<O>;
    using size_type = std::size_t;
    using iterator = slot_iterator<O>;
    using const_iterator = iterator;
    static constexpr std::size_t dimension = O::dimension;
    using bounds = collide::box_bounds<scalar_type, dimension>;

    explicit collision_grid(collide::cell_sort_grid_config config = {}) : grid_(config) {}
    template <class InputIt>
    collision_grid(InputIt first, InputIt last, collide::cell_sort_grid_config config = {}) : grid_(config) {
        insert(first, last);
    }

    // O(1).
    iterator insert(const O& x) {
        detail::require_finite_object(x, "collision_grid::insert");
        renumbered();
        return make(slots_.allocate(x, 1));
    }
    // Validates the whole batch before storing any of it. O(m). A forward range is validated
    // where it is (a single-pass one is copied first).
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        if constexpr (std::forward_iterator<InputIt>) {
            std::size_t m = 0;
            for (auto it = first; it != last; ++it, ++m) detail::require_finite_object(*it, "collision_grid::insert(first, last)");
            store(first, last, m);
        } else {
            const std::vector<O> batch(first, last);
            for (const O& x : batch) detail::require_finite_object(x, "collision_grid::insert(first, last)");
            store(batch.begin(), batch.end(), batch.size());
        }
    }
    // O(1). Returns the next element in iteration order.
    iterator erase(const_iterator pos) {
        check(pos, "collision_grid::erase");
        const slot_index s = pos.slot();
        renumbered();
        slots_.release(s);
        return make(slots_.next_occupied(s + 1));
    }
    // Moves the object at pos (same handle). O(1).
    iterator update(const_iterator pos, const O& x) {
        detail::require_finite_object(x, "collision_grid::update");
        check(pos, "collision_grid::update");
        slots_.replace(pos.slot(), x);
        moved_ = true;
        return pos;
    }
    // Moves many: [first, last) yields (iterator, new object) pairs. Every pair is validated
    // before any object is replaced (a NaN leaves the grid unchanged). O(m).
    template <class PairIt>
    void update(PairIt first, PairIt last) {
        for (auto it = first; it != last; ++it) {
            detail::require_finite_object(it->second, "collision_grid::update(first, last)");
            check(it->first, "collision_grid::update(first, last)");
        }
        for (auto it = first; it != last; ++it) slots_.replace(it->first.slot(), it->second);
        moved_ = true;
    }
    void clear() {
        renumbered();
        slots_.clear();
    }

    size_type size() const { return slots_.size(); }
    bool empty() const { return slots_.size() == 0; }
    iterator begin() const { return make(slots_.next_occupied(0)); }
    iterator end() const { return make(static_cast<slot_index>(slots_.capacity())); }
    std::size_t memory_bytes() const {
        return sizeof(*this) + slots_.memory_bytes() + grid_.memory_bytes() + moving_.memory_bytes() +
               (boxes_.capacity() + previous_boxes_.capacity() + before_boxes_.capacity()) * sizeof(bounds) +
               (slot_of_.capacity() + other_slot_of_.capacity()) * sizeof(slot_index) +
               other_boxes_.capacity() * sizeof(bounds);
    }
    // Every stored object overlapping the closed box: a linear scan, O(n).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        std::vector<iterator> out;
        for (auto it = begin(); it != end(); ++it)
            if (object_overlaps_box(*it, lo, hi)) out.push_back(it);
        return out;
    }

    // Pairs of distinct stored objects (collide/pairs.hpp). O(n + e + k) plus sorting k.
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
        std::vector<std::pair<iterator, iterator>> out;
        for_each_self_pair(filter, [&](iterator a, iterator b) { out.emplace_back(a, b); });
        sort_pairs(out);
        return out;
    }
    // The same pairs, unsorted, to a callback f(a, b) with a.slot() < b.slot(): no result
    // vector, no sort (what a simulation loop wants). The order is deterministic: the grid's,
    // or increasing (a.slot(), b.slot()) for a query answered from the moving set's candidate
    // list (fat_box_pairs.hpp; then O(n + c) for c candidates).
    template <class F>
    void for_each_self_pair(pair_filter filter, F&& f) const {
        const moving_gather gathered = gather_for_moving_set();
        const bool narrow = filter == pair_filter::exact && !box_test_is_exact;
        // With no free slot (nothing erased), box i is slot i: no lookup per pair.
        const bool dense = slots_.size() == slots_.capacity();
        auto deliver = [&](std::uint32_t i, std::uint32_t j) {
            const slot_index s = dense ? i : slot_of_[i], t = dense ? j : slot_of_[j];
            if (narrow && !collide::narrow_phase(slots_.value(s), slots_.value(t))) return;
            // min / max rather than a swap: which of the two is lower is a coin toss, and
            // a branch on it mispredicted about once in three pairs.
            f(make(std::min(s, t)), make(std::max(s, t)));
        };
        auto full_query = [&](const std::vector<bounds>& fat, auto&& collect) { grid_.self_pairs(fat, collect); };
        if (moving_.answer(boxes_, gathered.moved, gathered.previous, gathered.before, gathered.covered, full_query, deliver)) return;
        grid_.self_pairs(boxes_, deliver);
    }
    // The same pairs as for_each_self_pair(filter, f), found on the threads of the parallel
    // back end (spatial::par, core/parallel.hpp): the boxes are gathered in parallel chunks
    // and the grid is cut into one slab of cell layers per thread (cell_sort_grid.hpp,
    // self_pairs_in_slabs), the narrow phase running in the slabs' threads. f is then called
    // on the calling thread, once per pair, in an order that depends on the thread count.
    template <class F>
    void for_each_self_pair(parallel_policy, pair_filter filter, F&& f) const {
        const bool dense = gather_on_every_core();
        const bool narrow = filter == pair_filter::exact && !box_test_is_exact;
        auto slot = [&](std::uint32_t i) { return dense ? static_cast<slot_index>(i) : slot_of_[i]; };
        grid_.self_pairs_in_slabs(
            boxes_, detail::parallel_threads(),
            [&](std::uint32_t i, std::uint32_t j) {
                return !narrow || collide::narrow_phase(slots_.value(slot(i)), slots_.value(slot(j)));
            },
            [&](std::uint32_t i, std::uint32_t j) {
                const slot_index s = slot(i), t = slot(j);
                f(make(std::min(s, t)), make(std::max(s, t)));
            });
    }
    // The same pairs again, each delivered where it is found: f(part, a, b), a.slot() <
    // b.slot(), is called from the threads of the parallel back end, part <
    // detail::parallel_threads() (at least 1). Calls with different parts run concurrently,
    // calls with one part one after the other, so f can collect per part without a lock (as
    // Embree's rtcCollide calls its callback from its threads). Nothing is buffered, and no
    // pair waits for the calling thread: the choice for a consumer whose own work per pair
    // (a contact, a checksum) would otherwise run on one core. Which part reports a pair, and
    // the order within a part, depend on the thread count; the set does not.
    template <class F>
    void for_each_self_pair_concurrently(parallel_policy, pair_filter filter, F&& f) const {
        const bool dense = gather_on_every_core();
        const bool narrow = filter == pair_filter::exact && !box_test_is_exact;
        auto slot = [&](std::uint32_t i) { return dense ? static_cast<slot_index>(i) : slot_of_[i]; };
        grid_.self_pairs_in_slabs_concurrently(
            boxes_, detail::parallel_threads(), [&](std::size_t part, std::uint32_t i, std::uint32_t j) {
                const slot_index s = slot(i), t = slot(j);
                if (narrow && !collide::narrow_phase(slots_.value(s), slots_.value(t))) return;
                f(part, make(std::min(s, t)), make(std::max(s, t)));
            });
    }
    // self_pairs(filter) on several threads: the same sorted answer.
    std::vector<std::pair<iterator, iterator>> self_pairs(parallel_policy, pair_filter filter = pair_filter::exact) const {
        std::vector<std::pair<iterator, iterator>> out;
        for_each_self_pair(par, filter, [&](iterator a, iterator b) { out.emplace_back(a, b); });
        sort_pairs(out);
        return out;
    }
    // Bipartite pairs. With another collision_grid, one grid over both sets; otherwise the
    // generic pairs_between (other's box queries).
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        if constexpr (requires { other.grid_stats(); other.gather_into(boxes_, slot_of_); }) {
            std::vector<std::pair<iterator, typename Other::iterator>> out;
            gather(*this, boxes_, slot_of_);
            other.gather_into(other_boxes_, other_slot_of_);
            grid_.bipartite_pairs(boxes_, other_boxes_, [&](std::uint32_t i, std::uint32_t j) {
                const slot_index s = slot_of_[i], t = other_slot_of_[j];
                const auto ot = other.make_iterator(t);
                if (filter == pair_filter::exact && !collide::narrow_phase(slots_.value(s), *ot)) return;
                out.emplace_back(make(s), ot);
            });
            sort_pairs(out);
            return out;
        } else {
            return pairs_between(*this, other, filter);
        }
    }
    // Statistics of the last pair query that ran the grid (cells, entries, pairs looked at,
    // cell size).
    const typename collide::cell_sort_grid<scalar_type, dimension>::query_stats& grid_stats() const {
        return grid_.last_query_stats();
    }
    // The moving set's candidate lists so far: built, queries answered from one, the current
    // list's candidates and margin.
    const typename collide::fat_box_pairs<scalar_type, dimension>::statistics& candidate_list_stats() const {
        return moving_.stats();
    }

    // For pairs_with between two collision_grids of possibly different object types.
    template <class Bounds>
    void gather_into(std::vector<Bounds>& boxes, std::vector<slot_index>& slot_of) const {
        gather(*this, boxes, slot_of);
    }
    iterator make_iterator(slot_index s) const { return make(s); }

private:
    // For boxes and points the grid's closed box test IS the exact test: no second look at
    // the objects (which would cost a cache miss per pair).
    static constexpr bool box_test_is_exact =
        std::is_same_v<O, objects::box<scalar_type, dimension>> || std::is_same_v<O, point_type>;

    // The boxes for a parallel query. With no free slot (nothing erased) slot i is object i
    // and each chunk of boxes is written independently, on every core; otherwise they are
    // gathered with their slots on the calling thread. Returns whether the storage is dense.
    // Boxes that still hold the last query's, with no update, insert or erase since, are used
    // as they are, as a sequential query does (gather_for_moving_set): a repeated query on an
    // unchanged set no longer copies every box first (1e6 boxes: 48 MB read and written). The
    // flags are left alone: the next sequential query must still see an update() since its
    // own last query.
    bool gather_on_every_core() const {
        const bool dense = slots_.size() == slots_.capacity();
        if (boxes_current_ && !moved_ && boxes_.size() == slots_.size()) return dense;
        if (!dense) {
            gather(*this, boxes_, slot_of_);
            return false;
        }
        boxes_.resize(slots_.size());
        slot_of_.clear();
        detail::parallel_chunks(boxes_.size(), 1 << 14, [&](std::size_t first, std::size_t last) {
            for (std::size_t i = first; i < last; ++i) boxes_[i] = bounds_of(slots_.value(static_cast<slot_index>(i)));
        });
        return true;
    }
    // The objects were renumbered: the last query's boxes and candidate list no longer apply.
    void renumbered() {
        boxes_current_ = false;
        moving_.forget();
    }
    // What a sequential self-pair query hands the moving set's list (fat_box_pairs::answer):
    // whether the objects moved since the previous query (none inserted or erased), the
    // previous two queries' boxes where they were kept (else null), and whether every box lies
    // inside its fat box of the live list.
    struct moving_gather {
        bool moved = false;
        const std::vector<bounds>* previous = nullptr;
        const std::vector<bounds>* before = nullptr;
        bool covered = false;
    };
    // gather() for a sequential self-pair query, with the containment check in the same pass.
    // While the list may be rebuilt soon (fat_box_pairs::wants_previous), the boxes of the
    // previous two queries are kept in previous_boxes_ and before_boxes_ (swaps, no copy): what
    // a new list measures each box's motion from. A query with no update() since reuses the
    // gathered boxes as they are.
    moving_gather gather_for_moving_set() const {
        const bool updated = std::exchange(moved_, false);
        const bool comparable = boxes_current_ && boxes_.size() == slots_.size();
        moving_gather out;
        out.moved = updated && comparable;
        const bool keep = out.moved && moving_.wants_previous();
        if (keep) out.previous = &previous_boxes_;
        if (keep && kept_previous_) out.before = &before_boxes_;  // the previous query kept its previous boxes too
        kept_previous_ = keep;
        boxes_current_ = true;
        if (comparable && !updated) {  // unchanged since the last query
            out.covered = moving_.live();
            return out;
        }
        if (keep) {
            before_boxes_.swap(previous_boxes_);
            previous_boxes_.swap(boxes_);
        }
        if (!(moving_.live() && comparable)) {
            gather(*this, boxes_, slot_of_);
            return out;
        }
        boxes_.resize(slots_.size());
        slot_of_.clear();
        bool covered = true;
        std::size_t k = 0;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1), ++k) {
            const bounds b = bounds_of(slots_.value(s));
            covered &= moving_.contains(k, b);
            boxes_[k] = b;
            slot_of_.push_back(s);
        }
        out.covered = covered;
        return out;
    }
    template <class Bounds = bounds>
    static Bounds bounds_of(const O& x) {
        Bounds b;
        for (std::size_t i = 0; i < dimension; ++i) b.lo[i] = object_lower(x, i), b.hi[i] = object_upper(x, i);
        return b;
    }
    template <class Self, class Bounds>
    static void gather(const Self& self, std::vector<Bounds>& boxes, std::vector<slot_index>& slot_of) {
        boxes.clear();
        slot_of.clear();
        boxes.reserve(self.slots_.size());
        slot_of.reserve(self.slots_.size());
        for (slot_index s = self.slots_.next_occupied(0); s < self.slots_.capacity(); s = self.slots_.next_occupied(s + 1)) {
            boxes.push_back(bounds_of<Bounds>(self.slots_.value(s)));
            slot_of.push_back(s);
        }
    }
    // Stores m validated objects: the room is made first, so nothing is stored unless all are.
    template <class It>
    void store(It first, It last, std::size_t m) {
        slots_.require_room_for(m, "collision_grid::insert(first, last)");
        slots_.reserve(slots_.capacity() + m);
        renumbered();
        for (; first != last; ++first) slots_.allocate(*first, 1);
    }
    void check(const_iterator pos, const char* what) const {
        if (pos == end() || !slots_.occupied(pos.slot()))
            throw std::invalid_argument(std::string(what) + ": the iterator does not refer to a stored element");
    }
    iterator make(slot_index s) const { return iterator(&slots_, s); }

    slot_storage<O> slots_;
    mutable collide::cell_sort_grid<scalar_type, dimension> grid_;
    mutable std::vector<bounds> boxes_, previous_boxes_, before_boxes_, other_boxes_;
    mutable std::vector<slot_index> slot_of_, other_slot_of_;
    // The moving set's candidate list, and what it needs to know: whether update() ran since
    // the last self-pair query, and whether boxes_ holds the last query's boxes in the
    // current numbering (no insert or erase since).
    mutable collide::fat_box_pairs<scalar_type, dimension> moving_;
    mutable bool moved_ = false, boxes_current_ = false, kept_previous_ = false;
};

}  // namespace spatial
