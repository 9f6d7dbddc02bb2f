#pragma once
// spatial::octree<O, Config> — a dynamic 2^D-ary tree (quadtree in 2D, octree in 3D) over a
// cubic root cell, storing points or objects with extent, as a LOOSE octree (Ulrich 2000,
// "Loose octrees", Game Programming Gems): a node's loose cell is its cell scaled by
// Config::loose_factor (k) about its centre, and an object is stored at the deepest node whose
// loose cell contains its bounding box, found by following the object's centre. k = 1 is the
// classic octree (objects straddling a split plane stay in the inner node).
//
// Layout (docs/structures/octree-and-grids.md has the complexity table):
//  * Objects live in a slot_storage (stable 32-bit handles = iterators); a slot's metadata is
//    the node holding it, and pos_[slot] its index in that node's list, so erasure is O(1)
//    plus the merge check.
//  * Nodes live in one vector; the 2^D children of a node are one contiguous block, so a node
//    needs one child index. Freed blocks are reused.
//  * Each node stores its cell (corner + edge) and its loose cell. A child's loose cell is
//    clipped to its parent's, so loose cells nest exactly despite rounding: a query that
//    prunes by loose cells can never lose an object.
//  * Growth: an object outside the root's loose cell re-roots outward — a new root of twice
//    the size takes the old root as the child on the object's side (one level per doubling).
//    If more than 8 levels would be needed, or the root is still a leaf, the tree is rebuilt
//    around the bounding box of everything instead (at most about 2100 / 8 such rebuilds over
//    the whole double range, so the cost is bounded).
//  * Splitting: a leaf over capacity splits unless the split would be useless (every object
//    stays, or all centres coincide — duplicates); then it retries only after its count
//    doubles, so piles of duplicates cost O(1) amortised per insert, never infinite depth.
//    Cells are not split below root_size / 2^max_depth nor below 64 ulps of their coordinates.
//  * Merging: after an erasure, a node whose children are all leaves and whose subtree holds
//    at most leaf_capacity objects takes them back (cascading upward).
//  * Collision pairs: self_pairs descends the tree against itself (simultaneous traversal of
//    node pairs, Gottschalk, Lin & Manocha 1996; Larsson & Akenine-Moller's bounding volume
//    test tree), crossing sibling subtrees whose boxes overlap — objects of different
//    subtrees meet because loose cells overlap and closed cells share faces; pairs_with does
//    the same between two octrees of the same type. O(node pairs that overlap + candidates).
//  * Queries: kNN best-first by distance to the loose cell (Hjaltason & Samet 1999), with
//    (1+eps)-approximation; ball and box ranges pruned by loose cells; ray casting front to back
//    over the loose cells (children visited in order of slab entry time — an ordered variant of
//    the parametric traversal of Revelles, Urena & Lastra 2000), a subtree skipped once the best
//    hit so far is not later than its entry time.
// Traversals use explicit stacks (no recursion depth limit).
//
// Files: this header holds the class (types, the public interface with each member's
// contract, the data); the configuration is in octree_config.hpp, and the member definitions,
// included at the end, in octree_cells.hpp (cell geometry), octree_update.hpp (items, blocks,
// splits, merges), octree_root.hpp (root growth and rebuilds), octree_queries.hpp (kNN,
// ranges, lookup), octree_rays.hpp (ray casting), octree_pairs.hpp (collision pairs) and
// octree_checks.hpp (diagnostics).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/collide/pairs.hpp"
#include "spatial/collide/tree_pair_snapshot.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/free_list.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/octree/octree_config.hpp"
#include "spatial/octree/ray_cell_clip.hpp"

namespace spatial {

template <stored_object O, class Config = octree_config<>>
class octree : public container_base<octree<O, Config>, O> {
    using contract_base = container_base<octree<O, Config>, O>;
    friend contract_base;

public:
    static constexpr const char* structure_name = "octree";
    SPATIAL_CONTAINER_BASE_MEMBERS(contract_base);
    using config = Config;
    static constexpr std::size_t leaf_capacity = Config::leaf_capacity;
    static_assert(Config::leaf_capacity >= 1, "octree: leaf_capacity must be at least 1");
    static_assert(Config::loose_factor >= 1.0 && Config::loose_factor <= 16.0, "octree: loose factor in [1, 16]");
    static_assert(Config::max_depth >= 1 && Config::max_depth <= 1000, "octree: max_depth in [1, 1000]");
    static_assert(O::dimension >= 1 && O::dimension <= 8, "octree: dimension in [1, 8] (2^D children per node)");

private:
    using T = scalar_type;
    static constexpr std::size_t D = O::dimension;
    static constexpr std::size_t fanout = std::size_t(1) << D;
    using coords = std::array<T, D>;
    using node_index = std::uint32_t;
    static constexpr node_index no_node = std::numeric_limits<node_index>::max();
    // The meta word of a slot allocated but not yet in a node (a bulk insert that fails
    // half-way takes out exactly the placed ones). No node has this index (new_block's limit).
    static constexpr node_index unplaced = no_node - 1;
    // Relative slack on distance lower bounds: an object's exact distance (e.g. a sphere's)
    // may round a few ulps below the distance to a box containing it.
    static constexpr T bound_slack = 1 - 16 * std::numeric_limits<T>::epsilon();

    struct node {
        coords lo{};        // cell corner
        T size = 0;         // cell edge
        coords llo{}, lhi{};  // loose cell (nested in the parent's)
        node_index first_child = no_node;
        node_index parent = no_node;
        std::size_t split_retry = 0;  // a refused split is retried at this many items
        std::vector<slot_index> items;
        bool is_leaf() const { return first_child == no_node; }
    };
    struct extent {
        coords lo, hi, c;
    };
    // A slot with the box the bulk builders partition it by (octree_bulk.hpp). A point is its
    // own box, so only its coordinates are kept: a third of the bytes each partition moves.
    struct point_record {
        coords c;
        slot_index s;
        const coords& centre() const { return c; }
        extent box() const { return {c, c, c}; }
    };
    struct box_record {
        extent e;
        slot_index s;
        const coords& centre() const { return e.c; }
        const extent& box() const { return e; }
    };
    using record = std::conditional_t<bounded_object<O>, box_record, point_record>;

public:
    octree() = default;
    template <class InputIt>
    octree(InputIt first, InputIt last) { insert(first, last); }
    // Copies are independent; moves leave the source empty (its iterators die with it).
    octree(const octree&) = default;
    octree& operator=(const octree&) = default;
    octree(octree&& o) noexcept { swap_contents(o); }
    octree& operator=(octree&& o) noexcept { return this->move_assign_from(o); }

    // ---- insertion -------------------------------------------------------------------
    // O(depth) descent plus amortised splits; depth is O(log(root size / object spacing)).
    iterator insert(const O& x) {
        detail::require_finite_object(x, site("insert"));
        const extent e = extent_of(x);
        ensure_root_contains(e);
        return make(place(root_, x, e));
    }
    // Hinted insertion: climbs from the hint's node to the first ancestor whose loose cell
    // contains x, then descends; O(1) when x belongs to the hint's leaf.
    iterator insert(const_iterator hint, const O& x) {
        detail::require_finite_object(x, site("insert(hint, x)"));
        const extent e = extent_of(x);
        const bool rebuilt = ensure_root_contains(e);
        node_index n = root_;
        if (!rebuilt && hint != end() && slots_.occupied(hint.slot())) {
            n = slots_.meta(hint.slot());
            while (n != root_ && !loose_contains(nodes_[n], e)) n = nodes_[n].parent;
        }
        return make(place(n, x, e));
    }
    // Bulk insertion, better than a loop: validates everything, grows the root ONCE to cover
    // the batch's bounding box, then partitions the batch down the tree top-down as an array
    // (octree_bulk.hpp: each node scatters its share by child once, a leaf takes its share
    // with one reservation). Into an empty tree, or a batch at least as large as the tree,
    // everything is rebuilt around the joint bounding box by the same array partition, each
    // node's list allocated once: O((n + m) depth). Each object is routed by the same tests
    // as a single insertion's descent, and nodes split by the same rules. Strong guarantee
    // (invalid input, capacity errors, allocation failure).
    template <class InputIt>
    void insert(InputIt first, InputIt last);

    // ---- erasure ---------------------------------------------------------------------
    // O(1) plus the merge check (O(2^D) per level merged). Returns the next element.
    // Cannot fail once the free list has room (reserved first): removal does not allocate and
    // merging is best-effort (collapse_from).
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        const node_index n = slots_.meta(s);
        slots_.reserve_releases(1);
        remove_item(n, s);
        slots_.release(s);
        collapse_from(n);
        return make(slots_.next_occupied(s + 1));
    }
    // Erases ALL elements equal to x; returns how many. Visits only nodes whose loose cell
    // contains x's box.
    size_type erase(const O& x) {
        detail::require_finite_object(x, site("erase"));
        std::vector<slot_index> hits;
        collect_equal(x, hits, false);
        slots_.reserve_releases(hits.size());
        for (slot_index s : hits) erase(make(s));
        return hits.size();
    }
    void clear() {
        slots_.clear();
        pos_.clear();
        nodes_.clear();
        free_blocks_.clear();
        root_ = no_node;
    }

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x) {
        detail::require_finite_object(x, site("find"));
        std::vector<slot_index> hits;
        collect_equal(x, hits, true);
        return hits.empty() ? end() : make(hits.front());
    }
    size_type count(const O& x) const {
        detail::require_finite_object(x, site("count"));
        std::vector<slot_index> hits;
        collect_equal(x, hits, false);
        return hits.size();
    }

    // ---- ray cast --------------------------------------------------------------------
    // The object first hit before info.hit_time (smallest t reported by O::intersect), or
    // end(). Front to back over loose cells grown by the thickness; a subtree is entered only
    // while its entry time is before the best hit. Typical cost: the cells the ray crosses
    // before its first hit; O(n) worst case (every loose cell crossing the ray).
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const;

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // Best-first over loose cells; (1+eps)-approximate: a node is skipped once (1+eps) times
    // its distance is not below the k-th best distance, so the i-th reported distance is at
    // most (1+eps) times the true i-th. Expected O(log n + k log k) on well-spread data.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps) const;
    // Objects at distance <= radius (object_squared_distance <= radius^2).
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const;
    // Objects overlapping the closed box [lo, hi] (object_overlaps_box).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const;

    // ---- collision pairs (collide/pairs.hpp; the descent: octree_pairs.hpp) --------------
    // Self pairs (lower slot, higher slot) by descending the tree against itself, and pairs
    // with another container (object of *this, object of other): with another octree of the
    // same type the two trees descended together, else box queries. Sorted; candidates are
    // the pairs whose closed bounding boxes overlap, exact adds the narrow phase.
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const;
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const;

    // ---- STL basics and introspection ----------------------------------------------------
    std::size_t memory_bytes() const {
        std::size_t b = sizeof(*this) + slots_.memory_bytes() + pos_.capacity() * sizeof(std::uint32_t) +
                        nodes_.capacity() * sizeof(node) + free_blocks_.capacity() * sizeof(node_index);
        for (const node& nd : nodes_) b += nd.items.capacity() * sizeof(slot_index);
        return b;
    }
    // Nodes in use (the root and every allocated child block).
    std::size_t node_count() const {
        return root_ == no_node ? 0 : nodes_.size() - fanout * free_blocks_.size();
    }
    // Levels below the root (0 for a single leaf).
    std::size_t height() const;
    // Edge of the root cell (0 when nothing was ever inserted since the last clear()).
    scalar_type root_size() const { return root_ == no_node ? T(0) : nodes_[root_].size; }
    // Objects stored in inner (non-leaf) nodes: straddlers of the classic octree, objects too
    // big for their centre's child in the loose one.
    std::size_t objects_in_inner_nodes() const {
        std::size_t n = 0;
        for (std::size_t i = 0; i < nodes_.size(); ++i)
            if (!nodes_[i].is_leaf()) n += nodes_[i].items.size();
        return n;
    }

    // Checks every structural invariant (back-links, loose containment, nesting, counts);
    // empty when sound. For tests: O(n + nodes).
    std::string check_invariants() const;

private:
    // ---- cell geometry (octree_cells.hpp) ----
    static extent extent_of(const O& x);
    static void merge_into(extent& a, const extent& b);
    static bool loose_contains(const node& nd, const extent& e);
    static T cell_distance2(const node& nd, const coords& q);
    static void set_cell(node& nd, const coords& lo, T size);
    static T mid(const node& nd, std::size_t i);
    static std::size_t child_bits(const node& nd, const coords& c);
    static node geometry_of(const node& nd);
    static void set_child_cell(node& c, const node& parent, std::size_t b);
    bool may_split(const node& nd) const;
    std::size_t target_of(const node& nd, const extent& e) const;

    // ---- node and item bookkeeping, splits, merges (octree_update.hpp) ----
    void swap_contents(octree& o);
    slot_index allocate(const O& x);
    void add_item(node_index n, slot_index s);
    void remove_item(node_index n, slot_index s);
    node_index new_block();
    void make_children(node_index n);
    bool split(node_index n);
    void split_recursive(node_index n);
    slot_index place(node_index start, const O& x, const extent& e);
    // ---- bulk construction and merging (octree_bulk.hpp) ----
    record record_of(slot_index s) const;
    static void prefetch(const node* nd);
    void build_subtree(node_index root, std::vector<record>& recs);
    void merge_batch(std::vector<record>& recs);
    bool try_collapse(node_index x);
    void collapse_from(node_index n);
    // The range-erase hooks of container_base (see octree_update.hpp).
    void erase_slots(std::span<const slot_index> doomed);
    void rebuild_survivors() { rebuild_all(); }

    // ---- root management (octree_root.hpp) ----
    bool ensure_root_contains(const extent& e);
    void grow_once(const extent& e);
    void rebuild_all(const extent* extra = nullptr);
    void build_over(const std::vector<slot_index>& live, const extent& box, bool any);

    // ---- lookup (octree_queries.hpp) ----
    void collect_equal(const O& x, std::vector<slot_index>& out, bool first_only) const;

    // ---- collision pairs: the descent of self_pairs / pairs_with (octree_pairs.hpp) ----
    using bounds = collide::box_bounds<T, D>;
    struct node_pair {
        node_index a, b;  // a in this tree, b in the other (the same tree for self pairs)
    };
    struct pair_descent {
        std::vector<node_pair> crosses;  // cross(a, b) still to open
        std::vector<node_index> nodes;   // one object's walk over subtrees
    };
    // A query's snapshot (collide/tree_pair_snapshot.hpp): the objects' boxes in pre-order of
    // their nodes and each node's exact subtree box, by which the descent prunes instead of
    // the loose cells (up to k times wider than what a subtree occupies).
    using pair_layout = collide::tree_pair_snapshot<T, D>;
    pair_layout pair_layout_of() const;
    template <class Emit>
    void self_descent(const pair_layout& lay, Emit& emit) const;
    static void push_children(const node& nd, std::vector<node_index>& stack);
    template <class Hit>
    static void walk_subtrees(const octree& tree, const pair_layout& lay, const bounds& box,
                              std::vector<node_index>& stack, Hit&& hit);
    template <class Emit>
    void cross_step(const octree& other, const pair_layout& mine, const pair_layout& theirs, node_pair p,
                    pair_descent& walk, Emit& emit) const;
    static std::size_t meeting_children(const node& nd, node_index n, const pair_layout& lay, const bounds& box,
                                        bool opened, std::array<node_index, fanout>& out);

    // ================= data ================================================================
    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;
    using contract_base::ray_thickness_;
    std::vector<std::uint32_t> pos_;  // pos_[slot]: index in its node's item list
    std::vector<node> nodes_;
    std::vector<node_index> free_blocks_;
    node_index root_ = no_node;
};

}  // namespace spatial

#include "spatial/octree/octree_cells.hpp"
#include "spatial/octree/octree_update.hpp"
#include "spatial/octree/octree_bulk.hpp"
#include "spatial/octree/octree_root.hpp"
#include "spatial/octree/octree_queries.hpp"
#include "spatial/octree/octree_rays.hpp"
#include "spatial/octree/octree_pairs.hpp"
#include "spatial/octree/octree_checks.hpp"

#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"
static_assert(spatial::spatial_container<spatial::octree<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::octree<spatial::point<float, 2>>>);
static_assert(spatial::spatial_container<spatial::octree<spatial::objects::box<double, 3>>>);
