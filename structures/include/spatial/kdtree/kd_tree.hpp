#pragma once
// spatial::kd_tree<O, Config> — a dynamic bucket kd-tree over stored objects: points
// (point_object) or objects with extent (bounded_object: box, sphere, triangle, user types).
//
// Layout (rationale: docs/structures/kd-tree.md; complexity table: docs/contract.md):
//  * Objects live in a slot_storage (stable 32-bit handles = iterators). A bulk build into an
//    empty tree stores them in leaf order, so a leaf's points are contiguous in memory.
//  * Nodes live in one vector; the two children of an inner node are allocated as a pair
//    (first, first + 1), so an inner node needs one child index. A leaf points to a bucket
//    holding up to Config::leaf_capacity slot indices plus the leaf's CELL (the box its
//    ancestors' split planes bound), which makes hinted insertion O(1) when the hint's leaf
//    contains the new point.
//  * Every node keeps `restore`: its parent's cell bound on the parent's split dimension
//    on this node's side, so climbing from a leaf recomputes ancestor cells in O(1) a step.
//  * Balance under churn: (1) scapegoat rule (Galperin & Rivest 1993): an insertion that
//    makes a leaf deeper than log_{1/alpha}(n / leaf_capacity) + 2 rebuilds the lowest
//    ancestor whose heavier child holds more than alpha of its points; (2) when the size
//    drops below alpha times the size at the last full rebuild, or when leaves become on
//    average less than a quarter full, the whole tree is rebuilt. Rebuilding a subtree of
//    m points costs O(m log m) (a kd-subtree is re-split, Overmars 1983), so updates cost
//    O(log^2 n) amortised in the worst case, O(log n) expected on random data; depth stays
//    O(log n), so recursive traversal depth is bounded (no fixed-size stack).
//  * Queries: kNN with incremental distance to the cell (Arya & Mount 1993), optional
//    (1+eps)-approximation (Arya et al. 1998); ball and box range; thick-ray casting by
//    front-to-back traversal of ray-parameter intervals.
//  * Objects with extent: the spatial kd-tree ("skd-tree", Ooi, McDonell & Sacks-Davis 1987;
//    the same idea as the bounding interval hierarchy of Waechter & Keller 2006). Objects are
//    partitioned exactly like points, by the centre of their bounding box (object_center),
//    so each object is stored ONCE: no duplicates, no straddler lists, and erase, count,
//    iteration and "never report an object twice" cost what they cost for points. Because
//    an object may reach beyond its leaf's cell, every node also keeps `extents_[node]`, the
//    bounding box of the full extents of the objects below it, and every query prunes with
//    extents instead of cells (ray: clip to the padded extent of each child, front to back;
//    kNN and ball: distance to the extent less a rounding slack; box: extent overlap).
//    Extents grow on insertion (upwards until a node already contains the object); erasure
//    refits only the leaf, so inner extents may stay loose (conservative, slower, never
//    wrong) until a rebuild of their subtree recomputes them. For points nothing changes: an
//    extent would equal the cell, so none is stored and the point code paths are unchanged.
//  * Collision pairs of objects: the tree descended against itself, as a BVH (Gottschalk,
//    Lin & Manocha 1996) — each object sits in one leaf and each node's subtree box bounds
//    what is below, so node pairs whose boxes overlap are opened, the larger node first.
//
// Files: this header holds the class (types, the public interface with each member's
// contract, the data); the configuration is in kd_tree_config.hpp, and the member definitions,
// included at the end, in kd_tree_storage.hpp (keys, extents, buckets, node pairs),
// kd_tree_update.hpp (insertion and erasure in place), kd_tree_build.hpp ((re)building and the
// scapegoat rule), kd_tree_queries.hpp (kNN, ranges, lookup), kd_tree_rays.hpp (ray casting),
// kd_tree_pairs.hpp (collision pairs) and kd_tree_checks.hpp (diagnostics).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/bv/rounding.hpp"
#include "spatial/collide/box_bounds.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/collide/tree_pair_snapshot.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/free_list.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/knn_batch.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/preorder_plan.hpp"
#include "spatial/core/query_stats.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/kdtree/kd_tree_config.hpp"

namespace spatial {

// Upkeep of the tree's balance, counted always (rebuilds are rare and costly).
struct kd_tree_maintenance_stats {
    std::size_t subtree_rebuilds = 0;  // scapegoat and leaf-split rebuilds
    std::size_t full_rebuilds = 0;
};

template <stored_object O, class Config = kd_tree_config<>>
class kd_tree : public container_base<kd_tree<O, Config>, O> {
    using contract_base = container_base<kd_tree<O, Config>, O>;
    friend contract_base;

public:
    static constexpr const char* structure_name = "kd_tree";
    SPATIAL_CONTAINER_BASE_MEMBERS(contract_base);
    using config = Config;
    static constexpr std::size_t leaf_capacity = Config::leaf_capacity;
    static_assert(leaf_capacity >= 2, "kd_tree: leaf_capacity must be at least 2");
    static_assert(Config::balance_alpha > 0.5 && Config::balance_alpha < 1.0, "kd_tree: alpha in (0.5, 1)");

private:
    using T = scalar_type;
    using P = point_type;  // query points, ray origins and directions
    static constexpr std::size_t D = O::dimension;
    // Objects with extent (skd-tree, see the header comment): nodes also keep the bounding box
    // of their subtree's objects. For points it would equal the cell, so it is not stored.
    static constexpr bool has_extent = bounded_object<O>;
    using coords = std::array<T, D>;
    // Closed box; empty when lo > hi (an empty leaf).
    using extent = collide::box_bounds<T, D>;
    struct no_extent {};
    using node_index = std::uint32_t;
    static constexpr node_index no_node = std::numeric_limits<node_index>::max();
    static constexpr node_index root = 0;

    // Inner nodes: the range of each child's keys along the cut, [left_lo, left_hi] and
    // [right_lo, right_hi], rounded outward to float (a looser bound is still a bound; half
    // the bytes of double keeps a node at 32 B). Searches measure a query's offset to a child
    // from its range instead of the split plane, so empty space (between clusters, around the
    // data) prunes as if the nodes were tight boxes, as CGAL's Kd_tree_internal_node does
    // with lower_low_val ... upper_high_val. Exact after a build, widened by insertion, left
    // loose by erasure.
    struct child_ranges {
        float left_lo, left_hi, right_lo, right_hi;
    };
    // A leaf's use of its bucket. `run` lets a search skip the bucket: when the bucket's
    // slots are run, run + 1, ..., run + count - 1 (every leaf of a bulk build, which lays the
    // points out in leaf order, and of a rebuild whose slots happen to be consecutive), a scan
    // reads the values straight from the node (node -> values instead of node -> bucket ->
    // values: one dependent cache miss fewer per leaf). no_slot otherwise. Every change to a
    // leaf's items keeps it true or clears it (check_invariants verifies it).
    struct leaf_slots {
        std::uint32_t count = 0;  // number of points in the bucket
        slot_index run = no_slot;
    };
    // What every search reads: 32 B for double (the cold links are in links_).
    struct node {
        T split = 0;  // inner: left points have c[dim] <= split, right points >= split
        union {
            leaf_slots leaf{};     // leaf
            child_ranges ranges;   // inner
        };
        node_index first = 0;  // inner: first child (second is first + 1); leaf: bucket
        std::uint16_t depth = 0;
        std::uint8_t dim = 0;
        std::uint8_t is_leaf = 1;
    };
    static_assert(sizeof(T) != 8 || sizeof(node) == 32, "kd_tree: a node of a double tree must stay 32 B");
    // What only insertion's climb and rebuilds read, per node, apart so searches do not load it.
    struct node_link {
        T restore = 0;  // parent's cell bound on the parent's split dim, on this side
        node_index parent = no_node;
    };
    // Aligned to a cache line with the slot list first: a query scanning a leaf touches the
    // list's lines (two at the default capacity of 32), the cell is only read by insertion.
    struct alignas(64) bucket {
        std::array<slot_index, leaf_capacity> items;
        node_index owner = no_node;
        coords cell_lo, cell_hi;  // the leaf's cell (may be infinite)
    };
    // A point copied out for (re)building: partitioning moves these, not the slots.
    struct entry {
        coords c;             // the point, or the object's bounding-box centre (the key)
        slot_index slot;      // the point's slot (in a fresh build: its index in the batch)
        node_index bucket = 0;  // fresh build only: the leaf bucket it landed in
        // Objects only: the bounding box, so builds compute node extents without the slots
        // (a fresh build has not stored them yet). Takes no space for points.
        [[no_unique_address]] std::conditional_t<has_extent, extent, no_extent> bounds{};
    };
    struct entry_without_bounds {
        coords c;
        slot_index slot;
        node_index bucket;
    };
    static_assert(has_extent || sizeof(entry) == sizeof(entry_without_bounds),
                  "kd_tree: point build entries must not grow");

public:
    // The empty tree has no nodes yet (the "unallocated" state: nodes_, buckets_ and extents_
    // are empty vectors); the first insertion allocates the root leaf (ensure_root). So
    // constructing an empty tree allocates nothing and cannot throw, like std::vector's.
    kd_tree() noexcept { drop_tree(); }
    template <class InputIt>
    kd_tree(InputIt first, InputIt last) : kd_tree() { insert(first, last); }
    // The same tree built on every core (insert(first, last, par)).
    template <class InputIt>
    kd_tree(InputIt first, InputIt last, parallel_policy) : kd_tree() { insert(first, last, par); }
    // Copies are independent trees (iterators into one never refer to the other).
    kd_tree(const kd_tree&) = default;
    kd_tree& operator=(const kd_tree&) = default;
    // A moved-from tree is empty and usable. Iterators into the source are invalidated:
    // they refer to the source's storage (see docs/contract.md, iterators and invalidation).
    // noexcept: the source takes the unallocated empty tree in exchange (member-wise swaps of
    // vectors and scalars), so a std::vector of trees moves them when it grows instead of
    // copying (std::move_if_noexcept).
    kd_tree(kd_tree&& other) noexcept : kd_tree() { swap_contents(other); }
    kd_tree& operator=(kd_tree&& other) noexcept { return this->move_assign_from(other); }

    // ---- insertion -------------------------------------------------------------------
    // O(log n) expected, O(log^2 n) amortised worst case (scapegoat subtree rebuilds).
    iterator insert(const O& x) {
        begin_query();
        detail::require_finite_object(x, site("insert"));
        ensure_root();
        const coords c = key_of(x);
        return make(insert_at(descend(root, c), x, c));
    }

    // Hinted insertion: starts at the hint's leaf and climbs only as far as needed (each
    // step O(1) via the stored restore bounds), then descends. O(1) expected when x lies in
    // the hint's leaf cell or a nearby one; a far-away hint costs a climb to the root plus
    // the plain descent (about twice a plain insert).
    iterator insert(const_iterator hint, const O& x) {
        begin_query();
        detail::require_finite_object(x, site("insert(hint, x)"));
        ensure_root();
        const coords c = key_of(x);
        if (hint == end() || !slots_.occupied(hint.slot())) return make(insert_at(descend(root, c), x, c));
        const bucket& b = buckets_[slots_.meta(hint.slot())];
        node_index n = b.owner;
        coords lo = b.cell_lo, hi = b.cell_hi;
        while (n != root && !in_cell(c, lo, hi)) {
            if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
            const node_index p = links_[n].parent;
            const unsigned d = nodes_[p].dim;
            if (n == nodes_[p].first) hi[d] = links_[n].restore;
            else lo[d] = links_[n].restore;
            n = p;
        }
        return make(insert_at(descend(n, c), x, c));
    }

    // Bulk insertion, better than a loop: into an empty tree a median build that also lays
    // the points out in leaf order (O(m log m)); for a batch at least half the current size
    // a full rebuild (O((n+m) log(n+m))); otherwise the batch is partitioned down the tree
    // once and each touched leaf is rebuilt with its new points (O(m log n), one pass over
    // the touched nodes instead of m root-to-leaf descents). Validates everything first and
    // reserves storage before storing anything (strong guarantee for bad input and for
    // capacity errors; a std::bad_alloc during rebuilding leaves the tree unusable).
    template <class InputIt>
    void insert(InputIt first, InputIt last);
    // The bulk insertion on every core (core/parallel.hpp). Into an empty tree: the same tree
    // as insert(first, last), node for node and slot for slot — the splits of disjoint entry
    // ranges are made concurrently (each split only reorders its own range, so its outcome
    // does not depend on the schedule), then the nodes are laid out in the order the
    // sequential build allocates them. Work O(m log m), span O(m) (the root's split and the
    // layout pass); below 2 x 8192 points, and into a non-empty tree, insert(first, last)
    // itself. Same validation and guarantees as insert(first, last).
    template <class InputIt>
    void insert(InputIt first, InputIt last, parallel_policy);

    // ---- erasure ---------------------------------------------------------------------
    // O(leaf_capacity) plus amortised rebuilds. Returns the next element in iteration order.
    // Cannot fail under allocation failure (the free-list room is reserved first; merges and
    // the rebuild after erasure are best-effort).
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        slots_.reserve_releases(1);
        remove_slot(s, true);
        after_erase();
        return make(slots_.next_occupied(s + 1));
    }

    // Erases ALL elements equal to x; returns how many. O(log n + matches).
    size_type erase(const O& x) {
        detail::require_finite_object(x, site("erase"));
        if (!has_root()) return 0;
        std::vector<slot_index> hits;
        collect_equal(root, key_of(x), x, hits, false);
        slots_.reserve_releases(hits.size());
        for (slot_index s : hits) remove_slot(s, true);
        if (!hits.empty()) after_erase();
        return hits.size();
    }

    // Back to the unallocated empty tree (as the default constructor makes it); the vectors
    // keep their capacity, like std::vector::clear, so refilling does not reallocate. Cannot
    // throw (the move assignment clears the target first).
    void clear() noexcept {
        slots_.clear();
        drop_tree();
    }

private:
    void begin_query() const {
        if constexpr (Config::collect_stats) query_stats_ = {};
    }
    // The range-erase hooks of container_base. Past a quarter of the tree the survivors are
    // rebuilt once (O(n log n)); a smaller range releases the slots, then compacts each
    // touched bucket once and merges the leaves it emptied (O(m + touched buckets *
    // leaf_capacity) plus O(buckets) to clear a byte mark array), with one balance check.
    void rebuild_survivors() { rebuild_all(); }
    void erase_slots(std::span<const slot_index> doomed);

public:
    // ---- lookup ----------------------------------------------------------------------
    // O(log n) expected (both sides are searched where x lies on a split plane).
    iterator find(const O& x) {
        begin_query();
        detail::require_finite_object(x, site("find"));
        if (!has_root()) return end();
        std::vector<slot_index> hits;
        collect_equal(root, key_of(x), x, hits, true);
        return hits.empty() ? end() : make(hits.front());
    }
    size_type count(const O& x) const {
        begin_query();
        detail::require_finite_object(x, site("count"));
        if (!has_root()) return 0;
        std::vector<slot_index> hits;
        collect_equal(root, key_of(x), x, hits, false);
        return hits.size();
    }

    // ---- ray cast --------------------------------------------------------------------
    // Nearest point hit before info.hit_time by the ray thickened to `thickness` (see
    // point::intersect), or end(). Front-to-back traversal: a node is entered only for the
    // ray-parameter interval in which the thick ray can reach its half-space, and skipped once
    // a hit closer than that interval is known. Cost: the cells the ray crosses before its
    // first hit, typically about (n/leaf_capacity)^(1/D) in 3D-uniform data; O(n) worst case
    // with widest-spread splits (a ray along a very flat set).
    iterator intersect_object(const P& origin, const P& direction, scalar_type thickness,
                              info_type& info) const;

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // The k nearest (all if k >= size), sorted by increasing distance; k = 0 gives {}.
    // Expected O(log n + k log k) on well-distributed data (Friedman, Bentley & Finkel 1977).
    // (1+eps)-approximate: the i-th reported distance is at most (1+eps) times the true i-th.
    std::vector<iterator> find_nearest(const P& x, size_type k, scalar_type eps) const {
        begin_query();
        detail::require_finite(x, site("find_nearest"), "query point");
        detail::require_nonnegative(eps, site("find_nearest"), "eps");
        std::vector<iterator> out;
        if (k == 0 || slots_.size() == 0) return out;
        knn_result_set<T> best(std::min<std::size_t>(k, slots_.size()));
        run_knn(x, eps, best);
        for (const auto& c : best.finish()) out.push_back(make(c.slot));
        return out;
    }
    // Visitor form used by benchmarks: fills `result` with (squared distance, slot) sorted,
    // without building iterators. Same semantics as find_nearest.
    void find_nearest_candidates(const P& x, size_type k, scalar_type eps,
                                 std::vector<neighbor_candidate<T>>& result) const {
        begin_query();
        detail::require_finite(x, site("find_nearest"), "query point");
        detail::require_nonnegative(eps, site("find_nearest"), "eps");
        result.clear();
        if (k == 0 || slots_.size() == 0) return;
        knn_result_set<T> best(std::min<std::size_t>(k, slots_.size()));
        run_knn(x, eps, best);
        const auto found = best.finish();
        result.assign(found.begin(), found.end());
    }

    // Many queries at once (core/knn_batch.hpp): query i's answer is find_nearest(queries[i],
    // k, eps)'s, stored at i. query_order::morton searches them in Morton order (cheaper when
    // the queries are dense enough to share leaves; the O(Q) sort is included); spatial::par
    // answers chunks of them concurrently (sequentially with CollectStats, whose counters
    // would race; last_query_stats() is then the last searched query's). Every query point
    // is validated before any search. O(Q (log n + k log k)) expected, like Q single queries.
    template <class Policy = sequential_policy>
    knn_batch<iterator, scalar_type> find_nearest_batch(std::span<const P> queries, size_type k, scalar_type eps = 0,
                                                        query_order order = query_order::as_given,
                                                        Policy = {}) const {
        detail::require_finite_queries(queries, site("find_nearest_batch"));
        detail::require_nonnegative(eps, site("find_nearest_batch"), "eps");
        const std::size_t per_query = std::min<std::size_t>(k, slots_.size());
        constexpr bool concurrent = std::is_same_v<Policy, parallel_policy> && !Config::collect_stats;
        return detail::answer_knn_batch<concurrent, iterator>(
            queries, per_query, order,
            [this, eps](const P& x, knn_result_set<T>& best) {
                begin_query();
                run_knn(x, eps, best);
            },
            [this](slot_index s) { return make(s); });
    }

    // All points p with |p - center| <= radius (closed ball), in no particular order.
    std::vector<iterator> find_in_ball(const P& center, scalar_type radius) const {
        std::vector<iterator> out;
        find_in_ball(center, radius, out);
        return out;
    }
    // The same into `out`, which is cleared (after the arguments are checked) and keeps its
    // capacity: a caller asking many large balls reuses one buffer, where a fresh vector per
    // query grows by copying and faults its pages in again every time (on 1e7 clustered points
    // seen from far away, most of a radius query's time: docs/known-gaps.md).
    void find_in_ball(const P& center, scalar_type radius, std::vector<iterator>& out) const {
        require_ball_arguments(center, radius);
        out.clear();
        run_ball(center, radius, [&](slot_index s, T) { out.push_back(make(s)); });
    }
    // Visitor form used by benchmarks, as find_nearest_candidates is for kNN: the same ball as
    // (squared distance, slot) pairs in no particular order, the distances the search computed
    // (a caller wanting them need not look each point up again), into `out` (cleared after the
    // arguments are checked, its capacity kept).
    void find_in_ball_candidates(const P& center, scalar_type radius, std::vector<neighbor_candidate<T>>& out) const {
        require_ball_arguments(center, radius);
        out.clear();
        run_ball(center, radius, [&](slot_index s, T d2) { out.push_back({d2, s}); });
    }
    // All points p with lo <= p <= hi componentwise (closed box). O(n^(1-1/D) + hits) for
    // trees whose splits cycle through the dimensions (Lee & Wong 1977); with widest-spread
    // splits a thin box over a very elongated set can visit O(n) nodes.
    std::vector<iterator> find_in_box(const P& lo, const P& hi) const {
        begin_query();
        detail::require_finite(lo, site("find_in_box"), "box corner lo");
        detail::require_finite(hi, site("find_in_box"), "box corner hi");
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        box(root, lo, hi, out);
        return out;
    }

    // ---- collision pairs (collide/pairs.hpp; the descent: kd_tree_pairs.hpp) -------------
    // Self pairs (lower slot, higher slot) and pairs with another container (object of *this,
    // object of other), sorted; candidates are the pairs whose closed bounding boxes overlap,
    // exact adds the narrow phase. Objects with extent: the tree descended against itself or
    // another kd_tree as a BVH; points: through box queries.
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const;
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const;

    // ---- introspection -------------------------------------------------------------------
    std::size_t memory_bytes() const {
        return sizeof(*this) + slots_.memory_bytes() + nodes_.capacity() * sizeof(node) +
               links_.capacity() * sizeof(node_link) +
               extents_.capacity() * sizeof(extent) +
               entry_buffer_.capacity() * sizeof(entry) +
               buckets_.capacity() * sizeof(bucket) +
               (free_pairs_.capacity() + free_buckets_.capacity()) * sizeof(node_index);
    }
    // Tree height in nodes below the root (0 for a single leaf and for the unallocated tree).
    std::size_t height() const { return has_root() ? height_of(root) : 0; }
    // Leaves (0 for the unallocated empty tree, 1 for an empty tree that had elements).
    std::size_t leaf_count() const { return leaves_; }
    // The last query's counts (core/query_stats.hpp): a kNN, ball, box or ray query, a
    // find/count, or an insertion (nodes climbed from the hint plus nodes descended). Only
    // with Config::collect_stats, since counting costs time on every node.
    const query_stats& last_query_stats() const
        requires(Config::collect_stats)
    {
        return query_stats_;
    }
    const kd_tree_maintenance_stats& maintenance_stats() const { return maintenance_; }

    // Diagnostics: how many (point, ancestor split plane) pairs have the point exactly ON the
    // plane. Bulk builds place planes in gaps between coordinates (see splitters.hpp), so
    // this is 0 unless a coordinate run is too large to move the cut. O(n * height).
    std::size_t points_on_split_planes() const { return has_root() ? on_planes(root) : 0; }

    // Checks every structural invariant (split bounds, cells, bucket back-links, counts,
    // depths); returns an empty string when sound, else what is wrong. For tests: O(n).
    std::string check_invariants() const;

private:
    // ---- storage: keys, extents, buckets, node pairs (kd_tree_storage.hpp) ----
    static coords key_of(const O& x);
    static extent extent_of(const O& x);
    static entry make_entry(const O& x, slot_index s);
    void grow_extents_upward(node_index n, const extent& box);
    void refit_leaf(node_index leaf);
    static bool in_cell(const coords& c, const coords& lo, const coords& hi);
    void grow_bounds(const coords& c);
    // The unallocated empty tree: no nodes, no buckets (the state of a default-constructed or
    // moved-from tree, and after clear()). Every query answers it as empty; the modifiers that
    // need a root call ensure_root first. has_root() is false exactly in this state.
    bool has_root() const noexcept { return !nodes_.empty(); }
    void drop_tree() noexcept;
    void ensure_root();
    void reset_to_empty();
    void swap_contents(kd_tree& o) noexcept;
    node_index new_bucket(node_index owner, const coords& lo, const coords& hi);
    node_index new_pair();

    // ---- insertion and erasure in place (kd_tree_update.hpp) ----
    struct subtree_backup;  // kd_tree_backup.hpp
    node_index descend(node_index n, const coords& c) const;
    slot_index insert_at(node_index leaf, const O& x, const coords& c);
    void widen_child_ranges(node_index n, const coords& c) noexcept;
    // Widens a child range [lo, hi] to hold key v, rounding outward to float.
    static void widen_range(float& lo, float& hi, T v) noexcept {
        if (v < lo) lo = detail_rounding::round_down<float>(static_cast<double>(v));
        if (v > hi) hi = detail_rounding::round_up<float>(static_cast<double>(v));
    }
    // `leaf_backup`: reused for every leaf the batch splits (kd_tree_backup.hpp).
    void distribute(node_index n, entry* e, std::size_t count, std::uint16_t& max_depth, subtree_backup& leaf_backup);
    void remove_slot(slot_index s, bool allow_merge);
    void take_out_of_leaf(slot_index s) noexcept;
    void try_merge_empty_leaf(node_index leaf) noexcept;
    void merge_empty_leaf(node_index leaf);
    void after_erase();
    bool needs_full_rebuild() const;

    // ---- (re)building (kd_tree_build.hpp) ----
    std::uint16_t depth_limit() const;
    void gather(node_index n, std::vector<entry>& es);
    std::uint16_t rebuild_subtree(node_index n, std::vector<entry>& es);
    void cell_from_ancestors(node_index n, coords& lo, coords& hi) const;
    // What a (sub)tree build reports to its parent: its deepest leaf and its keys' box.
    struct built_subtree {
        std::uint16_t deepest;
        extent keys;
    };
    // Where a build takes each inner node's split from: Config::splitter on the spot, or a
    // plan made beforehand on several threads (planned_splits, kd_tree_build.hpp).
    struct split_by_config {
        split_choice<T> operator()(entry* e, std::size_t n) const { return typename Config::splitter{}(e, n, leaf_capacity); }
    };
    struct split_record;
    struct planned_splits;
    template <class SplitSource>
    built_subtree build_node(node_index at, entry* e, std::size_t n, const coords& lo, const coords& hi,
                             std::uint16_t depth, bool fresh, std::size_t base, SplitSource& split);
    built_subtree build_node(node_index at, entry* e, std::size_t n, const coords& lo, const coords& hi,
                             std::uint16_t depth, bool fresh, std::size_t base) {
        split_by_config split;
        return build_node(at, e, n, lo, hi, depth, fresh, base, split);
    }
    // Subtrees of fewer entries are planned on one thread (as bvh's parallel_grain).
    static constexpr std::size_t parallel_grain = 8192;
    using split_plan = detail::preorder_plan<split_record>;  // core/preorder_plan.hpp
    static void plan_splits(entry* es, std::size_t begin, std::size_t count, split_plan& plan);
    template <class RandomIt>
    void build_fresh(RandomIt batch, std::size_t count, bool parallel = false);
    template <class RandomIt>
    void build_fresh_in_place(RandomIt batch, std::size_t count, bool parallel);
    void rebuild_all();
    void rebuild_all_in_place();
    void rebalance_from(node_index n);

    // ---- undoing a change that ran out of memory (kd_tree_backup.hpp) ----
    subtree_backup backup_subtree(node_index n, std::size_t entries) const;
    void backup_subtree(node_index n, std::size_t entries, subtree_backup& into) const;
    void restore(subtree_backup& b) noexcept;
    struct tree_backup;
    tree_backup backup_all();
    void restore(tree_backup& b) noexcept;
    // The bucket word of a slot allocated but not yet in a leaf (a failed bulk insert takes
    // out exactly the placed ones); no bucket has this index.
    static constexpr node_index unplaced = no_node - 1;
    std::size_t subtree_size(node_index n) const;

    // ---- queries (kd_tree_queries.hpp) ----
    struct knn_query {
        coords x;
        T eps_factor;  // (1 + eps)^2: prune when cell distance^2 * factor >= worst^2
        knn_result_set<T>& best;
    };
    struct knn_object_query {
        const P& x;
        T eps_factor;  // (1 + eps)^2
        T slack;
        knn_result_set<T>& best;
    };
    void run_knn(const P& x, scalar_type eps, knn_result_set<T>& best) const;
    void knn(node_index n, coords& offset, knn_query& q) const;
    // A point leaf's offer to the result set; distances first when the leaf is a run.
    void knn_leaf(const node& nd, knn_query& q) const;
    static T far_cell_distance(const coords& offset, unsigned d, T diff);
    coords root_offsets(const coords& x) const;
    struct side_offsets {
        node_index near, far;
        T near_offset, far_offset;
    };
    static side_offsets child_offsets(const node& nd, T x, T old);
    // A child's key range along nd's cut, in T. The split plane bounds the inner sides too:
    // the float ranges, rounded outward, can reach past it at a cut through a run of equal keys.
    static std::pair<T, T> left_range(const node& nd) {
        return {T(nd.ranges.left_lo), std::min(T(nd.ranges.left_hi), nd.split)};
    }
    static std::pair<T, T> right_range(const node& nd) {
        return {std::max(T(nd.ranges.right_lo), nd.split), T(nd.ranges.right_hi)};
    }
    void require_ball_arguments(const P& center, scalar_type radius) const {
        begin_query();
        detail::require_finite(center, site("find_in_ball"), "center");
        detail::require_nonnegative(radius, site("find_in_ball"), "radius");
    }
    // The closed ball's search: emit(slot, squared distance) for every element in it.
    template <class Emit>
    void run_ball(const P& center, scalar_type radius, Emit&& emit) const {
        if (slots_.size() == 0) return;
        if constexpr (has_extent) {
            // Distance to a node's extent, less the rounding slack (see knn_slack), must not
            // exceed the radius; the slack also covers the rounding of radius * radius.
            const T sl = knn_slack(center) + radius * gamma;
            ball_objects(root, center, radius + sl, radius * radius, emit);
        } else {
            coords offset = root_offsets(point_coords(center));
            ball(root, offset, point_coords(center), radius * radius, emit);
        }
    }
    template <class Emit>
    void ball(node_index n, coords& offset, const coords& x, T r2, Emit& emit) const;
    void box(node_index n, const P& lo, const P& hi, std::vector<iterator>& out) const;
    void collect_equal(node_index n, const coords& c, const O& x, std::vector<slot_index>& out,
                       bool first_only) const;
    static bool extent_overlaps(const extent& ex, const P& lo, const P& hi);
    static T extent_squared_distance(const extent& ex, const P& x);
    T knn_slack(const P& x) const;
    T extent_lower_bound(node_index n, const P& x, T slack) const;
    void knn_objects(node_index n, knn_object_query& q) const;
    template <class Emit>
    void ball_objects(node_index n, const P& center, T reach, T r2, Emit& emit) const;

    // ---- ray casting (kd_tree_rays.hpp) ----
    struct ray_query {
        coords o, v;
        T r;
        const P& origin;
        const P& direction;
        info_type& info;
        slot_index hit = no_slot;
    };
    // Rounding slack: a point the exact test would accept must never be pruned. The slab
    // bound is widened by a few ulps of the magnitudes involved, the parameters by a
    // relative gamma (Pharr, Jakob & Humphreys, PBRT 3e, sec. 3.9).
    static constexpr T gamma = 16 * std::numeric_limits<T>::epsilon();
    static T pad(const ray_query& q, unsigned d, T bound);
    static void clip_below(const ray_query& q, unsigned d, T b, T& t0, T& t1);
    static void clip_above(const ray_query& q, unsigned d, T a, T& t0, T& t1);
    void cast(node_index n, T t0, T t1, ray_query& q) const;
    static bool clip_to_extent(const ray_query& q, const extent& ex, T& t0, T& t1);
    void cast_objects(node_index n, T t0, T t1, ray_query& q) const;

    // ---- collision pairs of objects (kd_tree_pairs.hpp) ----
    struct node_pair {
        node_index a, b;  // a in this tree, b in the other (the same tree for self pairs)
    };
    // A query's snapshot (collide/tree_pair_snapshot.hpp): the objects' boxes leaf by leaf and
    // each node's exact subtree box, by which the descent prunes instead of extents_.
    using pair_layout = collide::tree_pair_snapshot<T, D>;
    pair_layout pair_layout_of() const;
    static T half_perimeter(const extent& e);
    template <class Emit>
    void cross_step(const kd_tree& other, const pair_layout& mine, const pair_layout& theirs, node_pair p,
                    std::vector<node_pair>& todo, Emit& emit) const;

    // ---- diagnostics (kd_tree_checks.hpp) ----
    void check_node(node_index n, const coords& lo, const coords& hi, std::uint16_t depth, std::size_t& seen,
                    extent& keys, std::string& err) const;
    std::size_t on_planes(node_index n) const;
    template <class F>
    void for_each_slot(node_index n, F&& f) const;
    // f(slot) for each slot of leaf nd, in bucket order, through `run` when the leaf has one.
    template <class F>
    void scan_leaf(const node& nd, F&& f) const;
    // Prefetches the `count` values of the run starting at slot `run`; returns the first.
    const O* prefetch_run(slot_index run, std::uint32_t count) const;
    // The run of a leaf whose bucket holds items[0, count): its first slot when they are
    // consecutive, else no_slot. O(count).
    static slot_index run_of(const slot_index* items, std::uint32_t count) noexcept;
    // Appends slot s to leaf L's bucket b, keeping L's run when s extends it. O(1).
    static void append_to_leaf(node& L, bucket& b, slot_index s) noexcept;
    // Removes slot s from leaf L's bucket b (the last item takes its place) and recomputes
    // L's run. O(count).
    static void remove_from_leaf(node& L, bucket& b, slot_index s) noexcept;
    std::size_t height_of(node_index n) const;

    // ================= data ================================================================
    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;
    using contract_base::ray_thickness_;
    std::vector<node> nodes_;
    std::vector<node_link> links_;  // parallel to nodes_
    std::vector<bucket> buckets_;
    std::vector<node_index> free_pairs_;
    std::vector<node_index> free_buckets_;
    std::size_t leaves_ = 0;
    // Box of all keys inserted since the last rebuild. Points: the root clip of ray casts and
    // the starting offsets of kNN and ball searches (objects use extents_ for both).
    coords bounds_lo_{}, bounds_hi_{};
    std::size_t size_at_rebuild_ = 0;
    std::vector<entry> entry_buffer_;  // reused by leaf splits (no allocation per split)
    mutable query_stats query_stats_;  // written only with Config::collect_stats
    kd_tree_maintenance_stats maintenance_;
    // Objects only (empty for points; last, so the point layout above is unchanged): per
    // node, indexed like nodes_, the bounding box of its subtree's objects.
    std::vector<extent> extents_;
};

}  // namespace spatial

#include "spatial/kdtree/kd_tree_storage.hpp"
#include "spatial/kdtree/kd_tree_backup.hpp"
#include "spatial/kdtree/kd_tree_update.hpp"
#include "spatial/kdtree/kd_tree_build.hpp"
#include "spatial/kdtree/kd_tree_queries.hpp"
#include "spatial/kdtree/kd_tree_rays.hpp"
#include "spatial/kdtree/kd_tree_pairs.hpp"
#include "spatial/kdtree/kd_tree_checks.hpp"

#include "spatial/core/point.hpp"
static_assert(spatial::spatial_container<spatial::kd_tree<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::kd_tree<spatial::point<float, 2>>>);
