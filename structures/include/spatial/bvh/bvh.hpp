#pragma once
// spatial::bvh<O, BV, Config> — a dynamic bounding volume hierarchy over stored objects
// (points or bounded objects), ONE template for every bounding-volume type of bv/ (aabb,
// sphere, obb, kdop<K>, ellipsoid, convex_hull). Rationale and complexity: docs/structures/bvh.md.
//
// Layout
//  * Objects live in a slot_storage (stable 32-bit handles = iterators); each slot's meta word
//    is the index of the leaf that holds it.
//  * Nodes live in one std::vector; the two children of an inner node are allocated as a pair
//    (first, first + 1), so a node stores one child index and its parent. A leaf owns a block
//    of Config::leaf_size entries of one permutation array `items_` (slot indices), filled
//    [0, count). A node stores its volume BV and the AABB of its objects' bounds (the box is
//    the volume itself when BV is aabb): builders, insertion costs and box queries use the
//    box, rays, kNN and balls use the volume.
//  * Volumes: a node's volume is BV's default fast fit (bvh/node_volume.hpp) to the hull
//    points (object_hull_points) of all objects below it — fitted top-down by the builders;
//    after an insertion, erase, update or refit(), a leaf is refitted from its objects and an
//    inner node becomes BV::merged of its children (O(1) for the fixed-size types; looser than
//    a fit for sphere/obb/ellipsoid until the next rebuild).
//
// Builders (Config::builder): object-median split along the widest centroid axis, or binned
// SAH (Wald 2007), see bvh/builders.hpp. O(n log n) for balanced splits (fits included,
// except convex_hull whose Quickhull makes it O(n log^2 n)).
//
// Dynamic updates
//  * insert: greedy descent to the child whose AABB surface area grows least (Goldsmith &
//    Salmon 1987, "Automatic creation of object hierarchies for ray tracing"), then the
//    object joins that leaf, or a full leaf is rebuilt with the builder into a subtree; the
//    path is refitted. O(depth) plus O(leaf_size) fits. Hinted insert starts from the hint's
//    leaf, climbing only until a node's box contains the new object.
//  * erase: the leaf entry is removed (swap with its last); an emptied leaf is removed and
//    its sibling takes its parent's place; the path is refitted. O(depth).
//  * rebuild policy: when inserts + erases since the last build exceed
//    rebuild_factor * max(size at that build, min_rebuild_updates), the whole tree is rebuilt
//    with the builder, so a tree grown one object at a time is rebuilt at geometrically
//    growing sizes (O(log n) amortised per update) and quality never drifts far.
//  * motion: update(pos, v) replaces an object and refits its leaf-to-root path; with
//    refit_path = false many objects can be replaced and ONE refit() (bottom-up over all
//    nodes, O(n)) restores the volumes; until then queries throw std::logic_error.
//
// Queries: iterative traversal with a small-buffer stack that spills to the heap
// (bvh/traversal_stack.hpp) — never a fixed-size stack. Rays: front-to-back by the entry
// parameter of each child's volume, pruned by the best hit so far. kNN: best-first over a
// binary heap keyed by the volumes' distance_lower_bound, with (1+eps) pruning (Arya et al.
// 1998). Ball: distance_lower_bound; box: node AABBs. Every node test is conservative: the
// volume is grown by the ray thickness plus a rounding slack of 16 eps (|query|_inf +
// |scene|_inf) (see node_volume.hpp), distance lower bounds are reduced by that slack, so an
// object the exact test reports is never pruned. Statistics of the last query:
// last_query_stats() (not thread-safe: concurrent const queries race on these counters only).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/bv/aabb.hpp"
#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bvh/builders.hpp"
#include "spatial/bvh/node_volume.hpp"
#include "spatial/bvh/traversal_stack.hpp"
#include "spatial/bvh/wide_ray_layout.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/lazy_snapshot.hpp"
#include "spatial/core/motion.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/query_stats.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/ray.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial {

// Compile-time configuration with commented defaults.
template <std::size_t LeafSize = 4, bvh_build_method Builder = bvh_build_method::binned_sah,
          std::size_t SahBins = 16>
struct bvh_config {
    // Objects per leaf (at most). 4 is the usual SAH choice for ray tracing (Wald 2007);
    // larger leaves build faster and suit kNN over points.
    static constexpr std::size_t leaf_size = LeafSize;
    static constexpr bvh_build_method builder = Builder;
    // Bins per axis of the binned SAH (Wald 2007 found 16-32 as good as a full sweep).
    static constexpr std::size_t sah_bins = SahBins;
    // SAH constants C_trav and C_isect (only their ratio matters).
    static constexpr double traversal_cost = 1.0;
    static constexpr double intersection_cost = 1.0;
    // Full rebuild after rebuild_factor * max(size at last build, min_rebuild_updates)
    // inserts + erases.
    static constexpr double rebuild_factor = 1.0;
    static constexpr std::size_t min_rebuild_updates = 32;
    // Motion, automatic strategy (update(first, last)): reinsert the moved objects when at
    // most reinsert_fraction of the tree moved; otherwise refit, and rebuild once the refitted
    // tree's node-box area (relative to the root's) exceeds refit_quality_limit times its
    // value at the last build. Measured in results/collide.csv (refit_decay rows).
    static constexpr double reinsert_fraction = 1.0 / 32;
    static constexpr double refit_quality_limit = 1.3;
    // BV = aabb only: cast rays on a wide (8 or 4 lanes) copy of the tree with quantised
    // child boxes and the objects in leaf order (bvh/wide_ray_layout.hpp; triangles as SIMD
    // blocks of their vertices), built on the first ray cast after a change or by
    // prepare_rays(). Same answers; costs a copy of the objects (or of their vertices).
    static constexpr bool wide_ray_layout = true;
    // Lanes of a wide node: 8 with AVX (one 256-bit slab test per axis), else 4.
    static constexpr std::size_t wide_ray_width = bvh_detail::default_wide_ray_width;
};

template <std::size_t LeafSize = 4>
using bvh_median_config = bvh_config<LeafSize, bvh_build_method::median_split>;
template <std::size_t LeafSize = 4, std::size_t Bins = 16>
using bvh_sah_config = bvh_config<LeafSize, bvh_build_method::binned_sah, Bins>;

// nodes_visited: nodes whose volume was entered; objects_tested: exact object tests.
struct bvh_stats : query_stats {
    bool wide_ray_layout = false;    // last query was a ray cast on the wide layout (nodes
                                     // visited then counts wide nodes)
};

template <stored_object O, class BV = aabb<typename O::scalar_type, O::dimension>, class Config = bvh_config<>>
class bvh : public container_base<bvh<O, BV, Config>, O> {
    using contract_base = container_base<bvh<O, BV, Config>, O>;
    friend contract_base;

public:
    static constexpr const char* structure_name = "bvh";
    SPATIAL_CONTAINER_BASE_MEMBERS(contract_base);
    using volume_type = BV;
    using config = Config;
    static constexpr std::size_t leaf_size = Config::leaf_size;
    static_assert(bounding_volume<BV>, "bvh: BV must model spatial::bounding_volume");
    static_assert(std::is_same_v<typename BV::scalar_type, scalar_type> && BV::dimension == O::dimension,
                  "bvh: BV must have the objects' scalar type and dimension");
    static_assert(leaf_size >= 1 && leaf_size <= 255, "bvh: leaf_size in [1, 255]");

private:
    using T = scalar_type;
    static constexpr std::size_t D = O::dimension;
    using box_type = aabb<T, D>;
    using bv_point = typename BV::point_type;
    using item = bvh_detail::build_item<T, D>;
    using node_index = std::uint32_t;
    static constexpr node_index no_node = std::numeric_limits<node_index>::max();
    static constexpr node_index root = 0;
    static constexpr bool volume_is_box = std::is_same_v<BV, box_type>;
    static constexpr bool wide_rays = volume_is_box && [] {
        if constexpr (requires { Config::wide_ray_layout; }) return bool(Config::wide_ray_layout);
        else return true;
    }();
    using wide_layout = bvh_detail::wide_ray_layout<O, T, D, [] {
        if constexpr (requires { Config::wide_ray_width; }) return std::size_t{Config::wide_ray_width};
        else return bvh_detail::default_wide_ray_width;
    }()>;
    // The SAH counts leaf cost in the blocks the ray layout tests together (triangles: 4 per
    // SIMD step), else per object; see bvh_detail::sah_costs.
    static constexpr std::size_t sah_block = wide_rays && wide_layout::has_ray_forms ? wide_layout::form_lanes : 1;
    struct no_box {};

    struct node {
        BV volume{};
        [[no_unique_address]] std::conditional_t<volume_is_box, no_box, box_type> own_box{};
        node_index parent = no_node;
        node_index first = 0;     // inner: left child (right = first + 1); leaf: block index
        std::uint32_t count = 0;  // leaf: objects in the block
        bool leaf = true;
    };

public:
    bvh() { reset_to_empty(); }
    template <class InputIt>
    bvh(InputIt first, InputIt last) : bvh() { insert(first, last); }
    // Multi-threaded build (spatial::par, core/parallel.hpp): the same tree, node for node.
    template <class InputIt>
    bvh(InputIt first, InputIt last, parallel_policy) : bvh() { insert(first, last, par); }
    // Copies are independent trees.
    bvh(const bvh&) = default;
    bvh& operator=(const bvh&) = default;
    // A moved-from tree is empty and usable; iterators into the source are invalidated.
    bvh(bvh&& o) noexcept(false) : bvh() { swap_contents(o); }
    bvh& operator=(bvh&& o) noexcept(false) {
        if (this != &o) {
            clear();
            swap_contents(o);
        }
        return *this;
    }

    // ---- insertion -------------------------------------------------------------------
    // O(depth + leaf_size fits) plus amortised rebuilds (see the header comment).
    iterator insert(const O& x) {
        detail::require_finite_object(x, site("insert"));
        ensure_fresh();
        return make(insert_from(root, x));
    }
    // Hinted insertion: starts at the hint's leaf and climbs until a node's box contains the
    // object, then descends from there; saves the descent from the root when x lands near
    // the hint (an object moved a little, a stream of nearby points).
    iterator insert(const_iterator hint, const O& x) {
        detail::require_finite_object(x, site("insert(hint, x)"));
        ensure_fresh();
        if (hint == end() || !slots_.occupied(hint.slot())) return make(insert_from(root, x));
        node_index n = slots_.meta(hint.slot());
        const item it = item_of(x, 0);
        while (n != root && !box_contains(box_of(nodes_[n]), it)) n = nodes_[n].parent;
        return make(insert_from(n, x));
    }
    // Bulk insertion, better than a loop: into an empty tree, or with a batch at least a
    // quarter of the size, one build of everything with the builder (O((n + m) log(n + m)));
    // a smaller batch is inserted one by one (O(m depth)) with one rebuild check at the end.
    // Validates the whole batch and reserves storage before storing any of it.
    template <class InputIt>
    void insert(InputIt first, InputIt last) { bulk_insert(first, last, false); }
    // The same with spatial::par: a batch that triggers a build of everything builds it with
    // rebuild(par); the resulting tree is identical to the sequential one.
    template <class InputIt>
    void insert(InputIt first, InputIt last, parallel_policy) { bulk_insert(first, last, true); }

private:
    template <class InputIt>
    void bulk_insert(InputIt first, InputIt last, bool parallel) {
        if constexpr (!std::random_access_iterator<InputIt>) {
            const std::vector<O> batch(first, last);
            bulk_insert(batch.begin(), batch.end(), parallel);
        } else {
            for (auto it = first; it != last; ++it) detail::require_finite_object(*it, site("insert(first, last)"));
            const auto m = static_cast<std::size_t>(last - first);
            if (m == 0) return;
            slots_.require_room_for(m, site("insert(first, last)"));
            ensure_fresh();
            slots_.reserve(slots_.capacity() + m);
            if (slots_.size() == 0 || m * 4 >= slots_.size()) {
                for (auto it = first; it != last; ++it) slots_.allocate(*it, 0);
                if (parallel) rebuild(par);
                else rebuild();
                return;
            }
            for (auto it = first; it != last; ++it) place(slots_.allocate(*it, 0), root);
            updates_since_build_ += m;
            if (needs_rebuild()) rebuild();
        }
    }

public:

    // ---- erasure ---------------------------------------------------------------------
    // O(depth) plus amortised rebuilds. Returns the next element in iteration order.
    iterator erase(const_iterator pos) {
        ensure_fresh();
        const slot_index s = pos.slot();
        remove_from_leaf(s);
        slots_.release(s);
        ++updates_since_build_;
        if (needs_rebuild()) rebuild();
        return make(slots_.next_occupied(s + 1));
    }
    // Erases ALL elements equal to x; returns how many. Search pruned by x's bounding box.
    size_type erase(const O& x) {
        detail::require_finite_object(x, site("erase"));
        ensure_fresh();
        const std::vector<slot_index> hits = collect_equal(x, false);
        for (slot_index s : hits) {
            remove_from_leaf(s);
            slots_.release(s);
        }
        updates_since_build_ += hits.size();
        if (!hits.empty() && needs_rebuild()) rebuild();
        return hits.size();
    }
    void clear() {
        slots_.clear();
        reset_to_empty();
    }

    // ---- motion ------------------------------------------------------------------------
    // Replaces the object at pos by v (same iterator, which is returned). With refit_path
    // (default) its leaf and every ancestor are refitted now, O(depth). With refit_path =
    // false nothing is refitted: replace many objects, then call refit() once; queries throw
    // std::logic_error until then (insert/erase call refit() themselves).
    iterator update(const_iterator pos, const O& v, bool refit_path = true) {
        detail::require_finite_object(v, site("update"));
        if (pos == end() || !slots_.occupied(pos.slot()))
            throw std::invalid_argument(detail::site_text(site("update")) + ": the iterator does not refer to a stored element");
        const slot_index s = pos.slot();
        const node_index leaf = slots_.meta(s);
        slots_.release(s);
        const slot_index s2 = slots_.allocate(v, leaf);  // the free list is LIFO: s2 == s
        if (s2 != s) replace_in_leaf(leaf, s, s2);
        if (refit_path) refit_upward(leaf);
        else stale_ = true;
        return make(s2);
    }
    // Incremental reinsertion of one moved object: it leaves its leaf (as by erase; the
    // path is refitted) and is placed again by the greedy descent from the root (as by
    // insert), so the tree adapts to the new position instead of stretching a node over the
    // old and new ones. The iterator stays valid. O(depth) plus leaf fits.
    iterator reinsert(const_iterator pos, const O& v) {
        detail::require_finite_object(v, site("reinsert"));
        if (pos == end() || !slots_.occupied(pos.slot()))
            throw std::invalid_argument(detail::site_text(site("reinsert")) + ": the iterator does not refer to a stored element");
        ensure_fresh();
        const slot_index s = pos.slot();
        remove_from_leaf(s);
        slots_.release(s);
        const slot_index s2 = slots_.allocate(v, 0);  // LIFO free list: s2 == s
        place(s2, root);
        return make(s2);
    }
    // Moves many objects: [first, last) yields (iterator, new object) pairs; the tree is
    // restored by `strategy` (core/motion.hpp). Every object is validated before any is
    // replaced, so a NaN leaves the tree unchanged. Iterators stay valid.
    //   refit O(n + m), rebuild O(n log n), reinsert O(m depth);
    //   automatic: reinsert if m <= reinsert_fraction * n, else refit, then rebuild if the
    //   refitted tree's quality() exceeds refit_quality_limit * quality at the last build.
    // Returns the strategy that ran (automatic resolves to one of the three).
    template <class PairIt>
    motion_strategy update(PairIt first, PairIt last, motion_strategy strategy = motion_strategy::automatic) {
        std::size_t m = 0;
        for (auto it = first; it != last; ++it, ++m) {
            detail::require_finite_object(it->second, site("update(first, last)"));
            if (it->first == end() || !slots_.occupied(it->first.slot()))
                throw std::invalid_argument(detail::site_text(site("update(first, last)")) + ": an iterator does not refer to a stored element");
        }
        if (m == 0) return strategy == motion_strategy::automatic ? motion_strategy::refit : strategy;
        const bool automatic = strategy == motion_strategy::automatic;
        if (automatic)
            strategy = static_cast<double>(m) <= Config::reinsert_fraction * static_cast<double>(slots_.size())
                           ? motion_strategy::reinsert
                           : motion_strategy::refit;
        if (strategy == motion_strategy::reinsert) {
            for (auto it = first; it != last; ++it) reinsert(it->first, it->second);
            return strategy;
        }
        for (auto it = first; it != last; ++it) update(it->first, it->second, false);
        if (strategy == motion_strategy::rebuild) {
            rebuild();
            return strategy;
        }
        refit();
        if (automatic && quality() > Config::refit_quality_limit * quality_at_build_) {
            rebuild();
            return motion_strategy::rebuild;
        }
        return motion_strategy::refit;
    }
    // The tree's SAH quality: the sum of its nodes' box surface areas divided by the
    // root's (the expected number of nodes a random ray through the root enters, MacDonald
    // & Booth 1990). Lower is better; it grows as a refitted tree ages. O(nodes).
    double quality() const {
        const double root_area = static_cast<double>(box_of(nodes_[root]).surface_area());
        if (!(root_area > 0)) return 1;
        return node_surface_areas().second / root_area;
    }
    // quality() right after the last full build.
    double quality_at_build() const { return quality_at_build_; }

    // Recomputes every node volume bottom-up: leaves fitted to their objects, inner nodes
    // merged from their children. O(n) fits of leaf_size objects plus O(nodes) merges.
    // The topology is kept (rebuild() re-optimises it).
    void refit() {
        std::vector<node_index> order;
        preorder(order);
        for (auto i = order.size(); i-- > 0;) refit_node(order[i]);
        stale_ = false;
    }
    // Rebuilds the whole tree with the builder (iterators stay valid). O(n log n).
    void rebuild() {
        clear_nodes();
        std::vector<item> its;
        its.reserve(slots_.size());
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            its.push_back(item_of(slots_.value(s), s));
        nodes_.push_back(node{});
        if (its.empty()) {
            make_leaf(root, nullptr, 0);
        } else {
            build_subtree(root, its.data(), its.size());
        }
        finish_build();
    }

    // The same tree as rebuild(), node for node, built on several threads (spatial::par):
    //  1. split decisions: the builder partitions disjoint item ranges independently, so the
    //     two halves of a split are planned concurrently (a skewed split plans its small side
    //     sequentially and iterates on the large one: the recursion stays shallow);
    //     and each node's box and volume are fitted right after its split, as the sequential
    //     builder does;
    //  2. nodes are allocated in preorder, the order of the sequential builder (sequential,
    //     O(nodes)).
    // Work O(n log n) as rebuild(); span O(n) (the root's split) plus O(nodes) for step 2.
    void rebuild(parallel_policy) {
        if (slots_.size() < 2 * parallel_grain) {
            rebuild();
            return;
        }
        clear_nodes();
        std::vector<slot_index> occupied;
        occupied.reserve(slots_.size());
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            occupied.push_back(s);
        std::vector<item> its(occupied.size());
        detail::parallel_chunks(its.size(), 4096, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) its[i] = item_of(slots_.value(occupied[i]), occupied[i]);
        });
        nodes_.push_back(node{});

        split_plan plan;
        plan_splits(its.data(), 0, its.size(), plan);
        plan.sort_to_preorder();
        std::size_t records = 0, leaves = 0;
        for (const auto& chunk : plan.chunks) {
            records += chunk.size();
            for (const auto& r : chunk) leaves += r.left == 0;
        }
        nodes_.reserve(records);
        items_.reserve(leaves * leaf_size);

        std::vector<node_index> pending{root};
        for (auto& chunk : plan.chunks)
            for (split_record& r : chunk) {
                const node_index at = pending.back();
                pending.pop_back();
                nodes_[at].volume = std::move(r.volume);
                if constexpr (!volume_is_box) nodes_[at].own_box = r.box;
                if (r.left == 0) {
                    const node_index b = alloc_block();
                    node& nd = nodes_[at];
                    nd.leaf = true;
                    nd.first = b;
                    nd.count = static_cast<std::uint32_t>(r.count);
                    for (std::size_t k = 0; k < r.count; ++k) {
                        block(b)[k] = its[r.begin + k].slot;
                        slots_.set_meta(its[r.begin + k].slot, at);
                    }
                    continue;
                }
                const node_index c = alloc_pair();
                node& nd = nodes_[at];
                nd.leaf = false;
                nd.first = c;
                nd.count = 0;
                nodes_[c].parent = at;
                nodes_[c + 1].parent = at;
                pending.push_back(c + 1);
                pending.push_back(c);
            }
        if constexpr (wide_rays) wide_.reset();
        finish_build();
    }

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x) {
        detail::require_finite_object(x, site("find"));
        require_fresh(site("find"));
        const auto hits = collect_equal(x, true);
        return hits.empty() ? end() : make(hits.front());
    }
    size_type count(const O& x) const {
        detail::require_finite_object(x, site("count"));
        require_fresh(site("count"));
        return collect_equal(x, false).size();
    }

    // ---- ray cast --------------------------------------------------------------------
    // The object first hit before info.hit_time (smallest hit time reported by O::intersect),
    // or end(). Front-to-back: children are visited in order of their volumes' entry
    // parameter, and a node whose entry lies beyond the best hit so far is skipped.
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const {
        validate_ray(origin, direction, thickness);
        require_fresh(site("intersect"));
        bvh_stats st;
        const slot_index hit = cast_ray(origin, direction, thickness, info, st);
        stats_ = st;
        return make(hit);
    }

    // ---- batched ray casts -------------------------------------------------------------
    // hits[i] = intersect_object(rays[i].origin, rays[i].direction, rays[i].thickness,
    // infos[i]) for every i; set infos[i].hit_time beforehand as for a single cast (a default
    // intersect_info means no limit). With spatial::par the rays are spread over threads
    // (core/parallel.hpp); answers do not depend on the policy. last_query_stats() is not
    // updated. Throws std::invalid_argument (before casting anything) when the spans differ
    // in size or a ray is invalid.
    template <class Policy = sequential_policy>
    void intersect_batch(std::span<const ray<point_type>> rays, std::span<iterator> hits, std::span<info_type> infos,
                         Policy = {}) const {
        if (hits.size() != rays.size() || infos.size() != rays.size())
            throw std::invalid_argument(detail::site_text(site("intersect_batch")) + ": rays, hits and infos differ in size");
        for (const auto& r : rays) validate_ray(r.origin, r.direction, r.thickness);
        require_fresh(site("intersect_batch"));
        prepare_rays();  // once, before the threads start
        auto cast_range = [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                bvh_stats st;
                hits[i] = make(cast_ray(rays[i].origin, rays[i].direction, rays[i].thickness, infos[i], st));
            }
        };
        if constexpr (std::is_same_v<Policy, parallel_policy>) detail::parallel_chunks(rays.size(), 256, cast_range);
        else cast_range(0, rays.size());
    }

private:
    void validate_ray(const point_type& origin, const point_type& direction, scalar_type thickness) const {
        detail::require_finite(origin, site("intersect"), "ray origin");
        detail::require_nonzero_direction(direction, site("intersect"));
        detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
    }
    // The slot of the first object hit (capacity() when none); st receives the statistics.
    // The callers have validated the ray and checked that the tree is fresh.
    slot_index cast_ray(const point_type& origin, const point_type& direction, scalar_type thickness, info_type& info,
                        bvh_stats& st) const {
        const auto none = static_cast<slot_index>(slots_.capacity());
        if (slots_.size() == 0) return none;
        const T grow = thickness * (1 + 16 * eps) + slack(origin);
        if constexpr (wide_rays) {
            typename wide_layout::float_ray r;
            const wide_layout& w = wide_.get([this] { return make_wide_layout(); });
            if (w.accepts(to_bv(origin).coords, to_bv(direction).coords, grow, r))
                return intersect_wide(w, r, origin, direction, thickness, info, st);
        }
        if constexpr (volume_is_box)
            if (reciprocals_finite(direction)) return intersect_boxes(origin, direction, thickness, grow, info, st);
        const bv_point o = to_bv(origin), d = to_bv(direction);
        slot_index hit = no_slot;
        struct entry {
            node_index n;
            T t;
        };
        bvh_detail::traversal_stack<entry> stack;
        T t0 = 0, t1 = 0;
        if (!enter(root, o, d, grow, info.hit_time, t0, t1)) return none;
        stack.push({root, t0});
        while (!stack.empty()) {
            const entry e = stack.pop();
            if (e.t > info.hit_time) continue;
            ++st.nodes_visited;
            const node& nd = nodes_[e.n];
            if (nd.leaf) {
                const slot_index* b = block(nd.first);
                for (std::uint32_t i = 0; i < nd.count; ++i) {
                    ++st.objects_tested;
                    if (slots_.value(b[i]).intersect(origin, direction, thickness, info)) hit = b[i];
                }
                continue;
            }
            T a0 = 0, a1 = 0, b0 = 0, b1 = 0;
            const bool ha = enter(nd.first, o, d, grow, info.hit_time, a0, a1);
            const bool hb = enter(nd.first + 1, o, d, grow, info.hit_time, b0, b1);
            if (ha && hb) {  // push the farther first: the nearer is popped first
                if (a0 <= b0) stack.push({nd.first + 1, b0}), stack.push({nd.first, a0});
                else stack.push({nd.first, a0}), stack.push({nd.first + 1, b0});
            } else if (ha) {
                stack.push({nd.first, a0});
            } else if (hb) {
                stack.push({nd.first + 1, b0});
            }
        }
        return hit == no_slot ? none : hit;
    }

public:
    // ---- collision pairs (collide/pairs.hpp) -------------------------------------------
    // Self pairs by descending the tree against itself: a node with itself opens into its
    // children's self pairs and their cross pair; a cross pair of nodes is opened only when
    // their boxes and volumes overlap (BV::overlaps, so tighter volumes prune more), the
    // larger node first (by box surface area). Candidates: the object pairs of every leaf with
    // itself and of every overlapping leaf pair (for aabb: those whose object boxes overlap,
    // see leaf_objects_may_meet); exact adds the narrow phase. Sorted by slots,
    // (lower, higher). last_query_stats(): node pairs tested, candidate pairs.
    // O(node pairs whose volumes overlap + candidates); about O(n + k) for well-separated
    // objects with k pairs (Gottschalk, Lin & Manocha 1996 descend two OBB trees this way).
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
        require_fresh(site("self_pairs"));
        stats_ = {};
        std::vector<std::pair<iterator, iterator>> out;
        if (slots_.size() < 2) return out;
        auto emit = [&](slot_index s, slot_index t) {
            if (!leaf_objects_may_meet(slots_.value(s), slots_.value(t))) return;
            ++stats_.objects_tested;
            if (s > t) std::swap(s, t);
            if (filter == pair_filter::candidates || collide::narrow_phase(slots_.value(s), slots_.value(t)))
                out.emplace_back(make(s), make(t));
        };
        std::vector<std::pair<node_index, node_index>> todo{{root, root}};
        while (!todo.empty()) {
            const auto [a, b] = todo.back();
            todo.pop_back();
            const node& na = nodes_[a];
            if (a == b) {
                if (na.leaf) {
                    const slot_index* blk = block(na.first);
                    for (std::uint32_t i = 0; i < na.count; ++i)
                        for (std::uint32_t j = i + 1; j < na.count; ++j) emit(blk[i], blk[j]);
                } else {
                    todo.push_back({na.first, na.first + 1});
                    todo.push_back({na.first + 1, na.first + 1});
                    todo.push_back({na.first, na.first});
                }
                continue;
            }
            descend_pair(*this, a, b, todo, [&](const node& x, const node& y) {
                const slot_index* bx = block(x.first);
                const slot_index* by = block(y.first);
                for (std::uint32_t i = 0; i < x.count; ++i)
                    for (std::uint32_t j = 0; j < y.count; ++j) emit(bx[i], by[j]);
            });
        }
        sort_pairs(out);
        return out;
    }

    // Pairs (object of *this, object of other). With another bvh of the same type: the two
    // trees descended together as above; with any other container: collide/pairs.hpp's
    // pairs_between (a box query of *this per object of other).
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        if constexpr (!std::is_same_v<Other, bvh>) {
            return pairs_between(*this, other, filter);
        } else {
            require_fresh(site("pairs_with"));
            other.require_fresh(site("pairs_with"));
            stats_ = {};
            std::vector<std::pair<iterator, iterator>> out;
            if (slots_.size() == 0 || other.slots_.size() == 0) return out;
            std::vector<std::pair<node_index, node_index>> todo{{root, root}};
            while (!todo.empty()) {
                const auto [a, b] = todo.back();
                todo.pop_back();
                descend_pair(other, a, b, todo, [&](const node& x, const node& y) {
                    const slot_index* bx = block(x.first);
                    const slot_index* by = other.block(y.first);
                    for (std::uint32_t i = 0; i < x.count; ++i)
                        for (std::uint32_t j = 0; j < y.count; ++j) {
                            if (!leaf_objects_may_meet(slots_.value(bx[i]), other.slots_.value(by[j]))) continue;
                            ++stats_.objects_tested;
                            if (filter == pair_filter::candidates ||
                                collide::narrow_phase(slots_.value(bx[i]), other.slots_.value(by[j])))
                                out.emplace_back(make(bx[i]), other.make(by[j]));
                        }
                });
            }
            sort_pairs(out);
            return out;
        }
    }

    // Builds the ray layout now (BV = aabb with Config::wide_ray_layout; otherwise nothing),
    // which the first ray cast after a change would otherwise do: call it after building to
    // keep that O(n) cost out of the first query (the benchmarks count it as build time).
    void prepare_rays() const {
        if constexpr (wide_rays)
            if (!stale_ && slots_.size() > 0) (void)wide_.get([this] { return make_wide_layout(); });
    }

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // Best-first search (Hjaltason & Samet 1999) over the volumes' distance lower bounds.
    // With eps > 0 a node is skipped when (1 + eps) times its lower bound reaches the current
    // k-th distance, so the i-th reported distance is at most (1 + eps) times the true one
    // (Arya, Mount, Netanyahu, Silverman & Wu 1998). Sorted by increasing distance.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps_factor) const {
        detail::require_finite(x, site("find_nearest"), "query point");
        detail::require_nonnegative(eps_factor, site("find_nearest"), "eps");
        require_fresh(site("find_nearest"));
        stats_ = {};
        std::vector<iterator> out;
        if (k == 0 || slots_.size() == 0) return out;
        knn_result_set<T> best(std::min(k, slots_.size()));
        const T f = (1 + eps_factor) * (1 + eps_factor);
        const bv_point q = to_bv(x);
        const T sl = slack(x);
        struct entry {
            T key;
            node_index n;
            bool operator<(const entry& o) const { return key > o.key; }  // min-heap
        };
        std::vector<entry> heap;
        heap.push_back({0, root});
        auto prunable = [&](T key) {
            const T w = best.worst();
            return key > 0 && w < std::numeric_limits<T>::infinity() && key * f >= w;
        };
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end());
            const entry e = heap.back();
            heap.pop_back();
            if (prunable(e.key)) break;  // every remaining key is at least as large
            ++stats_.nodes_visited;
            const node& nd = nodes_[e.n];
            if (nd.leaf) {
                const slot_index* b = block(nd.first);
                for (std::uint32_t i = 0; i < nd.count; ++i) {
                    ++stats_.objects_tested;
                    best.add(object_squared_distance(slots_.value(b[i]), x), b[i]);
                }
                continue;
            }
            for (node_index c = nd.first; c <= nd.first + 1; ++c) {
                const T lb = std::max(T(0), static_cast<T>(nodes_[c].volume.distance_lower_bound(q)) - sl);
                const T key = lb * lb;
                if (prunable(key)) continue;
                heap.push_back({key, c});
                std::push_heap(heap.begin(), heap.end());
            }
        }
        for (const auto& c : best.finish()) out.push_back(make(c.slot));
        return out;
    }
    // All objects within distance radius of center (closed ball), in no particular order.
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const {
        detail::require_finite(center, site("find_in_ball"), "center");
        detail::require_nonnegative(radius, site("find_in_ball"), "radius");
        require_fresh(site("find_in_ball"));
        stats_ = {};
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        const bv_point q = to_bv(center);
        const T sl = slack(center) + radius * 16 * eps;
        const T r2 = radius * radius;
        visit([&](const node& nd) { return nd.volume.distance_lower_bound(q) - sl <= radius; },
              [&](slot_index s) {
                  if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
              });
        return out;
    }
    // All objects overlapping the closed box [lo, hi] (object_overlaps_box). Pruned by the
    // node AABBs for every BV type (BV::overlaps only compares two volumes of one type).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        detail::require_finite(lo, site("find_in_box"), "box corner lo");
        detail::require_finite(hi, site("find_in_box"), "box corner hi");
        require_fresh(site("find_in_box"));
        stats_ = {};
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        visit(
            [&](const node& nd) {
                const box_type& b = box_of(nd);
                for (std::size_t i = 0; i < D; ++i)
                    if (b.hi[i] < lo[i] || b.lo[i] > hi[i]) return false;
                return true;
            },
            [&](slot_index s) {
                if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
            });
        return out;
    }

    // ---- STL basics and introspection ----------------------------------------------------
    // Includes the heap memory of convex_hull volumes (their vertices, planes, triangles).
    std::size_t memory_bytes() const {
        std::size_t b = sizeof(*this) + slots_.memory_bytes() + nodes_.capacity() * sizeof(node) +
                        items_.capacity() * sizeof(slot_index) +
                        (free_pairs_.capacity() + free_blocks_.capacity()) * sizeof(node_index);
        if constexpr (!std::is_trivially_copyable_v<BV>)
            for (const node& n : nodes_) b += bvh_detail::volume_heap_bytes(n.volume);
        if constexpr (wide_rays)
            if (const wide_layout* w = wide_.peek()) b += sizeof(*w) + w->memory_bytes();
        return b;
    }

    // The last query's counts (core/query_stats.hpp, plus which ray path answered).
    const bvh_stats& last_query_stats() const { return stats_; }
    std::size_t full_rebuilds() const { return full_rebuilds_; }
    std::size_t node_count() const { return nodes_.size() - 2 * free_pairs_.size(); }
    // Height in nodes below the root (0 for a single leaf). O(nodes).
    std::size_t height() const {
        std::size_t h = 0;
        std::vector<std::pair<node_index, std::size_t>> st{{root, 0}};
        while (!st.empty()) {
            const auto [n, d] = st.back();
            st.pop_back();
            h = std::max(h, d);
            if (!nodes_[n].leaf) st.push_back({nodes_[n].first, d + 1}), st.push_back({nodes_[n].first + 1, d + 1});
        }
        return h;
    }
    // Node tightness, weighted as rays weigh nodes: the sum over all nodes of the volume's
    // surface area, and the same sum for the nodes' AABBs (equal for aabb). A random ray
    // enters a convex node with probability proportional to its surface area (the SAH's
    // argument, MacDonald & Booth 1990), so first / second estimates how many node tests a
    // tighter volume saves relative to boxes (lower = tighter). O(nodes).
    std::pair<double, double> node_surface_areas() const {
        std::vector<node_index> order;
        preorder(order);
        double volumes = 0, boxes = 0;
        for (node_index n : order) {
            volumes += static_cast<double>(nodes_[n].volume.surface_area());
            boxes += static_cast<double>(box_of(nodes_[n]).surface_area());
        }
        return {volumes, boxes};
    }
    static std::string volume_name() { return bvh_detail::volume_name(static_cast<const BV*>(nullptr)); }
    // The root volume (for tests and tightness figures).
    const BV& root_volume() const { return nodes_[root].volume; }

    // Checks every structural invariant (parent links, leaf back-links, counts, every object
    // in exactly one leaf, node boxes containing their objects' bounds, volumes containing
    // their objects' hull points up to the rounding slack). Empty string when sound. For
    // tests: O(n depth).
    std::string check_invariants() const {
        std::vector<node_index> order;
        preorder(order);
        std::size_t seen = 0;
        for (node_index n : order) {
            const node& nd = nodes_[n];
            if (n != root && (nd.parent == no_node || (nodes_[nd.parent].first != n && nodes_[nd.parent].first + 1 != n)))
                return "parent link broken at node " + std::to_string(n);
            if (!nd.leaf) continue;
            if (nd.count > leaf_size) return "leaf " + std::to_string(n) + " over capacity";
            if (nd.count == 0 && n != root) return "empty non-root leaf " + std::to_string(n);
            seen += nd.count;
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                const slot_index s = block(nd.first)[i];
                if (!slots_.occupied(s)) return "leaf holds a vacant slot";
                if (slots_.meta(s) != n) return "slot back-link broken";
                const O& v = slots_.value(s);
                for (node_index a = n; a != no_node; a = nodes_[a].parent) {
                    const box_type& b = box_of(nodes_[a]);
                    for (std::size_t k = 0; k < D; ++k)
                        if (object_lower(v, k) < b.lo[k] || object_upper(v, k) > b.hi[k])
                            return "node box misses an object";
                    bool ok = true;
                    object_hull_points(v, [&](const auto& hp) {
                        const bv_point p = to_bv(hp);
                        if (!(nodes_[a].volume.distance_lower_bound(p) <= slack_of(p))) ok = false;
                    });
                    if (!ok) return "volume of node " + std::to_string(a) + " misses a hull point";
                }
            }
        }
        if (seen != slots_.size())
            return "leaves hold " + std::to_string(seen) + " objects but size() is " + std::to_string(slots_.size());
        return {};
    }

private:
    static constexpr T eps = std::numeric_limits<T>::epsilon();

    // ================= small helpers =======================================================
    template <class P>
    static bv_point to_bv(const P& p) {
        bv_point q{};
        for (std::size_t i = 0; i < D; ++i) q[i] = static_cast<T>(p[i]);
        return q;
    }
    static const box_type& box_of(const node& n) {
        if constexpr (volume_is_box) return n.volume;
        else return n.own_box;
    }
    static box_type& box_of(node& n) {
        if constexpr (volume_is_box) return n.volume;
        else return n.own_box;
    }
    // Inside overlapping leaves, an aabb tree carries its test down to the objects: a pair is
    // a candidate only when the objects' boxes overlap (closed), as the octree and kd_tree
    // filter their leaves. Its leaves hold up to 4 triangles when the SAH counts blocks
    // (sah_block), and without the filter every pair of them would reach the narrow phase.
    // Other volumes pass every pair of their (per-object SAH, small) leaves on.
    template <class A, class B>
    static bool leaf_objects_may_meet(const A& a, const B& b) {
        if constexpr (volume_is_box)
            return object_boxes_overlap(a, b);
        else
            return true;
    }
    static item item_of(const O& x, slot_index s) {
        item it;
        for (std::size_t i = 0; i < D; ++i) it.lo[i] = object_lower(x, i), it.hi[i] = object_upper(x, i), it.c[i] = object_center(x, i);
        it.slot = s;
        return it;
    }
    static bool box_contains(const box_type& b, const item& it) {
        for (std::size_t i = 0; i < D; ++i)
            if (it.lo[i] < b.lo[i] || it.hi[i] > b.hi[i]) return false;
        return true;
    }
    const slot_index* block(node_index b) const { return items_.data() + std::size_t(b) * leaf_size; }
    slot_index* block(node_index b) { return items_.data() + std::size_t(b) * leaf_size; }

    // Rounding slack of a query at p: 16 eps (|p|_inf + |scene|_inf), plus the smallest
    // normal number so that it is never 0. Rounding errors of the BV tests are a few eps
    // times the magnitudes involved, which this bounds.
    template <class P>
    T slack(const P& p) const {
        return slack_of(to_bv(p));
    }
    T slack_of(const bv_point& p) const {
        T m = 0;
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(p[i]));
        const box_type& b = box_of(nodes_[root]);
        if (!b.is_empty())
            for (std::size_t i = 0; i < D; ++i) m = std::max({m, std::abs(b.lo[i]), std::abs(b.hi[i])});
        return 16 * eps * (2 * m) + std::numeric_limits<T>::min();
    }

    // The child's grown ray interval clipped to [0, tmax]; false when it misses.
    bool enter(node_index n, const bv_point& o, const bv_point& d, T grow, T tmax, T& t0, T& t1) const {
        const node& nd = nodes_[n];
        if (!bvh_detail::grown_ray_interval(nd.volume, box_of(nd), o, d, grow, t0, t1)) return false;
        if (t1 < 0 || t0 > tmax) return false;
        t0 = std::max(t0, T(0));
        return true;
    }

    // ---- the ray path for BV = aabb ------------------------------------------------------
    // The same traversal and the same answers as the generic path, organised as in fast ray
    // tracers (Williams, Barrus, Morley & Shirley 2005, "An efficient and robust ray-box
    // intersection algorithm"; Wald, Boulos & Shirley 2007, "Ray tracing deformable scenes
    // using dynamic bounding volume hierarchies"):
    //  * per ray, once: the inverse direction and the direction's sign per axis, so a slab
    //    test is two subtractions and two multiplications (no division, no swap) — the near
    //    plane is hi when the direction is negative (-0 included: 1 / -0 = -inf);
    //  * both children of a node are tested from the parent; the nearer one is visited
    //    directly, the farther is pushed only if it is hit, with its entry parameter so it is
    //    dropped unopened when a closer hit has been found meanwhile;
    //  * the counters of last_query_stats() live in registers and are stored once.
    // A zero direction component makes 1/d infinite: an origin strictly inside the grown slab
    // gives (-inf, +inf), outside gives an empty interval, and on its boundary 0 * inf = NaN,
    // which the comparisons below ignore (the slab imposes nothing: correct, the ray lies in
    // the closed slab). Multiplying by a rounded reciprocal adds one rounding to each slab
    // parameter; the grown box's slack (16 eps times the magnitudes, see slack_of) dwarfs
    // those few eps, so no box the exact test would enter is ever skipped.
    struct box_ray {
        std::array<T, D> origin, inverse;
        std::array<bool, D> negative;
        T grow;
    };
    // A nonzero component so small (subnormal) that 1/d overflows would make the slab
    // parameters infinite where the exact ones are merely huge; such rays take the generic
    // path, which divides.
    static bool reciprocals_finite(const point_type& d) {
        for (std::size_t i = 0; i < D; ++i) {
            const T c = static_cast<T>(d[i]);
            if (c != 0 && !std::isfinite(T(1) / c)) return false;
        }
        return true;
    }
    // The grown box's ray interval clipped to [0, tmax]; t0 is its entry. NaN-proof: a NaN
    // slab parameter fails both comparisons and leaves the interval unchanged.
    static bool slab_entry(const box_type& b, const box_ray& r, T tmax, T& t0) {
        T lo = 0, hi = tmax;
        for (std::size_t i = 0; i < D; ++i) {
            const T near_plane = r.negative[i] ? b.hi[i] + r.grow : b.lo[i] - r.grow;
            const T far_plane = r.negative[i] ? b.lo[i] - r.grow : b.hi[i] + r.grow;
            const T tn = (near_plane - r.origin[i]) * r.inverse[i];
            const T tf = (far_plane - r.origin[i]) * r.inverse[i];
            lo = tn > lo ? tn : lo;
            hi = tf < hi ? tf : hi;
        }
        t0 = lo;
        return lo <= hi;
    }
    slot_index intersect_boxes(const point_type& origin, const point_type& direction, T thickness, T grow,
                               info_type& info, bvh_stats& st) const {
        box_ray r;
        for (std::size_t i = 0; i < D; ++i) {
            r.origin[i] = static_cast<T>(origin[i]);
            r.inverse[i] = T(1) / static_cast<T>(direction[i]);
            r.negative[i] = std::signbit(static_cast<T>(direction[i]));
        }
        r.grow = grow;
        std::size_t visited = 0, tested = 0;
        slot_index hit = no_slot;
        // An object type may offer a per-ray preparation (objects::triangle does: the shear of
        // the watertight test); it must give the same answers as the plain call.
        auto test_leaf = [&](const node& nd, const auto& ray) {
            const slot_index* b = block(nd.first);
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                bool h;
                if constexpr (requires { typename O::prepared_ray; })
                    h = this->slots_.value(b[i]).intersect(ray, thickness, info);
                else
                    h = this->slots_.value(b[i]).intersect(origin, direction, thickness, info);
                if (h) hit = b[i];
            }
            tested += nd.count;
        };
        auto traverse = [&](const auto& ray) {
            struct entry {
                node_index n;
                T t;
            };
            bvh_detail::traversal_stack<entry> stack;
            T t_root;
            if (!slab_entry(nodes_[root].volume, r, info.hit_time, t_root)) return;
            node_index n = root;
            for (;;) {
                const node& nd = nodes_[n];
                ++visited;
                if (nd.leaf) {
                    test_leaf(nd, ray);
                } else {
                    T ta, tb;
                    const bool ha = slab_entry(nodes_[nd.first].volume, r, info.hit_time, ta);
                    const bool hb = slab_entry(nodes_[nd.first + 1].volume, r, info.hit_time, tb);
                    if (ha && hb) {
                        if (ta <= tb) {
                            stack.push({nd.first + 1, tb});
                            n = nd.first;
                        } else {
                            stack.push({nd.first, ta});
                            n = nd.first + 1;
                        }
                        continue;
                    }
                    if (ha || hb) {
                        n = ha ? nd.first : nd.first + 1;
                        continue;
                    }
                }
                // Next: the nearest pending node whose entry is not beyond the best hit.
                for (;;) {
                    if (stack.empty()) return;
                    const entry e = stack.pop();
                    if (e.t <= info.hit_time) {
                        n = e.n;
                        break;
                    }
                }
            }
        };
        if constexpr (requires { typename O::prepared_ray; })
            traverse(typename O::prepared_ray(origin, direction));
        else
            traverse(0);
        st.nodes_visited = visited;
        st.objects_tested = tested;
        return hit == no_slot ? static_cast<slot_index>(slots_.capacity()) : hit;
    }

    // ---- collision descent ----------------------------------------------------------------
    // One step of the two-tree descent for node a of *this and node b of `other`: nothing when
    // their boxes or volumes are disjoint, leaves(x, y) for two leaves, otherwise the larger
    // inner node is opened (both children paired with the other node).
    template <class Leaves>
    void descend_pair(const bvh& other, node_index a, node_index b, std::vector<std::pair<node_index, node_index>>& todo,
                      Leaves&& leaves) const {
        const node& na = nodes_[a];
        const node& nb = other.nodes_[b];
        ++stats_.nodes_visited;
        if (!box_of(na).overlaps(box_of(nb))) return;
        if constexpr (!volume_is_box)
            if (!na.volume.overlaps(nb.volume)) return;
        if (na.leaf && nb.leaf) {
            leaves(na, nb);
            return;
        }
        const bool open_a = nb.leaf || (!na.leaf && box_of(na).surface_area() >= box_of(nb).surface_area());
        if (open_a) {
            todo.push_back({na.first, b});
            todo.push_back({na.first + 1, b});
        } else {
            todo.push_back({a, nb.first});
            todo.push_back({a, nb.first + 1});
        }
    }

    // ---- the wide ray layout (BV = aabb) --------------------------------------------------
    // The binary tree as wide_ray_layout::build reads it.
    struct binary_view {
        using node_index = typename bvh::node_index;
        const bvh& t;
        node_index root() const { return bvh::root; }
        bool is_leaf(node_index n) const { return t.nodes_[n].leaf; }
        node_index left(node_index n) const { return t.nodes_[n].first; }
        T lower(node_index n, std::size_t a) const { return box_of(t.nodes_[n]).lo[a]; }
        T upper(node_index n, std::size_t a) const { return box_of(t.nodes_[n]).hi[a]; }
        std::size_t leaf_size(node_index n) const { return t.nodes_[n].count; }
        std::size_t object_count() const { return t.slots_.size(); }
        slot_index leaf_slot(node_index n, std::size_t i) const { return t.block(t.nodes_[n].first)[i]; }
        const O& value(slot_index s) const { return t.slots_.value(s); }
    };
    wide_layout make_wide_layout() const {
        wide_layout w;
        w.build(binary_view{*this});
        return w;
    }
    slot_index intersect_wide(const wide_layout& w, const typename wide_layout::float_ray& r, const point_type& origin,
                              const point_type& direction, T thickness, info_type& info, bvh_stats& st) const {
        std::size_t visited = 0, tested = 0;
        typename wide_layout::object_index hit;
        using object_index = typename wide_layout::object_index;
        // Leaves tested object by object, in order: test(i) is the exact test of object i.
        auto one_by_one = [&](auto&& test) {
            return w.intersect(
                r, info,
                [&](object_index first, std::size_t count) {
                    object_index h = wide_layout::no_object;
                    for (object_index i = first; i < first + count; ++i)
                        if (test(i)) h = i;
                    return h;
                },
                visited, tested);
        };
        if constexpr (wide_layout::has_ray_forms) {
            // Thin rays on the compact blocks alone; thick rays on the stored objects.
            const typename O::prepared_ray ray(origin, direction);
            if (thickness == T(0))
                hit = w.intersect(
                    r, info,
                    [&](object_index first, std::size_t count) { return w.intersect_forms(first, count, ray, info); },
                    visited, tested);
            else
                hit = one_by_one(
                    [&](object_index i) { return slots_.value(w.slot_of(i)).intersect(ray, thickness, info); });
        } else if constexpr (requires { typename O::prepared_ray; }) {
            const typename O::prepared_ray ray(origin, direction);
            hit = one_by_one([&](object_index i) { return w.object(i).intersect(ray, thickness, info); });
        } else {
            hit = one_by_one([&](object_index i) { return w.object(i).intersect(origin, direction, thickness, info); });
        }
        st.nodes_visited = visited;
        st.objects_tested = tested;
        st.wide_ray_layout = true;
        return hit == wide_layout::no_object ? static_cast<slot_index>(slots_.capacity()) : w.slot_of(hit);
    }

    // Depth-first traversal: descend into nodes for which keep(node) holds, call leaf_fn on
    // every slot of a kept leaf.
    template <class Keep, class LeafFn>
    void visit(Keep&& keep, LeafFn&& leaf_fn) const {
        bvh_detail::traversal_stack<node_index> stack;
        if (keep(nodes_[root])) stack.push(root);
        while (!stack.empty()) {
            const node& nd = nodes_[stack.pop()];
            ++stats_.nodes_visited;
            if (nd.leaf) {
                const slot_index* b = block(nd.first);
                for (std::uint32_t i = 0; i < nd.count; ++i) {
                    ++stats_.objects_tested;
                    leaf_fn(b[i]);
                }
                continue;
            }
            if (keep(nodes_[nd.first + 1])) stack.push(nd.first + 1);
            if (keep(nodes_[nd.first])) stack.push(nd.first);
        }
    }

    std::vector<slot_index> collect_equal(const O& x, bool first_only) const {
        std::vector<slot_index> hits;
        if (slots_.size() == 0) return hits;
        const item it = item_of(x, 0);
        visit(
            [&](const node& nd) {
                const box_type& b = box_of(nd);
                for (std::size_t i = 0; i < D; ++i)
                    if (b.hi[i] < it.lo[i] || b.lo[i] > it.hi[i]) return false;
                return !(first_only && !hits.empty());
            },
            [&](slot_index s) {
                if (!(first_only && !hits.empty()) && slots_.value(s) == x) hits.push_back(s);
            });
        return hits;
    }

    void preorder(std::vector<node_index>& order) const {
        order.clear();
        order.reserve(nodes_.size());
        std::vector<node_index> st{root};
        while (!st.empty()) {
            const node_index n = st.back();
            st.pop_back();
            order.push_back(n);
            if (!nodes_[n].leaf) st.push_back(nodes_[n].first + 1), st.push_back(nodes_[n].first);
        }
    }

    void require_fresh(detail::call_site where) const {
        if (stale_)
            throw std::logic_error(detail::site_text(where) +
                                   ": objects were updated with refit_path = false; call refit() first");
    }
    void ensure_fresh() {
        if (stale_) refit();
    }

    // ================= storage of nodes and leaf blocks =====================================
    void clear_nodes() {
        nodes_.clear();
        items_.clear();
        free_pairs_.clear();
        free_blocks_.clear();
    }
    // The bookkeeping after a full build (rebuild() and rebuild(par)).
    void finish_build() {
        size_at_build_ = slots_.size();
        updates_since_build_ = 0;
        stale_ = false;
        ++full_rebuilds_;
        quality_at_build_ = quality();
    }
    void reset_to_empty() {
        clear_nodes();
        nodes_.push_back(node{});
        make_leaf(root, nullptr, 0);
        size_at_build_ = 0;
        updates_since_build_ = 0;
        stale_ = false;
    }
    void swap_contents(bvh& o) {
        this->swap_base(o);
        std::swap(nodes_, o.nodes_);
        std::swap(items_, o.items_);
        std::swap(free_pairs_, o.free_pairs_);
        std::swap(free_blocks_, o.free_blocks_);
        std::swap(size_at_build_, o.size_at_build_);
        std::swap(updates_since_build_, o.updates_since_build_);
        std::swap(full_rebuilds_, o.full_rebuilds_);
        std::swap(stale_, o.stale_);
        std::swap(quality_at_build_, o.quality_at_build_);
        if constexpr (wide_rays) wide_.swap(o.wide_);
    }
    node_index alloc_block() {
        if (!free_blocks_.empty()) {
            const node_index b = free_blocks_.back();
            free_blocks_.pop_back();
            return b;
        }
        items_.resize(items_.size() + leaf_size, no_slot);
        return static_cast<node_index>(items_.size() / leaf_size - 1);
    }
    node_index alloc_pair() {
        if (!free_pairs_.empty()) {
            const node_index p = free_pairs_.back();
            free_pairs_.pop_back();
            nodes_[p] = node{};
            nodes_[p + 1] = node{};
            return p;
        }
        if (nodes_.size() + 2 >= static_cast<std::size_t>(no_node)) throw std::length_error("bvh: too many nodes");
        const auto p = static_cast<node_index>(nodes_.size());
        nodes_.resize(nodes_.size() + 2);
        return p;
    }

    // ================= building ============================================================
    // Makes `at` a leaf holding items [first, first + m) (m <= leaf_size) and fits it.
    void make_leaf(node_index at, const item* first, std::size_t m) {
        const node_index b = alloc_block();
        node& nd = nodes_[at];
        nd.leaf = true;
        nd.first = b;
        nd.count = static_cast<std::uint32_t>(m);
        for (std::size_t i = 0; i < m; ++i) {
            block(b)[i] = first[i].slot;
            slots_.set_meta(first[i].slot, at);
        }
        refit_node(at);
    }
    // Builds the subtree rooted at `at` over the items (in place), iteratively (an explicit
    // task stack: a skewed SAH split sequence cannot overflow the call stack). Each inner
    // node's volume is fitted to ALL hull points below it (tighter than merging).
    void build_subtree(node_index at, item* first, std::size_t m) {
        struct task {
            node_index n;
            std::size_t begin, count;
        };
        std::vector<task> tasks{{at, 0, m}};
        while (!tasks.empty()) {
            const task t = tasks.back();
            tasks.pop_back();
            item* f = first + t.begin;
            const std::size_t left = choose_split(f, t.count);
            if (left == 0) {
                make_leaf(t.n, f, t.count);
                continue;
            }
            const node_index c = alloc_pair();
            node& nd = nodes_[t.n];
            nd.leaf = false;
            nd.first = c;
            nd.count = 0;
            nodes_[c].parent = t.n;
            nodes_[c + 1].parent = t.n;
            fit_inner_from_items(t.n, f, t.count);
            tasks.push_back({c + 1, t.begin + left, t.count - left});
            tasks.push_back({c, t.begin, left});
        }
    }
    std::size_t choose_split(item* f, std::size_t m) const {
        if constexpr (Config::builder == bvh_build_method::median_split) {
            return m <= leaf_size ? 0 : bvh_detail::median_split(f, m);
        } else {
            return bvh_detail::binned_sah_split<Config::sah_bins>(
                f, m, leaf_size, bvh_detail::sah_costs{Config::traversal_cost, Config::intersection_cost, sah_block});
        }
    }
    void fit_inner_from_items(node_index n, const item* f, std::size_t m) {
        box_type b;
        fit_items(f, m, scratch_, b, nodes_[n].volume);
        if constexpr (!volume_is_box) nodes_[n].own_box = b;
    }
    // The box of items [f, f + m) and the volume fitted to all their hull points (in item
    // order), with a caller-owned scratch buffer (so concurrent planners can fit). For
    // BV = aabb the volume is the box.
    void fit_items(const item* f, std::size_t m, std::vector<bv_point>& scratch, box_type& box, BV& volume) const {
        box = box_type::empty();
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t k = 0; k < D; ++k)
                box.lo[k] = std::min(box.lo[k], f[i].lo[k]), box.hi[k] = std::max(box.hi[k], f[i].hi[k]);
        if constexpr (volume_is_box) {
            volume = box;
        } else {
            scratch.clear();
            for (std::size_t i = 0; i < m; ++i)
                object_hull_points(slots_.value(f[i].slot), [&](const auto& hp) { scratch.push_back(to_bv(hp)); });
            volume = bvh_detail::fit_volume<BV>(scratch);
        }
    }
    void add_hull_points(const O& v) {
        object_hull_points(v, [&](const auto& hp) { scratch_.push_back(to_bv(hp)); });
    }

    // ---- the parallel builder's plan (see rebuild(parallel_policy)) -----------------------
    // Below this many items a range is planned sequentially (and the whole build is).
    static constexpr std::size_t parallel_grain = 4096;
    // A node of the plan: its items, its split, and its box and volume fitted when the
    // sequential builder fits them (right after the node's own split: order-dependent fits
    // such as Ritter's sphere then see the items in the same order).
    struct split_record {
        std::size_t begin, count, left;  // items [begin, begin + count); left == 0: a leaf
        box_type box;
        BV volume;
    };
    split_record make_record(const item* base, std::size_t b, std::size_t m, std::size_t left,
                             std::vector<bv_point>& scratch) const {
        split_record r{b, m, left, box_type{}, BV{}};
        fit_items(base + b, m, scratch, r.box, r.volume);
        return r;
    }
    // Chunks of records, each the preorder of a whole subtree or a single node, appended by
    // concurrent planners. Ordering the chunks by their first node's (begin ascending, count
    // descending) — which is preorder for nodes of one partition tree — and concatenating
    // them gives the preorder of the whole tree without sorting the records themselves.
    struct split_plan {
        std::mutex mutex;
        std::vector<std::vector<split_record>> chunks;
        void append(std::vector<split_record>&& local) {
            std::lock_guard<std::mutex> lock(mutex);
            chunks.push_back(std::move(local));
        }
        void sort_to_preorder() {
            std::sort(chunks.begin(), chunks.end(), [](const auto& a, const auto& b) {
                return a.front().begin != b.front().begin ? a.front().begin < b.front().begin
                                                          : a.front().count > b.front().count;
            });
        }
    };
    void plan_splits(item* base, std::size_t b, std::size_t m, split_plan& plan) const {
        // The builder's decisions for a range, sequentially (an explicit stack).
        std::vector<bv_point> scratch;
        auto plan_sequentially = [&](std::size_t b0, std::size_t m0) {
            std::vector<split_record> local;
            std::vector<std::pair<std::size_t, std::size_t>> todo{{b0, m0}};
            while (!todo.empty()) {
                const auto [tb, tm] = todo.back();
                todo.pop_back();
                const std::size_t left = choose_split(base + tb, tm);
                local.push_back(make_record(base, tb, tm, left, scratch));
                if (left == 0) continue;
                todo.push_back({tb + left, tm - left});
                todo.push_back({tb, left});
            }
            plan.append(std::move(local));
        };
        for (;;) {
            if (m <= parallel_grain) {
                plan_sequentially(b, m);
                return;
            }
            const std::size_t left = choose_split(base + b, m);
            std::vector<split_record> single;
            single.push_back(make_record(base, b, m, left, scratch));
            plan.append(std::move(single));
            if (left == 0) return;
            if (left >= parallel_grain && m - left >= parallel_grain) {
                detail::parallel_invoke([&] { plan_splits(base, b, left, plan); },
                                        [&] { plan_splits(base, b + left, m - left, plan); });
                return;
            }
            if (left < m - left) {
                plan_sequentially(b, left);
                b += left;
                m -= left;
            } else {
                plan_sequentially(b + left, m - left);
                m = left;
            }
        }
    }

    // ================= refitting ===========================================================
    // Leaf: box = union of the objects' bounds, volume = fit to their hull points (for the
    // aabb volume: the box itself). Inner: box = union, volume = BV::merged of the children.
    void refit_node(node_index n) {
        // Every change of the tree (build, insert, erase, update, refit) passes here.
        if constexpr (wide_rays) wide_.reset();
        node& nd = nodes_[n];
        if (nd.leaf) {
            box_type b = box_type::empty();
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                const O& v = slots_.value(block(nd.first)[i]);
                for (std::size_t k = 0; k < D; ++k)
                    b.lo[k] = std::min(b.lo[k], object_lower(v, k)), b.hi[k] = std::max(b.hi[k], object_upper(v, k));
            }
            if constexpr (volume_is_box) {
                nd.volume = b;
            } else {
                nd.own_box = b;
                scratch_.clear();
                for (std::uint32_t i = 0; i < nd.count; ++i) add_hull_points(slots_.value(block(nd.first)[i]));
                nodes_[n].volume = bvh_detail::fit_volume<BV>(scratch_);
            }
            return;
        }
        const node& l = nodes_[nd.first];
        const node& r = nodes_[nd.first + 1];
        BV merged = l.volume.merged(r.volume);
        box_type b = box_of(l).merged(box_of(r));
        node& m = nodes_[n];
        m.volume = std::move(merged);
        if constexpr (!volume_is_box) m.own_box = b;
    }
    void refit_upward(node_index n) {
        for (; n != no_node; n = nodes_[n].parent) refit_node(n);
    }

    // ================= dynamic insertion and removal =======================================
    bool needs_rebuild() const {
        const double base = static_cast<double>(std::max(size_at_build_, Config::min_rebuild_updates));
        return static_cast<double>(updates_since_build_) > Config::rebuild_factor * base;
    }
    slot_index insert_from(node_index start, const O& x) {
        const slot_index s = slots_.allocate(x, 0);
        ++updates_since_build_;
        if (needs_rebuild()) {
            rebuild();
            return s;
        }
        place(s, start);
        return s;
    }
    // Goldsmith & Salmon (1987) greedy descent: into the child whose AABB surface area grows
    // least (ties: the smaller resulting area), then into that leaf, splitting it with the
    // builder when full; the path to the root is refitted.
    void place(slot_index s, node_index n) {
        const item it = item_of(slots_.value(s), s);
        while (!nodes_[n].leaf) {
            const node_index c = nodes_[n].first;
            double grow[2], area[2];
            for (int k = 0; k < 2; ++k) {
                bvh_detail::box_accumulator<T, D> acc;
                const box_type& b = box_of(nodes_[c + static_cast<node_index>(k)]);
                acc.add(b.lo.coords, b.hi.coords);
                const double before = acc.area();
                acc.add(it.lo, it.hi);
                area[k] = acc.area();
                grow[k] = area[k] - before;
            }
            n = (grow[1] < grow[0] || (grow[1] == grow[0] && area[1] < area[0])) ? c + 1 : c;
        }
        node& L = nodes_[n];
        if (L.count < leaf_size) {
            block(L.first)[L.count++] = s;
            slots_.set_meta(s, n);
            refit_upward(n);
            return;
        }
        std::vector<item> its;
        its.reserve(leaf_size + 1);
        for (std::uint32_t i = 0; i < L.count; ++i) {
            const slot_index t = block(L.first)[i];
            its.push_back(item_of(slots_.value(t), t));
        }
        its.push_back(it);
        free_blocks_.push_back(L.first);
        L.count = 0;
        build_subtree(n, its.data(), its.size());
        refit_upward(nodes_[n].parent);
    }
    // Removes slot s from its leaf (swap with the last entry); an emptied non-root leaf is
    // removed and its sibling replaces the parent. Refits the path. Does not release s.
    void remove_from_leaf(slot_index s) {
        const node_index n = slots_.meta(s);
        node& L = nodes_[n];
        slot_index* b = block(L.first);
        std::uint32_t i = 0;
        while (i < L.count && b[i] != s) ++i;
        if (i == L.count) return;  // not found: cannot happen for a stored slot
        b[i] = b[--L.count];
        if (L.count > 0 || n == root) {
            refit_upward(n);
            return;
        }
        const node_index p = L.parent;
        const node_index pair = nodes_[p].first;
        const node_index sib = n == pair ? pair + 1 : pair;
        free_blocks_.push_back(L.first);
        const node_index grand = nodes_[p].parent;
        nodes_[p] = nodes_[sib];
        nodes_[p].parent = grand;
        if (nodes_[p].leaf) {
            for (std::uint32_t k = 0; k < nodes_[p].count; ++k) slots_.set_meta(block(nodes_[p].first)[k], p);
        } else {
            nodes_[nodes_[p].first].parent = p;
            nodes_[nodes_[p].first + 1].parent = p;
        }
        nodes_[pair] = node{};
        nodes_[pair + 1] = node{};
        free_pairs_.push_back(pair);
        refit_upward(grand);
    }
    void replace_in_leaf(node_index leaf, slot_index from, slot_index to) {
        slot_index* b = block(nodes_[leaf].first);
        for (std::uint32_t i = 0; i < nodes_[leaf].count; ++i)
            if (b[i] == from) b[i] = to;
    }

    // ================= data ================================================================
    // The range-erase hooks of container_base: past a quarter of the tree the survivors are
    // rebuilt once (O(n log n)); a smaller range is removed with each object's path refit.
    void rebuild_survivors() { rebuild(); }
    void erase_slots(std::span<const slot_index> doomed) {
        ensure_fresh();
        for (slot_index s : doomed) {
            remove_from_leaf(s);
            slots_.release(s);
        }
        updates_since_build_ += doomed.size();
        if (needs_rebuild()) rebuild();
    }

    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;
    using contract_base::ray_thickness_;
    std::vector<node> nodes_;
    std::vector<slot_index> items_;  // leaf blocks of leaf_size slot indices
    std::vector<node_index> free_pairs_, free_blocks_;
    std::vector<bv_point> scratch_;  // hull points of the node being fitted (no allocation per fit)
    std::size_t size_at_build_ = 0, updates_since_build_ = 0, full_rebuilds_ = 0;
    bool stale_ = false;
    double quality_at_build_ = 1;
    mutable bvh_stats stats_;
    struct no_layout {};
    [[no_unique_address]] std::conditional_t<wide_rays, lazy_snapshot<wide_layout>, no_layout> wide_;
};

}  // namespace spatial

#include "spatial/core/point.hpp"
static_assert(spatial::spatial_container<spatial::bvh<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::bvh<spatial::point<float, 2>, spatial::sphere<float, 2>>>);
