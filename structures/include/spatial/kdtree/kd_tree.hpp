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

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "spatial/collide/box_bounds.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/collide/tree_pair_snapshot.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/query_stats.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/kdtree/splitters.hpp"

namespace spatial {

// Compile-time configuration with commented defaults.
template <std::size_t LeafCapacity = 16, class Splitter = median_of_widest_spread,
          bool CollectStats = false>
struct kd_tree_config {
    // Points per leaf bucket. 16 keeps a leaf's slot list in one cache line and makes a
    // leaf scan cheaper than descending further.
    static constexpr std::size_t leaf_capacity = LeafCapacity;
    // How a node's points are divided (see splitters.hpp).
    using splitter = Splitter;
    // When true, queries count visited nodes and tested objects (kd_tree::last_query_stats()).
    static constexpr bool collect_stats = CollectStats;
    // Weight-balance parameter alpha of the scapegoat rule, in (0.5, 1).
    static constexpr double balance_alpha = 0.75;
};

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

    struct node {
        T split = 0;       // inner: left points have c[dim] <= split, right points >= split
        T restore = 0;     // parent's cell bound on the parent's split dim, on this side
        node_index first = 0;  // inner: first child (second is first + 1); leaf: bucket
        node_index parent = no_node;
        std::uint32_t count = 0;  // leaf: number of points in the bucket
        std::uint16_t depth = 0;
        std::uint8_t dim = 0;
        std::uint8_t is_leaf = 1;
    };
    // Aligned to a cache line with the slot list first: a query scanning a leaf touches one
    // line for the list (for capacity <= 16), the cell is only read by hinted insertion.
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
    kd_tree() { reset_to_empty(); }
    template <class InputIt>
    kd_tree(InputIt first, InputIt last) : kd_tree() { insert(first, last); }
    // Copies are independent trees (iterators into one never refer to the other).
    kd_tree(const kd_tree&) = default;
    kd_tree& operator=(const kd_tree&) = default;
    // A moved-from tree is empty and usable. Iterators into the source are invalidated:
    // they refer to the source's storage (see docs/contract.md, iterators and invalidation).
    kd_tree(kd_tree&& other) noexcept(false) : kd_tree() { swap_contents(other); }
    kd_tree& operator=(kd_tree&& other) noexcept(false) {
        if (this != &other) {
            clear();
            swap_contents(other);
        }
        return *this;
    }

    // ---- insertion -------------------------------------------------------------------
    // O(log n) expected, O(log^2 n) amortised worst case (scapegoat subtree rebuilds).
    iterator insert(const O& x) {
        begin_query();
        detail::require_finite_object(x, site("insert"));
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
        const coords c = key_of(x);
        if (hint == end() || !slots_.occupied(hint.slot())) return make(insert_at(descend(root, c), x, c));
        const bucket& b = buckets_[slots_.meta(hint.slot())];
        node_index n = b.owner;
        coords lo = b.cell_lo, hi = b.cell_hi;
        while (n != root && !in_cell(c, lo, hi)) {
            if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
            const node_index p = nodes_[n].parent;
            const unsigned d = nodes_[p].dim;
            if (n == nodes_[p].first) hi[d] = nodes_[n].restore;
            else lo[d] = nodes_[n].restore;
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
    void insert(InputIt first, InputIt last) {
        if constexpr (!std::random_access_iterator<InputIt>) {
            // Single-pass or list-like input: copy once so it can be validated first.
            const std::vector<O> batch(first, last);
            insert(batch.begin(), batch.end());
        } else {
            for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last)"));
            const auto m = static_cast<std::size_t>(last - first);
            if (m == 0) return;
            slots_.require_room_for(m, site("insert(first, last)"));
            if (slots_.size() == 0) {
                build_fresh(first, m);
                return;
            }
            const std::size_t old_size = slots_.size();
            slots_.reserve(slots_.capacity() + m);  // no reallocation failure half-way
            std::vector<entry> fresh;
            fresh.reserve(m);
            for (auto it = first; it != last; ++it) {
                fresh.push_back(make_entry(*it, slots_.allocate(*it, 0)));
                grow_bounds(fresh.back().c);
            }
            if (m * 2 >= old_size) {
                rebuild_all();
                return;
            }
            std::uint16_t max_depth = 0;
            distribute(root, fresh.data(), fresh.size(), max_depth);
            if (max_depth > depth_limit() || needs_full_rebuild()) rebuild_all();
        }
    }

    // ---- erasure ---------------------------------------------------------------------
    // O(leaf_capacity) plus amortised rebuilds. Returns the next element in iteration order.
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        remove_slot(s, true);
        after_erase();
        return make(slots_.next_occupied(s + 1));
    }

    // Erases ALL elements equal to x; returns how many. O(log n + matches).
    size_type erase(const O& x) {
        detail::require_finite_object(x, site("erase"));
        std::vector<slot_index> hits;
        collect_equal(root, key_of(x), x, hits, false);
        for (slot_index s : hits) remove_slot(s, true);
        if (!hits.empty()) after_erase();
        return hits.size();
    }

    void clear() {
        slots_.clear();
        reset_to_empty();
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
    void erase_slots(std::span<const slot_index> doomed) {
        std::vector<node_index> touched;
        std::vector<char> marked(buckets_.size(), 0);  // O(buckets) bytes, cheaper than sorting
        for (slot_index s : doomed) {
            const node_index b = slots_.meta(s);
            if (!marked[b]) {
                marked[b] = 1;
                touched.push_back(b);
            }
            slots_.release(s);
        }
        for (node_index b : touched) {
            node& L = nodes_[buckets_[b].owner];
            auto& items = buckets_[b].items;
            std::uint32_t kept = 0;
            for (std::uint32_t i = 0; i < L.count; ++i)
                if (slots_.occupied(items[i])) items[kept++] = items[i];
            L.count = kept;
            if constexpr (has_extent) refit_leaf(buckets_[b].owner);
        }
        for (node_index b : touched) {  // merging may free buckets later in the list
            const node_index leaf = buckets_[b].owner;
            if (leaf == no_node || !nodes_[leaf].is_leaf || nodes_[leaf].first != b) continue;
            if (nodes_[leaf].count == 0 && leaf != root) merge_empty_leaf(leaf);
        }
        after_erase();
    }


    void swap_contents(kd_tree& o) {
        this->swap_base(o);
        std::swap(nodes_, o.nodes_);
        std::swap(extents_, o.extents_);
        std::swap(buckets_, o.buckets_);
        std::swap(free_pairs_, o.free_pairs_);
        std::swap(free_buckets_, o.free_buckets_);
        std::swap(leaves_, o.leaves_);
        std::swap(bounds_lo_, o.bounds_lo_);
        std::swap(bounds_hi_, o.bounds_hi_);
        std::swap(size_at_rebuild_, o.size_at_rebuild_);
    }

public:

    // ---- lookup ----------------------------------------------------------------------
    // O(log n) expected (both sides are searched where x lies on a split plane).
    iterator find(const O& x) {
        begin_query();
        detail::require_finite_object(x, site("find"));
        std::vector<slot_index> hits;
        collect_equal(root, key_of(x), x, hits, true);
        return hits.empty() ? end() : make(hits.front());
    }
    size_type count(const O& x) const {
        begin_query();
        detail::require_finite_object(x, site("count"));
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
                              info_type& info) const {
        begin_query();
        detail::require_finite(origin, site("intersect"), "ray origin");
        detail::require_nonzero_direction(direction, site("intersect"));
        detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
        if (slots_.size() == 0) return end();
        ray_query q{coords_of(origin), coords_of(direction), thickness, origin, direction, info};
        T t0 = 0, t1 = info.hit_time;
        if constexpr (has_extent) {
            // Objects: every node is clipped against its subtree's padded extent.
            if (clip_to_extent(q, extents_[root], t0, t1)) cast_objects(root, t0, t1, q);
        } else {
            for (unsigned d = 0; d < D && t0 <= t1; ++d) {
                clip_below(q, d, bounds_hi_[d] + pad(q, d, bounds_hi_[d]), t0, t1);
                clip_above(q, d, bounds_lo_[d] - pad(q, d, bounds_lo_[d]), t0, t1);
            }
            if (t0 <= t1) cast(root, t0, t1, q);
        }
        return q.hit == no_slot ? end() : make(q.hit);
    }

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
        result = std::move(best.finish());
    }

    // All points p with |p - center| <= radius (closed ball), in no particular order.
    std::vector<iterator> find_in_ball(const P& center, scalar_type radius) const {
        begin_query();
        detail::require_finite(center, site("find_in_ball"), "center");
        detail::require_nonnegative(radius, site("find_in_ball"), "radius");
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        if constexpr (has_extent) {
            // Distance to a node's extent, less the rounding slack (see knn_slack), must not
            // exceed the radius; the slack also covers the rounding of radius * radius.
            const T sl = knn_slack(center) + radius * gamma;
            ball_objects(root, center, radius + sl, radius * radius, out);
        } else {
            coords offset{};
            ball(root, T(0), offset, coords_of(center), radius * radius, out);
        }
        return out;
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

    // ---- STL basics and introspection ----------------------------------------------------
    // ---- collision pairs (collide/pairs.hpp) ---------------------------------------------
    // Objects with extent: self pairs by descending the tree against itself, as a BVH does
    // (simultaneous traversal of node pairs, Gottschalk, Lin & Manocha 1996). Each object is
    // stored once, in one leaf, and each node's subtree box bounds the objects below it, so
    // the skd-tree is a binary BVH whose boxes may overlap:
    //   self(N)     = self(left), self(right), cross(left, right) if their boxes overlap;
    //                 a leaf: its objects pairwise;
    //   cross(A, B) = the larger node (by box half-perimeter) opened, each child crossed with
    //                 the other node when their boxes overlap; two leaves: objects pairwise.
    // Every pair of objects has one place in this decomposition (the node where their leaves
    // part), so each is considered once: no seen-set. The boxes are the exact subtree boxes
    // of a per-query snapshot (see pair_layout), not extents_, which erasure leaves loose.
    // Candidates: the pairs whose closed bounding boxes overlap; exact adds the narrow phase
    // (the set brute force reports). Sorted by slots, (lower, higher).
    // Cost: O(n + nodes) for the snapshot plus O(node pairs whose boxes overlap + candidates),
    // about O(n + k) on well-spread objects with k pairs, against n box queries
    // (O(n log n) at best) through self_pairs_by_queries; O(n^2) when everything overlaps,
    // as any method that lists the pairs.
    // Points: two points collide only when equal; through the box queries (O(n log n)).
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
        if constexpr (!has_extent) {
            return self_pairs_by_queries(*this, filter);
        } else {
            std::vector<std::pair<iterator, iterator>> out;
            if (slots_.size() < 2) return out;
            const pair_layout lay = pair_layout_of();
            auto emit = [&](std::uint32_t i, std::uint32_t j) {
                if (!collide::closed_boxes_overlap(lay.box[i], lay.box[j])) return;
                slot_index s = lay.slot[i], t = lay.slot[j];
                if (filter == pair_filter::exact && !collide::narrow_phase(slots_.value(s), slots_.value(t))) return;
                if (s > t) std::swap(s, t);
                out.emplace_back(make(s), make(t));
            };
            std::vector<node_pair> todo{{root, root}};
            while (!todo.empty()) {
                const node_pair p = todo.back();
                todo.pop_back();
                if (p.a != p.b) {
                    cross_step(*this, lay, lay, p, todo, emit);
                    continue;
                }
                const node& nd = nodes_[p.a];
                if (nd.is_leaf) {
                    const std::uint32_t first = lay.first[p.a], last = first + nd.count;
                    for (std::uint32_t i = first; i < last; ++i)
                        for (std::uint32_t j = i + 1; j < last; ++j) emit(i, j);
                    continue;
                }
                if (collide::closed_boxes_overlap(lay.subtree[nd.first], lay.subtree[nd.first + 1]))
                    todo.push_back({nd.first, nd.first + 1});
                todo.push_back({nd.first + 1, nd.first + 1});
                todo.push_back({nd.first, nd.first});
            }
            sort_pairs(out);
            return out;
        }
    }
    // Pairs (object of *this, object of other). With another kd_tree of the same type over
    // objects with extent: the two trees descended together (cross(root, root) above); with
    // any other container, or over points: collide/pairs.hpp's pairs_between (a box query of
    // *this per object of other). Candidates as for self_pairs.
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        if constexpr (!has_extent || !std::is_same_v<Other, kd_tree>) {
            return pairs_between(*this, other, filter);
        } else {
            std::vector<std::pair<iterator, iterator>> out;
            if (slots_.size() == 0 || other.slots_.size() == 0) return out;
            const pair_layout mine = pair_layout_of(), theirs = other.pair_layout_of();
            auto emit = [&](std::uint32_t i, std::uint32_t j) {
                if (!collide::closed_boxes_overlap(mine.box[i], theirs.box[j])) return;
                const slot_index s = mine.slot[i], t = theirs.slot[j];
                if (filter == pair_filter::exact && !collide::narrow_phase(slots_.value(s), other.slots_.value(t)))
                    return;
                out.emplace_back(make(s), other.make(t));
            };
            std::vector<node_pair> todo;
            if (collide::closed_boxes_overlap(mine.subtree[root], theirs.subtree[root])) todo.push_back({root, root});
            while (!todo.empty()) {
                const node_pair p = todo.back();
                todo.pop_back();
                cross_step(other, mine, theirs, p, todo, emit);
            }
            sort_pairs(out);
            return out;
        }
    }


    std::size_t memory_bytes() const {
        return sizeof(*this) + slots_.memory_bytes() + nodes_.capacity() * sizeof(node) +
               extents_.capacity() * sizeof(extent) +
               entry_buffer_.capacity() * sizeof(entry) +
               buckets_.capacity() * sizeof(bucket) +
               (free_pairs_.capacity() + free_buckets_.capacity()) * sizeof(node_index);
    }
    // Tree height in nodes below the root (0 for a single leaf).
    std::size_t height() const { return height_of(root); }
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
    std::size_t points_on_split_planes() const { return on_planes(root); }

    // Checks every structural invariant (split bounds, cells, bucket back-links, counts,
    // depths); returns an empty string when sound, else what is wrong. For tests: O(n).
    std::string check_invariants() const {
        std::string err;
        coords lo, hi;
        lo.fill(-std::numeric_limits<T>::infinity());
        hi.fill(std::numeric_limits<T>::infinity());
        std::size_t seen = 0;
        check_node(root, lo, hi, 0, seen, err);
        if (err.empty() && seen != slots_.size())
            err = "tree holds " + std::to_string(seen) + " points but size() is " + std::to_string(slots_.size());
        return err;
    }

private:
    // ================= helpers: coordinates, cells ========================================
    static coords coords_of(const P& p) {
        coords c;
        for (std::size_t i = 0; i < D; ++i) c[i] = p[i];
        return c;
    }
    // The partitioning key of a stored value: the point itself, or the centre of an object's
    // bounding box (object_center never rounds outside the box).
    static coords key_of(const O& x) {
        coords c;
        for (std::size_t i = 0; i < D; ++i) c[i] = object_center(x, i);
        return c;
    }
    static extent extent_of(const O& x) {
        extent e;
        for (std::size_t i = 0; i < D; ++i) e.lo[i] = object_lower(x, i), e.hi[i] = object_upper(x, i);
        return e;
    }
    static entry make_entry(const O& x, slot_index s) {
        entry e{key_of(x), s};
        if constexpr (has_extent) e.bounds = extent_of(x);
        return e;
    }

    // ---- objects: keeping node extents conservative ----
    // Insertion grows the extents from the leaf upwards and stops at the first node that
    // already contains the object's box: every ancestor's extent contains its descendants',
    // so the nodes above contain it too. O(1) when the object fits its leaf's extent (the
    // usual case), O(depth) at worst.
    void grow_extents_upward(node_index n, const extent& box) {
        while (!extents_[n].contains(box)) {
            extents_[n].grow(box);
            if (n == root) return;
            n = nodes_[n].parent;
        }
    }
    // Erasure tightens only the leaf (O(leaf_capacity)); its ancestors keep their extents,
    // which stay conservative (they contain everything below, and more) until the subtree
    // is rebuilt. Loose extents cost pruning power, never correctness.
    void refit_leaf(node_index leaf) {
        const node& L = nodes_[leaf];
        const bucket& b = buckets_[L.first];
        extent ex = extent::empty();
        for (std::uint32_t i = 0; i < L.count; ++i) ex.grow(extent_of(slots_.value(b.items[i])));
        extents_[leaf] = ex;
    }
    static bool in_cell(const coords& c, const coords& lo, const coords& hi) {
        for (std::size_t i = 0; i < D; ++i)
            if (c[i] < lo[i] || c[i] > hi[i]) return false;
        return true;
    }

    void grow_bounds(const coords& c) {
        for (std::size_t i = 0; i < D; ++i) {
            bounds_lo_[i] = std::min(bounds_lo_[i], c[i]);
            bounds_hi_[i] = std::max(bounds_hi_[i], c[i]);
        }
    }

    void reset_to_empty() {
        nodes_.assign(1, node{});
        if constexpr (has_extent) extents_.assign(1, extent::empty());
        buckets_.clear();
        free_pairs_.clear();
        free_buckets_.clear();
        coords lo, hi;
        lo.fill(-std::numeric_limits<T>::infinity());
        hi.fill(std::numeric_limits<T>::infinity());
        nodes_[root].first = new_bucket(root, lo, hi);
        leaves_ = 1;
        bounds_lo_.fill(std::numeric_limits<T>::infinity());
        bounds_hi_.fill(-std::numeric_limits<T>::infinity());
        size_at_rebuild_ = 0;
    }

    node_index new_bucket(node_index owner, const coords& lo, const coords& hi) {
        node_index b;
        if (!free_buckets_.empty()) {
            b = free_buckets_.back();
            free_buckets_.pop_back();
        } else {
            b = static_cast<node_index>(buckets_.size());
            buckets_.emplace_back();
        }
        buckets_[b].cell_lo = lo;
        buckets_[b].cell_hi = hi;
        buckets_[b].owner = owner;
        return b;
    }
    node_index new_pair() {
        if (!free_pairs_.empty()) {
            const node_index p = free_pairs_.back();
            free_pairs_.pop_back();
            return p;
        }
        const node_index p = static_cast<node_index>(nodes_.size());
        nodes_.resize(nodes_.size() + 2);
        if constexpr (has_extent) extents_.resize(nodes_.size(), extent::empty());
        return p;
    }

    // ================= insertion ===========================================================
    node_index descend(node_index n, const coords& c) const {
        while (!nodes_[n].is_leaf) {
            if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
            const node& nd = nodes_[n];
            n = c[nd.dim] <= nd.split ? nd.first : nd.first + 1;
        }
        return n;
    }

    slot_index insert_at(node_index leaf, const O& x, const coords& c) {
        // Allocate the slot first: if it throws (capacity), nothing else has changed. (A
        // std::bad_alloc in the split below would leave the slot unlinked.)
        const slot_index s = slots_.allocate(x, nodes_[leaf].first);
        grow_bounds(c);
        if constexpr (has_extent) grow_extents_upward(leaf, extent_of(x));
        node& L = nodes_[leaf];
        if (L.count < leaf_capacity) {
            buckets_[L.first].items[L.count++] = s;
            return s;
        }
        // Full leaf: rebuild it as a small subtree over its points plus the new one. Its
        // cell is in its bucket (no walk from the root, which would cost a descent).
        const coords lo = buckets_[L.first].cell_lo, hi = buckets_[L.first].cell_hi;
        entry_buffer_.clear();
        gather(leaf, entry_buffer_);
        if constexpr (has_extent) entry_buffer_.push_back(make_entry(x, s));
        else entry_buffer_.push_back({c, s});
        ++maintenance_.subtree_rebuilds;
        const std::uint16_t deepest =
            build_node(leaf, entry_buffer_.data(), entry_buffer_.size(), lo, hi, nodes_[leaf].depth, false, 0);
        if (deepest > depth_limit()) rebalance_from(leaf);
        return s;
    }

    // Batch distribution for bulk insert: partition [e, e+n) by each split on the way down.
    void distribute(node_index n, entry* e, std::size_t count, std::uint16_t& max_depth) {
        if (count == 0) return;
        if constexpr (has_extent) {
            // Every node on the batch's paths grows by the objects passing through it; a leaf
            // rebuilt below recomputes its own extent exactly.
            for (std::size_t i = 0; i < count; ++i) extents_[n].grow(e[i].bounds);
        }
        if (nodes_[n].is_leaf) {
            node& L = nodes_[n];
            if (L.count + count <= leaf_capacity) {
                bucket& b = buckets_[L.first];
                for (std::size_t i = 0; i < count; ++i) {
                    b.items[L.count++] = e[i].slot;
                    slots_.set_meta(e[i].slot, L.first);
                }
                max_depth = std::max(max_depth, L.depth);
                return;
            }
            const coords lo = buckets_[L.first].cell_lo, hi = buckets_[L.first].cell_hi;
            std::vector<entry> es;
            es.reserve(L.count + count);
            gather(n, es);
            es.insert(es.end(), e, e + count);
            ++maintenance_.subtree_rebuilds;
            max_depth = std::max(max_depth, build_node(n, es.data(), es.size(), lo, hi, nodes_[n].depth, false, 0));
            return;
        }
        const unsigned d = nodes_[n].dim;
        const T s = nodes_[n].split;
        entry* mid = std::partition(e, e + count, [d, s](const entry& a) { return a.c[d] <= s; });
        const node_index first = nodes_[n].first;
        const std::size_t left = static_cast<std::size_t>(mid - e);
        distribute(first, e, left, max_depth);
        distribute(first + 1, mid, count - left, max_depth);
    }

    // ================= erasure =============================================================
    void remove_slot(slot_index s, bool allow_merge) {
        const node_index b = slots_.meta(s);
        const node_index leaf = buckets_[b].owner;
        node& L = nodes_[leaf];
        auto& items = buckets_[b].items;
        for (std::uint32_t i = 0; i < L.count; ++i)
            if (items[i] == s) {
                items[i] = items[--L.count];
                break;
            }
        slots_.release(s);
        if constexpr (has_extent) refit_leaf(leaf);
        if (allow_merge && L.count == 0 && leaf != root) merge_empty_leaf(leaf);
    }

    // An empty leaf whose sibling is a leaf: the parent becomes a leaf holding the sibling's
    // bucket, whose cell widens to the parent's cell (the union of the two children's cells).
    void merge_empty_leaf(node_index leaf) {
        const node_index p = nodes_[leaf].parent;
        const node_index first = nodes_[p].first;
        const node_index sib = leaf == first ? first + 1 : first;
        if (!nodes_[sib].is_leaf) return;
        const unsigned d = nodes_[p].dim;
        const node_index eb = nodes_[leaf].first, sb = nodes_[sib].first;
        bucket& keep = buckets_[sb];
        keep.cell_lo[d] = std::min(keep.cell_lo[d], buckets_[eb].cell_lo[d]);
        keep.cell_hi[d] = std::max(keep.cell_hi[d], buckets_[eb].cell_hi[d]);
        keep.owner = p;
        node& P_ = nodes_[p];
        P_.is_leaf = 1;
        P_.first = sb;
        P_.count = nodes_[sib].count;
        if constexpr (has_extent) extents_[p] = extents_[sib];  // the empty leaf held nothing
        buckets_[eb].owner = no_node;
        free_buckets_.push_back(eb);
        free_pairs_.push_back(first);
        --leaves_;
    }

    void after_erase() {
        if (needs_full_rebuild()) rebuild_all();
    }

    // Galperin & Rivest's deletion rule, plus a leaf-occupancy rule that bounds the garbage
    // left by splits and erasures under long churn.
    bool needs_full_rebuild() const {
        const std::size_t n = slots_.size();
        if (n == 0) return leaves_ > 1;
        if (static_cast<double>(n) < Config::balance_alpha * static_cast<double>(size_at_rebuild_) &&
            size_at_rebuild_ > 4 * leaf_capacity)
            return true;
        return leaves_ > 16 && leaves_ * leaf_capacity > 4 * n + 4 * leaf_capacity;
    }

    // ================= (re)building ========================================================
    std::uint16_t depth_limit() const {
        const double n = std::max<double>(static_cast<double>(slots_.size()), leaf_capacity);
        return static_cast<std::uint16_t>(
            std::ceil(std::log(n / leaf_capacity) / std::log(1.0 / Config::balance_alpha)) + 2);
    }

    // Collect the points below n as build entries and free every node and bucket below n
    // (n itself is kept).
    void gather(node_index n, std::vector<entry>& es) {
        node& nd = nodes_[n];
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i) es.push_back(make_entry(slots_.value(b.items[i]), b.items[i]));
            free_buckets_.push_back(nd.first);
            --leaves_;
            return;
        }
        const node_index first = nd.first;
        gather(first, es);
        gather(first + 1, es);
        free_pairs_.push_back(first);
    }

    // Rebuild the subtree rooted at n over `es`; returns the deepest leaf depth.
    std::uint16_t rebuild_subtree(node_index n, std::vector<entry>& es) {
        coords lo, hi;
        // n's cell: it is intact in n's ancestors (restores) but its own bucket may be
        // freed already, so recompute from the parent chain.
        cell_from_ancestors(n, lo, hi);
        ++maintenance_.subtree_rebuilds;
        return build_node(n, es.data(), es.size(), lo, hi, nodes_[n].depth, false, 0);
    }

    // The cell of n from the root down (O(depth)), valid even when n's subtree is gone.
    void cell_from_ancestors(node_index n, coords& lo, coords& hi) const {
        lo.fill(-std::numeric_limits<T>::infinity());
        hi.fill(std::numeric_limits<T>::infinity());
        std::vector<node_index> path;
        for (node_index c = n; c != root; c = nodes_[c].parent) path.push_back(c);
        for (auto it = path.rbegin(); it != path.rend(); ++it) {
            const node_index p = nodes_[*it].parent;
            const unsigned d = nodes_[p].dim;
            if (*it == nodes_[p].first) hi[d] = nodes_[p].split;
            else lo[d] = nodes_[p].split;
        }
    }

    // Build over entries e[0, n) into node index `at` (already allocated) with cell [lo, hi].
    // fresh: slot ids are positions (base + index into e), used by build_fresh to lay points
    // out in leaf order. Returns the deepest leaf depth.
    std::uint16_t build_node(node_index at, entry* e, std::size_t n, const coords& lo, const coords& hi,
                             std::uint16_t depth, bool fresh, std::size_t base) {
        nodes_[at].depth = depth;
        if (n <= leaf_capacity) {
            const node_index b = new_bucket(at, lo, hi);
            node& L = nodes_[at];
            L.is_leaf = 1;
            L.first = b;
            L.count = static_cast<std::uint32_t>(n);
            for (std::size_t i = 0; i < n; ++i) {
                const slot_index s = fresh ? static_cast<slot_index>(base + i) : e[i].slot;
                buckets_[b].items[i] = s;
                if (fresh) e[i].bucket = b;  // build_fresh sets the slot metadata afterwards
                else slots_.set_meta(s, b);
            }
            if constexpr (has_extent) {
                extent ex = extent::empty();
                for (std::size_t i = 0; i < n; ++i) ex.grow(e[i].bounds);
                extents_[at] = ex;
            }
            ++leaves_;
            return depth;
        }
        const split_choice<T> sc = typename Config::splitter{}(e, n, leaf_capacity);
        const node_index first = new_pair();
        {
            node& nd = nodes_[at];
            nd.is_leaf = 0;
            nd.dim = static_cast<std::uint8_t>(sc.dim);
            nd.split = sc.value;
            nd.first = first;
            nd.count = 0;
        }
        nodes_[first] = node{};
        nodes_[first + 1] = node{};
        nodes_[first].parent = nodes_[first + 1].parent = at;
        nodes_[first].restore = hi[sc.dim];
        nodes_[first + 1].restore = lo[sc.dim];
        coords lhi = hi, rlo = lo;
        lhi[sc.dim] = sc.value;
        rlo[sc.dim] = sc.value;
        const auto d1 = build_node(first, e, sc.left, lo, lhi, static_cast<std::uint16_t>(depth + 1), fresh, base);
        const auto d2 = build_node(first + 1, e + sc.left, n - sc.left, rlo, hi,
                                   static_cast<std::uint16_t>(depth + 1), fresh, base + sc.left);
        if constexpr (has_extent) {
            extents_[at] = extents_[first];
            extents_[at].grow(extents_[first + 1]);
        }
        return std::max(d1, d2);
    }

    // Bulk build into an empty tree. Slots are assigned in leaf order, so each leaf's points
    // are contiguous in memory (sequential access when a query scans a leaf).
    template <class RandomIt>
    void build_fresh(RandomIt batch, std::size_t count) {
        reset_to_empty();
        free_buckets_.push_back(nodes_[root].first);
        leaves_ = 0;
        std::vector<entry> es(count);
        for (std::size_t i = 0; i < count; ++i) {
            es[i] = make_entry(batch[i], static_cast<slot_index>(i));
            grow_bounds(es[i].c);
        }
        coords lo, hi;
        lo.fill(-std::numeric_limits<T>::infinity());
        hi.fill(std::numeric_limits<T>::infinity());
        build_node(root, es.data(), es.size(), lo, hi, 0, true, 0);
        // After partitioning, position i of `es` is the i-th point in leaf order.
        std::vector<O> ordered;
        ordered.reserve(count);
        for (const entry& e : es) ordered.push_back(batch[e.slot]);
        slots_.assign(std::move(ordered), 0);
        for (std::size_t i = 0; i < es.size(); ++i) slots_.set_meta(static_cast<slot_index>(i), es[i].bucket);
        size_at_rebuild_ = slots_.size();
        ++maintenance_.full_rebuilds;
        nodes_.shrink_to_fit();
        buckets_.shrink_to_fit();
    }

    // Rebuild everything from the live slots (slots keep their ids).
    void rebuild_all() {
        std::vector<entry> es;
        es.reserve(slots_.size());
        bounds_lo_.fill(std::numeric_limits<T>::infinity());
        bounds_hi_.fill(-std::numeric_limits<T>::infinity());
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
            es.push_back(make_entry(slots_.value(s), s));
            grow_bounds(es.back().c);
        }
        nodes_.assign(1, node{});
        if constexpr (has_extent) extents_.assign(1, extent::empty());
        buckets_.clear();
        free_pairs_.clear();
        free_buckets_.clear();
        leaves_ = 0;
        coords lo, hi;
        lo.fill(-std::numeric_limits<T>::infinity());
        hi.fill(std::numeric_limits<T>::infinity());
        build_node(root, es.data(), es.size(), lo, hi, 0, false, 0);
        size_at_rebuild_ = slots_.size();
        ++maintenance_.full_rebuilds;
    }

    // Scapegoat search from a too-deep leaf: climb while the subtree is weight-balanced.
    void rebalance_from(node_index n) {
        // n was just rebuilt; find its deepest leaf's ancestor chain from n upward.
        std::size_t size_child = subtree_size(n);
        node_index child = n;
        while (child != root) {
            const node_index p = nodes_[child].parent;
            const node_index first = nodes_[p].first;
            const node_index sib = child == first ? first + 1 : first;
            const std::size_t size_p = size_child + subtree_size(sib);
            const std::size_t heavy = std::max(size_child, size_p - size_child);
            if (static_cast<double>(heavy) > Config::balance_alpha * static_cast<double>(size_p) &&
                size_p > 2 * leaf_capacity) {
                std::vector<entry> es;
                es.reserve(size_p);
                gather(p, es);
                rebuild_subtree(p, es);
                return;
            }
            size_child = size_p;
            child = p;
        }
        rebuild_all();
    }

    std::size_t subtree_size(node_index n) const {
        if (nodes_[n].is_leaf) return nodes_[n].count;
        return subtree_size(nodes_[n].first) + subtree_size(nodes_[n].first + 1);
    }
    std::size_t on_planes(node_index n) const {
        const node& nd = nodes_[n];
        if (nd.is_leaf) return 0;
        std::size_t here = 0;
        for_each_slot(n, [&](slot_index s) { here += object_center(slots_.value(s), nd.dim) == nd.split; });
        return here + on_planes(nd.first) + on_planes(nd.first + 1);
    }
    template <class F>
    void for_each_slot(node_index n, F&& f) const {
        const node& nd = nodes_[n];
        if (nd.is_leaf) {
            for (std::uint32_t i = 0; i < nd.count; ++i) f(buckets_[nd.first].items[i]);
            return;
        }
        for_each_slot(nd.first, f);
        for_each_slot(nd.first + 1, f);
    }
    std::size_t height_of(node_index n) const {
        if (nodes_[n].is_leaf) return 0;
        return 1 + std::max(height_of(nodes_[n].first), height_of(nodes_[n].first + 1));
    }

    // ================= queries =============================================================
    struct knn_query {
        coords x;
        T eps_factor;  // (1 + eps)^2: prune when cell distance^2 * factor >= worst^2
        knn_result_set<T>& best;
    };

    // Arya & Mount's incremental distance: `rd` is the squared distance from x to the cell,
    // `offset[d]` the per-dimension component of it; entering the far child changes one.
    void knn(node_index n, T rd, coords& offset, knn_query& q) const {
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                const slot_index s = b.items[i];
                if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
                const T d2 = squared_distance(slots_.value(s), q.x);
                if (d2 < q.best.worst()) q.best.add(d2, s);
            }
            return;
        }
        const unsigned d = nd.dim;
        const T diff = q.x[d] - nd.split;
        const node_index near = diff <= 0 ? nd.first : nd.first + 1;
        knn(near, rd, offset, q);
        const T old = offset[d];
        const T far_rd = rd - old * old + diff * diff;
        if (far_rd * q.eps_factor < q.best.worst()) {
            offset[d] = diff;
            knn(near == nd.first ? nd.first + 1 : nd.first, far_rd, offset, q);
            offset[d] = old;
        }
    }

    void ball(node_index n, T rd, coords& offset, const coords& x, T r2, std::vector<iterator>& out) const {
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i)
                if (squared_distance(slots_.value(b.items[i]), x) <= r2) out.push_back(make(b.items[i]));
            return;
        }
        const unsigned d = nd.dim;
        const T diff = x[d] - nd.split;
        const node_index near = diff <= 0 ? nd.first : nd.first + 1;
        ball(near, rd, offset, x, r2, out);
        const T old = offset[d];
        const T far_rd = rd - old * old + diff * diff;
        if (far_rd <= r2) {
            offset[d] = diff;
            ball(near == nd.first ? nd.first + 1 : nd.first, far_rd, offset, x, r2, out);
            offset[d] = old;
        }
    }

    void box(node_index n, const P& lo, const P& hi, std::vector<iterator>& out) const {
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i)
                if (object_overlaps_box(slots_.value(b.items[i]), lo, hi)) out.push_back(make(b.items[i]));
            return;
        }
        if constexpr (has_extent) {
            // An object overlapping the box has a bounding box overlapping it (the exact test
            // of object_overlaps_box runs only after the box test), so extents prune exactly.
            for (node_index c = nd.first; c <= nd.first + 1; ++c)
                if (extent_overlaps(extents_[c], lo, hi)) box(c, lo, hi, out);
        } else {
            if (lo[nd.dim] <= nd.split) box(nd.first, lo, hi, out);
            if (hi[nd.dim] >= nd.split) box(nd.first + 1, lo, hi, out);
        }
    }

    // Equal objects have equal coordinates, so only cells containing x are searched; on a
    // split plane both sides may hold copies.
    void collect_equal(node_index n, const coords& c, const O& x, std::vector<slot_index>& out,
                       bool first_only) const {
        const node& nd = nodes_[n];
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i)
                if (slots_.value(b.items[i]) == x) {
                    out.push_back(b.items[i]);
                    if (first_only) return;
                }
            return;
        }
        if (c[nd.dim] <= nd.split) collect_equal(nd.first, c, x, out, first_only);
        if (first_only && !out.empty()) return;
        if (c[nd.dim] >= nd.split) collect_equal(nd.first + 1, c, x, out, first_only);
    }

    // ---- ray casting ----
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
    static T pad(const ray_query& q, unsigned d, T bound) {
        return q.r + gamma * (std::abs(bound) + std::abs(q.o[d]) + q.r);
    }
    // Restrict [t0, t1] to the parameters where o_d + t v_d <= b.
    static void clip_below(const ray_query& q, unsigned d, T b, T& t0, T& t1) {
        const T v = q.v[d];
        if (v == 0) {
            if (!(q.o[d] <= b)) t1 = -1, t0 = 1;
            return;
        }
        const T t = (b - q.o[d]) / v;
        if (v > 0) t1 = std::min(t1, t + gamma * std::abs(t));
        else t0 = std::max(t0, t - gamma * std::abs(t));
    }
    // Restrict [t0, t1] to the parameters where o_d + t v_d >= a.
    static void clip_above(const ray_query& q, unsigned d, T a, T& t0, T& t1) {
        const T v = q.v[d];
        if (v == 0) {
            if (!(q.o[d] >= a)) t1 = -1, t0 = 1;
            return;
        }
        const T t = (a - q.o[d]) / v;
        if (v > 0) t0 = std::max(t0, t - gamma * std::abs(t));
        else t1 = std::min(t1, t + gamma * std::abs(t));
    }

    void cast(node_index n, T t0, T t1, ray_query& q) const {
        if (!(t0 < q.info.hit_time) || t0 > t1) return;
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
                if (slots_.value(b.items[i]).intersect(q.origin, q.direction, q.r, q.info)) q.hit = b.items[i];
            }
            return;
        }
        const unsigned d = nd.dim;
        T l0 = t0, l1 = t1, r0 = t0, r1 = t1;
        clip_below(q, d, nd.split + pad(q, d, nd.split), l0, l1);
        clip_above(q, d, nd.split - pad(q, d, nd.split), r0, r1);
        // Front to back: the child the ray enters first.
        const bool left_first = q.v[d] > 0 || (q.v[d] == 0 && q.o[d] <= nd.split);
        if (left_first) {
            cast(nd.first, l0, l1, q);
            cast(nd.first + 1, r0, r1, q);
        } else {
            cast(nd.first + 1, r0, r1, q);
            cast(nd.first, l0, l1, q);
        }
    }

    // ---- objects: collision pairs (the descent of self_pairs / pairs_with) ----
    struct node_pair {
        node_index a, b;  // a in this tree, b in the other (the same tree for self pairs)
    };
    // A query's snapshot (collide/tree_pair_snapshot.hpp): the objects' boxes leaf by leaf and
    // each node's exact subtree box, by which the descent prunes instead of extents_.
    using pair_layout = collide::tree_pair_snapshot<T, D>;
    pair_layout pair_layout_of() const {
        std::vector<node_index> order{root};  // pre-order: a parent before its children
        for (std::size_t k = 0; k < order.size(); ++k)
            if (!nodes_[order[k]].is_leaf)
                order.push_back(nodes_[order[k]].first), order.push_back(nodes_[order[k]].first + 1);
        return pair_layout(
            order, nodes_.size(), slots_.size(),
            [this](node_index n, auto&& f) {
                const node& nd = nodes_[n];
                if (!nd.is_leaf) return;
                for (std::uint32_t i = 0; i < nd.count; ++i) f(buckets_[nd.first].items[i]);
            },
            [this](node_index n) { return nodes_[n].parent; },
            [this](slot_index s) -> const O& { return slots_.value(s); });
    }
    static T half_perimeter(const extent& e) {
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) s += e.hi[i] - e.lo[i];
        return s;
    }
    // One step of cross(A, B), A = p.a of *this, B = p.b of other (their boxes overlap):
    // two leaves give their objects pairwise (emit(position in mine, position in theirs));
    // otherwise the inner node with the larger box is opened and each child whose box
    // meets the other node's is crossed with it — the rule that keeps the two sides of a
    // node pair of similar size (Gottschalk, Lin & Manocha 1996).
    template <class Emit>
    void cross_step(const kd_tree& other, const pair_layout& mine, const pair_layout& theirs, node_pair p,
                    std::vector<node_pair>& todo, Emit& emit) const {
        const node& na = nodes_[p.a];
        const node& nb = other.nodes_[p.b];
        if (na.is_leaf && nb.is_leaf) {
            // Only objects that meet the other leaf's box can pair across: filtering both
            // sides first costs |A| + |B| tests and often spares most of the |A| x |B|.
            std::array<std::uint32_t, leaf_capacity> as, bs;
            std::size_t ma = 0, mb = 0;
            for (std::uint32_t i = mine.first[p.a], stop = i + na.count; i < stop; ++i)
                if (collide::closed_boxes_overlap(mine.box[i], theirs.subtree[p.b])) as[ma++] = i;
            for (std::uint32_t j = theirs.first[p.b], stop = j + nb.count; j < stop; ++j)
                if (collide::closed_boxes_overlap(theirs.box[j], mine.subtree[p.a])) bs[mb++] = j;
            for (std::size_t i = 0; i < ma; ++i)
                for (std::size_t j = 0; j < mb; ++j) emit(as[i], bs[j]);
            return;
        }
        const bool open_a =
            !na.is_leaf && (nb.is_leaf || half_perimeter(mine.subtree[p.a]) >= half_perimeter(theirs.subtree[p.b]));
        if (open_a) {
            for (node_index c = na.first; c <= na.first + 1; ++c)
                if (collide::closed_boxes_overlap(mine.subtree[c], theirs.subtree[p.b])) todo.push_back({c, p.b});
        } else {
            for (node_index c = nb.first; c <= nb.first + 1; ++c)
                if (collide::closed_boxes_overlap(mine.subtree[p.a], theirs.subtree[c])) todo.push_back({p.a, c});
        }
    }

    // ---- objects: queries pruned by node extents (skd-tree) ----
    static bool extent_overlaps(const extent& ex, const P& lo, const P& hi) {
        for (std::size_t i = 0; i < D; ++i)
            if (ex.hi[i] < lo[i] || ex.lo[i] > hi[i]) return false;  // also false when empty
        return true;
    }
    // Squared distance from x to a closed box (+inf when the box is empty).
    static T extent_squared_distance(const extent& ex, const P& x) {
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const T d = x[i] < ex.lo[i] ? ex.lo[i] - x[i] : (x[i] > ex.hi[i] ? x[i] - ex.hi[i] : T(0));
            s += d * d;
        }
        return s;
    }
    // Rounding slack for distance lower bounds at query x: an object's own distance routine
    // (a triangle's Voronoi-region projection, a sphere's |x - c| - r) may round below the
    // distance to its bounding box. Its error is a few eps times the magnitudes involved, so
    // 16 eps (|x|_inf + |scene|_inf), the bound the bvh uses too, keeps every lower bound
    // conservative (PBRT 3e sec. 3.9 style error bounds).
    T knn_slack(const P& x) const {
        T m = 0;
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(x[i]));
        const extent& r = extents_[root];
        if (!r.is_empty())
            for (std::size_t i = 0; i < D; ++i) m = std::max({m, std::abs(r.lo[i]), std::abs(r.hi[i])});
        return gamma * (2 * m) + std::numeric_limits<T>::min();
    }
    // Lower bound on the squared distance from x to anything below node n.
    T extent_lower_bound(node_index n, const P& x, T slack) const {
        const T d2 = extent_squared_distance(extents_[n], x);
        if (d2 == 0) return 0;
        const T d = std::sqrt(d2) - slack;
        return d > 0 ? d * d : T(0);
    }

    void run_knn(const P& x, scalar_type eps, knn_result_set<T>& best) const {
        if constexpr (has_extent) {
            knn_object_query q{x, (1 + eps) * (1 + eps), knn_slack(x), best};
            knn_objects(root, q);
        } else {
            knn_query q{coords_of(x), (1 + eps) * (1 + eps), best};
            coords offset{};
            knn(root, T(0), offset, q);
        }
    }
    struct knn_object_query {
        const P& x;
        T eps_factor;  // (1 + eps)^2
        T slack;
        knn_result_set<T>& best;
    };
    // Depth-first, nearer extent first; a child is entered only while its extent's distance
    // times (1 + eps) is below the current k-th distance (Arya et al. 1998, on extents instead
    // of cells). The objects' distances are exact, so with eps = 0 the answer is exact.
    void knn_objects(node_index n, knn_object_query& q) const {
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                const slot_index s = b.items[i];
                if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
                const T d2 = object_squared_distance(slots_.value(s), q.x);
                if (d2 < q.best.worst()) q.best.add(d2, s);
            }
            return;
        }
        const T la = extent_lower_bound(nd.first, q.x, q.slack), lb = extent_lower_bound(nd.first + 1, q.x, q.slack);
        const bool left_first = la <= lb;
        const node_index near = left_first ? nd.first : nd.first + 1;
        const T near_bound = left_first ? la : lb, far_bound = left_first ? lb : la;
        if (near_bound * q.eps_factor < q.best.worst()) knn_objects(near, q);
        if (far_bound * q.eps_factor < q.best.worst()) knn_objects(near == nd.first ? nd.first + 1 : nd.first, q);
    }

    // reach: the radius plus the rounding slack, compared with extent distances.
    void ball_objects(node_index n, const P& center, T reach, T r2, std::vector<iterator>& out) const {
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i)
                if (object_squared_distance(slots_.value(b.items[i]), center) <= r2) out.push_back(make(b.items[i]));
            return;
        }
        for (node_index c = nd.first; c <= nd.first + 1; ++c) {
            const T d2 = extent_squared_distance(extents_[c], center);
            if (d2 == 0 || std::sqrt(d2) <= reach) ball_objects(c, center, reach, r2, out);
        }
    }

    // Restrict [t0, t1] to the parameters where the thick ray can touch the (padded) box;
    // false when nothing is left. Same padding argument as the cell planes (sec. 5.10): an
    // object hit at t* has its contact point within r of its bounding box, hence of ex.
    static bool clip_to_extent(const ray_query& q, const extent& ex, T& t0, T& t1) {
        if (ex.is_empty()) return false;
        for (unsigned d = 0; d < D && t0 <= t1; ++d) {
            clip_below(q, d, ex.hi[d] + pad(q, d, ex.hi[d]), t0, t1);
            clip_above(q, d, ex.lo[d] - pad(q, d, ex.lo[d]), t0, t1);
        }
        return t0 <= t1;
    }
    // [t0, t1]: the ray interval already clipped to n's extent. Children are clipped to their
    // own extents and visited in order of entry; a child entered at or after the best hit so
    // far cannot hold a strictly earlier one and is skipped.
    void cast_objects(node_index n, T t0, T t1, ray_query& q) const {
        if (!(t0 < q.info.hit_time)) return;
        const node& nd = nodes_[n];
        if constexpr (Config::collect_stats) ++query_stats_.nodes_visited;
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                if constexpr (Config::collect_stats) ++query_stats_.objects_tested;
                if (slots_.value(b.items[i]).intersect(q.origin, q.direction, q.r, q.info)) q.hit = b.items[i];
            }
            return;
        }
        T a0 = t0, a1 = t1, b0 = t0, b1 = t1;
        const bool hit_a = clip_to_extent(q, extents_[nd.first], a0, a1);
        const bool hit_b = clip_to_extent(q, extents_[nd.first + 1], b0, b1);
        if (hit_a && hit_b) {
            if (a0 <= b0) {
                cast_objects(nd.first, a0, a1, q);
                cast_objects(nd.first + 1, b0, b1, q);
            } else {
                cast_objects(nd.first + 1, b0, b1, q);
                cast_objects(nd.first, a0, a1, q);
            }
        } else if (hit_a) {
            cast_objects(nd.first, a0, a1, q);
        } else if (hit_b) {
            cast_objects(nd.first + 1, b0, b1, q);
        }
    }

    // ---- invariant checking ----
    void check_node(node_index n, const coords& lo, const coords& hi, std::uint16_t depth, std::size_t& seen,
                    std::string& err) const {
        if (!err.empty()) return;
        const node& nd = nodes_[n];
        if (nd.depth != depth) err = "node " + std::to_string(n) + " has a wrong depth";
        if (nd.is_leaf) {
            const bucket& b = buckets_[nd.first];
            if (b.owner != n) err = "bucket owner mismatch at node " + std::to_string(n);
            if (b.cell_lo != lo || b.cell_hi != hi) err = "stale cell at leaf " + std::to_string(n);
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                const slot_index s = b.items[i];
                if (!slots_.occupied(s) || slots_.meta(s) != nd.first) err = "slot back-link broken";
                else if (!in_cell(key_of(slots_.value(s)), lo, hi)) err = "point outside its leaf cell";
                else if constexpr (has_extent) {
                    if (!extents_[n].contains(extent_of(slots_.value(s))))
                        err = "object outside its leaf's extent at node " + std::to_string(n);
                }
            }
            seen += nd.count;
            return;
        }
        if (nodes_[nd.first].parent != n || nodes_[nd.first + 1].parent != n) err = "parent link broken";
        if constexpr (has_extent) {
            for (node_index c = nd.first; c <= nd.first + 1; ++c)
                if (!extents_[c].is_empty() && !extents_[n].contains(extents_[c]))
                    err = "extent of node " + std::to_string(c) + " not inside its parent's";
        }
        if (nodes_[nd.first].restore != hi[nd.dim] || nodes_[nd.first + 1].restore != lo[nd.dim])
            err = "restore bound broken below node " + std::to_string(n);
        coords lhi = hi, rlo = lo;
        lhi[nd.dim] = nd.split;
        rlo[nd.dim] = nd.split;
        check_node(nd.first, lo, lhi, static_cast<std::uint16_t>(depth + 1), seen, err);
        check_node(nd.first + 1, rlo, hi, static_cast<std::uint16_t>(depth + 1), seen, err);
    }

    // ================= data ================================================================
    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;
    using contract_base::ray_thickness_;
    std::vector<node> nodes_;
    std::vector<bucket> buckets_;
    std::vector<node_index> free_pairs_;
    std::vector<node_index> free_buckets_;
    std::size_t leaves_ = 0;
    coords bounds_lo_{}, bounds_hi_{};  // box of all keys inserted since rebuild (points: the root clip of ray casts; objects clip with extents_)
    std::size_t size_at_rebuild_ = 0;
    std::vector<entry> entry_buffer_;  // reused by leaf splits (no allocation per split)
    mutable query_stats query_stats_;  // written only with Config::collect_stats
    kd_tree_maintenance_stats maintenance_;
    // Objects only (empty for points; last, so the point layout above is unchanged): per
    // node, indexed like nodes_, the bounding box of its subtree's objects.
    std::vector<extent> extents_;
};

}  // namespace spatial

#include "spatial/core/point.hpp"
static_assert(spatial::spatial_container<spatial::kd_tree<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::kd_tree<spatial::point<float, 2>>>);
