#pragma once
// spatial::bvh<O, BV, Config> — a dynamic bounding volume hierarchy over stored objects
// (points or bounded objects), ONE template for every bounding-volume type of bv/ (aabb,
// sphere, obb, kdop<K>, ellipsoid, convex_hull). Rationale and complexity: docs/structures/bvh.md.
//
// This header is the front class: its types, the node, the public interface with each
// member's contract and complexity, and the data. The members are defined, one idea per
// header, in the headers included at the end (out-of-class definitions of the class
// template's members, marked inline as the in-class definitions they were):
//   bvh/config.hpp       bvh_config (settings with commented defaults), bvh_stats
//   bvh/bvh_storage.hpp  node pairs and leaf blocks: allocation, reuse, swap, preorder
//   bvh/bvh_build.hpp    rebuild(), rebuild(par), the subtree builder, the node writer both
//                        builders emit through (split decisions: bvh/builders.hpp)
//   bvh/bvh_motion.hpp   insert, erase, update, reinsert, refit, the rebuild policy
//   bvh/bvh_queries.hpp  the traversal skeleton (visit), find/count, kNN, ball, box
//   bvh/bvh_rays.hpp     ray casts: the generic path, the slab path and the wide layout's
//                        (bvh/wide_ray_layout.hpp, bvh/compact_ray_form.hpp) for BV = aabb
//   bvh/bvh_pairs.hpp    self_pairs / pairs_with by the two-tree descent
//   bvh/bvh_checks.hpp   quality, surface areas, height, memory, check_invariants
// Node volumes: bvh/node_volume.hpp; the traversal stack: bvh/traversal_stack.hpp.
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

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/bv/aabb.hpp"
#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bvh/builders.hpp"
#include "spatial/bvh/config.hpp"
#include "spatial/bvh/node_volume.hpp"
#include "spatial/bvh/traversal_stack.hpp"
#include "spatial/bvh/wide_ray_layout.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/core/capacity_headroom.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/free_list.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/lazy_snapshot.hpp"
#include "spatial/core/motion.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/query_stats.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/preorder_plan.hpp"
#include "spatial/core/ray.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial {

template <stored_object O, class BV = aabb<typename O::scalar_type, O::dimension>, class Config = bvh_default_config<O>>
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
    static constexpr bvh_ray_leaves ray_leaves = [] {
        if constexpr (requires { Config::ray_leaves; }) return bvh_ray_leaves{Config::ray_leaves};
        else return bvh_ray_leaves::copies;
    }();
    static constexpr bool build_headroom = [] {
        if constexpr (requires { Config::build_headroom; }) return bool(Config::build_headroom);
        else return true;
    }();
    // The capacity a full build leaves its node and leaf-block arrays of n entries
    // (core/capacity_headroom.hpp): an eighth spare, or none without Config::build_headroom.
    static constexpr std::size_t capacity_after_build(std::size_t n) {
        return build_headroom ? detail::capacity_with_headroom(n) : n;
    }
    // The SAH counts a leaf's cost in blocks of objects tested as one (bvh_detail::sah_costs):
    // the blocks the ray layout tests together (triangles: 4 per SIMD step); for points, half
    // a leaf; else one object. A point's box has no area, so with a cost per point every split
    // of two or more points costs C_trav + 0 < C_isect N and the SAH split point trees down to
    // single points: 2n nodes, each leaf a block of leaf_size slots holding one. Counted in
    // blocks of leaf_size / 2, up to half a leaf of points is one test and stays a leaf: the
    // build leaves each leaf about half free for later insertions, as B-tree bulk loading
    // leaves a fill factor (docs/structures/bvh.md).
    static constexpr std::size_t sah_block = wide_rays && wide_layout::has_ray_forms ? wide_layout::form_lanes
                                             : point_object<O> ? std::max<std::size_t>(1, leaf_size / 2)
                                                               : 1;
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
    // The empty tree has no nodes yet (the "unallocated" state: nodes_ and items_ are empty
    // vectors); the first insertion allocates the root leaf (ensure_root). So constructing an
    // empty tree allocates nothing and cannot throw, like std::vector's.
    bvh() noexcept = default;
    template <class InputIt>
    bvh(InputIt first, InputIt last) : bvh() { insert(first, last); }
    // Multi-threaded build (spatial::par, core/parallel.hpp): the same tree, node for node.
    template <class InputIt>
    bvh(InputIt first, InputIt last, parallel_policy) : bvh() { insert(first, last, par); }
    // Copies are independent trees.
    bvh(const bvh&) = default;
    bvh& operator=(const bvh&) = default;
    // A moved-from tree is empty and usable; iterators into the source are invalidated.
    // noexcept: the source takes the unallocated empty tree in exchange (member-wise swaps of
    // vectors, scalars and the ray layout's pointer), so a std::vector of trees moves them when
    // it grows instead of copying (std::move_if_noexcept).
    bvh(bvh&& o) noexcept : bvh() { swap_contents(o); }
    bvh& operator=(bvh&& o) noexcept { return this->move_assign_from(o); }

    // ---- insertion -------------------------------------------------------------------
    // O(depth + leaf_size fits) plus amortised rebuilds (see bvh_motion.hpp).
    iterator insert(const O& x) {
        detail::require_finite_object(x, site("insert"));
        ensure_fresh();
        ensure_root();
        return make(insert_from(root, x));
    }
    // Hinted insertion: starts at the hint's leaf and climbs until a node's box contains the
    // object, then descends from there; saves the descent from the root when x lands near
    // the hint (an object moved a little, a stream of nearby points).
    iterator insert(const_iterator hint, const O& x);
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
    void bulk_insert(InputIt first, InputIt last, bool parallel);  // bvh_motion.hpp

public:

    // ---- erasure ---------------------------------------------------------------------
    // O(depth) plus amortised rebuilds. Returns the next element in iteration order.
    iterator erase(const_iterator pos);
    // Erases ALL elements equal to x; returns how many. Search pruned by x's bounding box.
    size_type erase(const O& x);
    // Back to the unallocated empty tree (as the default constructor makes it); the vectors
    // keep their capacity, like std::vector::clear, so refilling does not reallocate. Cannot
    // throw (the move assignment clears the target first).
    void clear() noexcept {
        slots_.clear();
        drop_tree();
    }

    // ---- motion ------------------------------------------------------------------------
    // Replaces the object at pos by v (same iterator, which is returned). With refit_path
    // (default) its leaf and every ancestor are refitted now, O(depth). With refit_path =
    // false nothing is refitted: replace many objects, then call refit() once; queries throw
    // std::logic_error until then (insert/erase call refit() themselves).
    iterator update(const_iterator pos, const O& v, bool refit_path = true);
    // Incremental reinsertion of one moved object: it leaves its leaf (as by erase; the
    // path is refitted) and is placed again by the greedy descent from the root (as by
    // insert), so the tree adapts to the new position instead of stretching a node over the
    // old and new ones. The iterator stays valid. O(depth) plus leaf fits.
    iterator reinsert(const_iterator pos, const O& v);
    // Moves many objects: [first, last) yields (iterator, new object) pairs; the tree is
    // restored by `strategy` (core/motion.hpp). Every object is validated before any is
    // replaced, so a NaN leaves the tree unchanged. Iterators stay valid.
    //   refit O(n + m), rebuild O(n log n), reinsert O(m depth);
    //   automatic: reinsert if m <= reinsert_fraction * n, else refit, then rebuild if the
    //   refitted tree's quality() exceeds refit_quality_limit * quality at the last build.
    // Returns the strategy that ran (automatic resolves to one of the three).
    template <class PairIt>
    motion_strategy update(PairIt first, PairIt last, motion_strategy strategy = motion_strategy::automatic);
    // The tree's SAH quality: the sum of its nodes' box surface areas divided by the
    // root's (the expected number of nodes a random ray through the root enters, MacDonald
    // & Booth 1990). Lower is better; it grows as a refitted tree ages. O(nodes).
    double quality() const;
    // quality() right after the last full build.
    double quality_at_build() const { return quality_at_build_; }

    // Recomputes every node volume bottom-up: leaves fitted to their objects, inner nodes
    // merged from their children. O(n) fits of leaf_size objects plus O(nodes) merges.
    // The topology is kept (rebuild() re-optimises it).
    void refit();
    // Rebuilds the whole tree with the builder (iterators stay valid). O(n log n).
    void rebuild();
    // The same tree as rebuild(), node for node, built on several threads (spatial::par):
    //  1. split decisions: the builder partitions disjoint item ranges independently, so the
    //     two halves of a split are planned concurrently (a skewed split plans its small side
    //     sequentially and iterates on the large one: the recursion stays shallow);
    //     and each node's box and volume are fitted right after its split, as the sequential
    //     builder does;
    //  2. nodes are allocated in preorder, the order of the sequential builder (sequential,
    //     O(nodes)).
    // Work O(n log n) as rebuild(); span O(n) (the root's split) plus O(nodes) for step 2.
    void rebuild(parallel_policy);

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x);
    size_type count(const O& x) const;

    // ---- ray cast --------------------------------------------------------------------
    // The object first hit before info.hit_time (smallest hit time reported by O::intersect),
    // or end(). Front-to-back: children are visited in order of their volumes' entry
    // parameter, and a node whose entry lies beyond the best hit so far is skipped.
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const;

    // ---- batched ray casts -------------------------------------------------------------
    // hits[i] = intersect_object(rays[i].origin, rays[i].direction, rays[i].thickness,
    // infos[i]) for every i; set infos[i].hit_time beforehand as for a single cast (a default
    // intersect_info means no limit). With spatial::par the rays are spread over threads
    // (core/parallel.hpp); answers do not depend on the policy. last_query_stats() is not
    // updated. Throws std::invalid_argument (before casting anything) when the spans differ
    // in size or a ray is invalid.
    template <class Policy = sequential_policy>
    void intersect_batch(std::span<const ray<point_type>> rays, std::span<iterator> hits, std::span<info_type> infos,
                         Policy = {}) const;

private:
    // bvh_rays.hpp
    void validate_ray(const point_type& origin, const point_type& direction, scalar_type thickness) const;
    slot_index cast_ray(const point_type& origin, const point_type& direction, scalar_type thickness, info_type& info,
                        bvh_stats& st) const;

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
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const;
    // Pairs (object of *this, object of other). With another bvh of the same type: the two
    // trees descended together as above; with any other container: collide/pairs.hpp's
    // pairs_between (a box query of *this per object of other).
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const;

    // Builds the ray layout now (BV = aabb with Config::wide_ray_layout; otherwise nothing),
    // which the first ray cast after a change would otherwise do: call it after building to
    // keep that O(n) cost out of the first query (the benchmarks count it as build time).
    void prepare_rays() const;
    // The same with the objects gathered on every core of the parallel back end (the copy
    // is most of the layout's O(n); the collapse of the tree stays on one thread).
    void prepare_rays(parallel_policy) const;

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // Best-first search (Hjaltason & Samet 1999) over the volumes' distance lower bounds.
    // With eps > 0 a node is skipped when (1 + eps) times its lower bound reaches the current
    // k-th distance, so the i-th reported distance is at most (1 + eps) times the true one
    // (Arya, Mount, Netanyahu, Silverman & Wu 1998). Sorted by increasing distance.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps_factor) const;
    // All objects within distance radius of center (closed ball), in no particular order.
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const;
    // All objects overlapping the closed box [lo, hi] (object_overlaps_box). Pruned by the
    // node AABBs for every BV type (BV::overlaps only compares two volumes of one type).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const;

    // ---- STL basics and introspection ----------------------------------------------------
    // Includes the heap memory of convex_hull volumes (their vertices, planes, triangles).
    std::size_t memory_bytes() const;

    // The last query's counts (core/query_stats.hpp, plus which ray path answered).
    const bvh_stats& last_query_stats() const { return stats_; }
    std::size_t full_rebuilds() const { return full_rebuilds_; }
    // Nodes in the tree (0 for the unallocated empty tree, 1 for an empty tree that had elements).
    std::size_t node_count() const { return nodes_.size() - 2 * free_pairs_.size(); }
    // Height in nodes below the root (0 for a single leaf and for the unallocated tree). O(nodes).
    std::size_t height() const;
    // Node tightness, weighted as rays weigh nodes: the sum over all nodes of the volume's
    // surface area, and the same sum for the nodes' AABBs (equal for aabb). A random ray
    // enters a convex node with probability proportional to its surface area (the SAH's
    // argument, MacDonald & Booth 1990), so first / second estimates how many node tests a
    // tighter volume saves relative to boxes (lower = tighter). O(nodes).
    std::pair<double, double> node_surface_areas() const;
    static std::string volume_name() { return bvh_detail::volume_name(static_cast<const BV*>(nullptr)); }
    // The root volume (for tests and tightness figures); the unallocated tree answers the
    // volume of an empty leaf.
    const BV& root_volume() const { return has_root() ? nodes_[root].volume : empty_volume(); }

    // Checks every structural invariant (parent links, leaf back-links, counts, every object
    // in exactly one leaf, node boxes containing their objects' bounds, volumes containing
    // their objects' hull points up to the rounding slack). Empty string when sound. For
    // tests: O(n depth).
    std::string check_invariants() const;

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
    // Inside overlapping leaves, only for aabb the objects' boxes are compared (bvh_pairs.hpp).
    template <class A, class B>
    static bool leaf_objects_may_meet(const A& a, const B& b);
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

    // ---- queries (bvh_queries.hpp) and rays (bvh_rays.hpp) --------------------------------
    template <class P>
    T slack(const P& p) const;
    T slack_of(const bv_point& p) const;
    // The slack for a largest absolute coordinate m (of the query and the scene together).
    static T slack_for_magnitude(T m) { return 16 * eps * (2 * m) + underflow_slack<T>; }
    bool enter(node_index n, const bv_point& o, const bv_point& d, T grow, T tmax, T& t0, T& t1) const;
    struct box_ray;
    static bool reciprocals_finite(const point_type& d);
    static bool slab_entry(const box_type& b, const box_ray& r, T tmax, T& t0);
    slot_index intersect_boxes(const point_type& origin, const point_type& direction, T thickness, T grow,
                               info_type& info, bvh_stats& st) const;

    // ---- collision descent (bvh_pairs.hpp) ------------------------------------------------
    template <class Leaves>
    void descend_pair(const bvh& other, node_index a, node_index b, std::vector<std::pair<node_index, node_index>>& todo,
                      Leaves&& leaves) const;

    // ---- the wide ray layout (bvh_rays.hpp) -------------------------------------------------
    struct binary_view;
    wide_layout make_wide_layout(bool parallel = false) const;
    slot_index intersect_wide(const wide_layout& w, const typename wide_layout::float_ray& r, const point_type& origin,
                              const point_type& direction, T thickness, info_type& info, bvh_stats& st) const;

    // ---- the traversal skeleton (bvh_queries.hpp) ---------------------------------------------
    template <class Keep, class LeafFn>
    void visit(Keep&& keep, LeafFn&& leaf_fn) const;
    std::vector<slot_index> collect_equal(const O& x, bool first_only) const;

    void preorder(std::vector<node_index>& order) const;  // bvh_storage.hpp
    // require_fresh: queries throw std::logic_error after update(..., refit_path = false)
    // until refit(); ensure_fresh: modifications refit first.
    void require_fresh(detail::call_site where) const {
        if (stale_)
            throw std::logic_error(detail::site_text(where) +
                                   ": objects were updated with refit_path = false; call refit() first");
    }
    void ensure_fresh() {
        if (stale_) refit();
    }

    // ---- tree storage (bvh_storage.hpp) -----------------------------------------------
    // The unallocated empty tree: no nodes, no leaf blocks (the state of a default-constructed
    // or moved-from tree, and after clear()). Every query answers it as empty; the modifiers
    // that place an object below the root call ensure_root first (the full builds make their
    // own root). has_root() is false exactly in this state.
    bool has_root() const noexcept { return !nodes_.empty(); }
    void clear_nodes() noexcept;
    void drop_tree() noexcept;
    void ensure_root();
    static const BV& empty_volume();
    void finish_build(std::optional<double> quality_now = std::nullopt);  // bvh_build.hpp
    double quality_from(double preorder_area_sum) const;                 // bvh_checks.hpp
    void swap_contents(bvh& o) noexcept;
    node_index alloc_block();
    node_index alloc_pair();

    // ---- building (bvh_build.hpp) -----------------------------------------------------
    void write_leaf(node_index at, const item* first, std::size_t m);  // the node writer
    void open_leaf(node_index at, std::size_t m);
    void open_leaf_on(node_index at, node_index block, std::size_t m);
    void fill_leaf(node_index at, const item* first);
    node_index write_inner(node_index at);
    void write_inner_over(node_index at, node_index pair);
    void make_leaf(node_index at, const item* first, std::size_t m);
    void build_subtree(node_index at, item* first, std::size_t m);
    void store_in_leaf_order(bool parallel) noexcept;
    using item_bounds = bvh_detail::range_bounds<T, D>;
    static box_type box_from(const item_bounds& b);
    // on_every_core: a large node's passes may run on every core (the top of rebuild(par)).
    std::size_t choose_split(item* f, std::size_t m, const item_bounds& bounds, std::array<item_bounds, 2>& parts,
                             bool on_every_core = false) const;
    void fit_inner_from_items(node_index n, const item* f, std::size_t m);
    void fit_items(const item* f, std::size_t m, std::vector<bv_point>& scratch, box_type& box, BV& volume) const;
    void add_hull_points(const O& v);
    // Below this many items a range is planned sequentially (and the whole build is).
    static constexpr std::size_t parallel_grain = 4096;
    struct split_record;
    split_record make_record(const item* base, std::size_t b, std::size_t m, std::size_t left, const item_bounds& bounds,
                             std::vector<bv_point>& scratch) const;
    using split_plan = detail::preorder_plan<split_record>;  // core/preorder_plan.hpp
    void plan_splits(item* base, std::size_t b, std::size_t m, item_bounds bounds, split_plan& plan) const;
    double replay(split_plan& plan, const item* its);

    // ---- dynamic updates (bvh_motion.hpp) ---------------------------------------------
    void refit_node(node_index n);
    box_type objects_box(const node& leaf) const;  // the box of a leaf's objects
    void refit_upward(node_index n);

    // ---- undoing a change that ran out of memory (bvh_backup.hpp) ----------------------
    template <class Nodes>
    void refit_or_undo(const Nodes& order);
    void refit_upward_or_undo(node_index n);
    void refit_upward_if_possible(node_index n) noexcept;
    struct leaf_backup;
    leaf_backup backup_leaf(node_index n) const;
    void restore(leaf_backup& b) noexcept;
    struct tree_backup;
    tree_backup backup_all();
    void restore(tree_backup& b) noexcept;
    void rebuild_in_place();
    void rebuild_in_place(parallel_policy);
    void rebuild_if_possible() noexcept;
    void reserve_removals(std::size_t m);
    void remove_empty_leaf(node_index n) noexcept;
    bool needs_rebuild() const;
    slot_index insert_from(node_index start, const O& x);
    void place(slot_index s, node_index n);
    void grow_upward(node_index n, const item& it) noexcept;
    node_index lowest_holder(node_index n, const item& it) const;
    void remove_from_leaf(slot_index s);
    void replace_in_leaf(node_index leaf, slot_index from, slot_index to);

    // The range-erase hooks of container_base: past a quarter of the tree the survivors are
    // rebuilt once (O(n log n)); a smaller range is removed with each object's path refit.
    void rebuild_survivors() { rebuild(); }
    void erase_slots(std::span<const slot_index> doomed);

    // ================= data ================================================================
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

#include "spatial/bvh/bvh_storage.hpp"
#include "spatial/bvh/bvh_backup.hpp"
#include "spatial/bvh/bvh_build.hpp"
#include "spatial/bvh/bvh_motion.hpp"
#include "spatial/bvh/bvh_queries.hpp"
#include "spatial/bvh/bvh_rays.hpp"
#include "spatial/bvh/bvh_pairs.hpp"
#include "spatial/bvh/bvh_checks.hpp"

#include "spatial/core/point.hpp"
static_assert(spatial::spatial_container<spatial::bvh<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::bvh<spatial::point<float, 2>, spatial::sphere<float, 2>>>);
