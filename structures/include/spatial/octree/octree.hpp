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

public:
    octree() = default;
    template <class InputIt>
    octree(InputIt first, InputIt last) { insert(first, last); }
    // Copies are independent; moves leave the source empty (its iterators die with it).
    octree(const octree&) = default;
    octree& operator=(const octree&) = default;
    octree(octree&& o) noexcept { swap_contents(o); }
    octree& operator=(octree&& o) noexcept {
        if (this != &o) {
            clear();
            swap_contents(o);
        }
        return *this;
    }

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
    // the batch's bounding box, then distributes the batch down the tree top-down (each node
    // partitions its share once; a leaf receiving many objects is split recursively, moving
    // each object O(depth) times in total instead of once per split). Into an empty tree, or
    // a batch at least as large as the tree, everything is rebuilt around the joint bounding
    // box. Strong guarantee for invalid input and capacity errors.
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        std::vector<O> batch(first, last);
        for (const O& x : batch) detail::require_finite_object(x, site("insert(first, last)"));
        if (batch.empty()) return;
        slots_.require_room_for(batch.size(), site("insert(first, last)"));
        slots_.reserve(slots_.capacity() + batch.size());
        const bool rebuild = slots_.size() == 0 || batch.size() >= slots_.size();
        extent box = extent_of(batch.front());
        for (const O& x : batch) merge_into(box, extent_of(x));
        for (std::size_t i = 0; i < D; ++i) box.c[i] = box.lo[i] + (box.hi[i] - box.lo[i]) / 2;
        if (!rebuild) ensure_root_contains(box);
        std::vector<slot_index> fresh;
        fresh.reserve(batch.size());
        for (const O& x : batch) fresh.push_back(allocate(x));
        if (rebuild) {
            rebuild_all();
            return;
        }
        distribute(root_, fresh);
    }

    // ---- erasure ---------------------------------------------------------------------
    // O(1) plus the merge check (O(2^D) per level merged). Returns the next element.
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        const node_index n = slots_.meta(s);
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
                              info_type& info) const {
        detail::require_finite(origin, site("intersect"), "ray origin");
        detail::require_nonzero_direction(direction, site("intersect"));
        detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
        if (slots_.size() == 0) return end();
        const coords o = coords_of(origin), v = coords_of(direction);
        slot_index hit = no_slot;
        struct pending {
            node_index n;
            T t_enter;
        };
        std::vector<pending> stack;
        {
            T t0 = 0, t1 = info.hit_time;
            const node& r = nodes_[root_];
            if (!detail::clip_box<T, D>(o, v, r.llo, r.lhi, thickness, t0, t1)) return end();
            stack.push_back({root_, t0});
        }
        std::array<pending, fanout> kids;
        while (!stack.empty()) {
            const pending p = stack.back();
            stack.pop_back();
            if (!(p.t_enter < info.hit_time)) continue;
            const node& nd = nodes_[p.n];
            for (slot_index s : nd.items)
                if (slots_.value(s).intersect(origin, direction, thickness, info)) hit = s;
            if (nd.is_leaf()) continue;
            std::size_t m = 0;
            for (std::size_t b = 0; b < fanout; ++b) {
                const node_index c = nd.first_child + static_cast<node_index>(b);
                const node& cn = nodes_[c];
                if (cn.is_leaf() && cn.items.empty()) continue;
                T t0 = 0, t1 = info.hit_time;
                if (detail::clip_box<T, D>(o, v, cn.llo, cn.lhi, thickness, t0, t1) && t0 < info.hit_time)
                    kids[m++] = {c, t0};
            }
            // Insertion sort (at most 2^D entries) by decreasing entry time, then push: the
            // earliest entry ends on top of the stack and is visited first.
            for (std::size_t i = 1; i < m; ++i)
                for (std::size_t j = i; j > 0 && kids[j - 1].t_enter < kids[j].t_enter; --j) std::swap(kids[j - 1], kids[j]);
            for (std::size_t i = 0; i < m; ++i) stack.push_back(kids[i]);
        }
        return hit == no_slot ? end() : make(hit);
    }

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // Best-first over loose cells; (1+eps)-approximate: a node is skipped once (1+eps) times
    // its distance is not below the k-th best distance, so the i-th reported distance is at
    // most (1+eps) times the true i-th. Expected O(log n + k log k) on well-spread data.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps) const {
        detail::require_finite(x, site("find_nearest"), "query point");
        detail::require_nonnegative(eps, site("find_nearest"), "eps");
        std::vector<iterator> out;
        if (k == 0 || slots_.size() == 0) return out;
        const coords q = coords_of(x);
        const T factor = (1 + eps) * (1 + eps);
        knn_result_set<T> best(std::min<std::size_t>(k, slots_.size()));
        using entry = std::pair<T, node_index>;
        std::priority_queue<entry, std::vector<entry>, std::greater<entry>> frontier;
        frontier.push({cell_distance2(nodes_[root_], q), root_});
        while (!frontier.empty()) {
            const auto [lb, n] = frontier.top();
            frontier.pop();
            if (!(lb * bound_slack * factor < best.worst())) break;
            const node& nd = nodes_[n];
            for (slot_index s : nd.items) best.add(object_squared_distance(slots_.value(s), x), s);
            if (nd.is_leaf()) continue;
            for (std::size_t b = 0; b < fanout; ++b) {
                const node_index c = nd.first_child + static_cast<node_index>(b);
                if (nodes_[c].is_leaf() && nodes_[c].items.empty()) continue;
                const T d2 = cell_distance2(nodes_[c], q);
                if (d2 * bound_slack * factor < best.worst()) frontier.push({d2, c});
            }
        }
        for (const auto& c : best.finish()) out.push_back(make(c.slot));
        return out;
    }
    // Objects at distance <= radius (object_squared_distance <= radius^2).
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const {
        detail::require_finite(center, site("find_in_ball"), "center");
        detail::require_nonnegative(radius, site("find_in_ball"), "radius");
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        const coords q = coords_of(center);
        const T r2 = radius * radius;
        std::vector<node_index> stack{root_};
        while (!stack.empty()) {
            const node& nd = nodes_[stack.back()];
            stack.pop_back();
            if (!(cell_distance2(nd, q) * bound_slack <= r2)) continue;
            for (slot_index s : nd.items)
                if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
            if (!nd.is_leaf())
                for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
        }
        return out;
    }
    // Objects overlapping the closed box [lo, hi] (object_overlaps_box).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        detail::require_finite(lo, site("find_in_box"), "box corner lo");
        detail::require_finite(hi, site("find_in_box"), "box corner hi");
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        std::vector<node_index> stack{root_};
        while (!stack.empty()) {
            const node& nd = nodes_[stack.back()];
            stack.pop_back();
            bool overlaps = true;
            // Same comparison form as object_box_overlaps_box, so an object inside the
            // loose cell that passes it implies the cell passes it (even for lo > hi).
            for (std::size_t i = 0; i < D && overlaps; ++i) overlaps = !(nd.lhi[i] < lo[i] || nd.llo[i] > hi[i]);
            if (!overlaps) continue;
            for (slot_index s : nd.items)
                if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
            if (!nd.is_leaf())
                for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
        }
        return out;
    }

    // ---- collision pairs (collide/pairs.hpp) ---------------------------------------------
    // Self pairs by descending the tree against itself: a simultaneous traversal of node
    // pairs (Gottschalk, Lin & Manocha 1996 descend two OBB trees this way; Larsson &
    // Akenine-Moller 2001 call the pairs the bounding volume test tree). In a loose octree an
    // object can meet objects stored in its own node, in its ancestors, in its descendants AND
    // in other subtrees (siblings' loose cells overlap when k > 1; closed cells share faces
    // even when k = 1), so the descent is
    //   self(N)     = the pairs within N's items, N's items against the subtrees below N,
    //                 self(c) for every child c, cross(c, c') for every two distinct children
    //                 whose subtree boxes overlap;
    //   cross(A, B) = every object below A (A included) against every object below B, opened
    //                 one level at a time (both nodes when they have the same size), a pair of
    //                 children crossed only when their subtree boxes overlap.
    // A subtree box is the exact bounding box of the objects below the node (min / max, no
    // rounding; inside the loose cell, often much smaller), computed once per query; an object
    // against a subtree walks it, pruned by closed box comparisons, so no pair is ever lost.
    // Every pair of objects has exactly one place in this decomposition, so each is considered
    // once: no seen-set. Candidates: the pairs whose closed bounding boxes overlap; exact adds
    // the narrow phase (the set brute force reports). Sorted by slots, (lower, higher).
    // Cost: O(n + nodes) for the boxes, plus O(node pairs whose subtree boxes overlap +
    // inner-node objects x nodes their boxes reach + candidates): on well-spread data a node
    // meets O(3^D) nodes of its size, so about O(3^D n + k) for k pairs, against n box
    // queries (O(n log n) at best) through self_pairs_by_queries; O(n^2) when everything
    // overlaps, as any method that lists the pairs.
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
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
        pair_descent walk;
        std::vector<node_index> selves{root_};
        while (!walk.crosses.empty() || !selves.empty()) {
            if (!walk.crosses.empty()) {  // finish crosses first: keeps both stacks short
                const node_pair p = walk.crosses.back();
                walk.crosses.pop_back();
                cross_step(*this, lay, lay, p, walk, emit);
                continue;
            }
            const node_index n = selves.back();
            selves.pop_back();
            const node& nd = nodes_[n];
            const std::uint32_t first = lay.first[n], last = first + static_cast<std::uint32_t>(nd.items.size());
            for (std::uint32_t i = first; i < last; ++i)
                for (std::uint32_t j = i + 1; j < last; ++j) emit(i, j);
            if (nd.is_leaf()) continue;
            for (std::uint32_t i = first; i < last; ++i) {
                push_children(nd, walk.nodes);
                walk_subtrees(*this, lay, lay.box[i], walk.nodes, [&](std::uint32_t j) { emit(i, j); });
            }
            for (std::size_t b = 0; b < fanout; ++b) {
                const node_index c = nd.first_child + static_cast<node_index>(b);
                if (lay.subtree[c].is_empty()) continue;
                selves.push_back(c);
                for (std::size_t b2 = b + 1; b2 < fanout; ++b2) {
                    const node_index c2 = nd.first_child + static_cast<node_index>(b2);
                    if (collide::closed_boxes_overlap(lay.subtree[c], lay.subtree[c2])) walk.crosses.push_back({c, c2});
                }
            }
        }
        sort_pairs(out);
        return out;
    }
    // Pairs (object of *this, object of other). With another octree of the same type: the two
    // trees descended together (cross(root, root) above, the larger node opened first); with
    // any other container: collide/pairs.hpp's pairs_between (a box query of *this per object
    // of other). Candidates as for self_pairs.
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        if constexpr (!std::is_same_v<Other, octree>) {
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
            pair_descent walk;
            if (collide::closed_boxes_overlap(mine.subtree[root_], theirs.subtree[other.root_]))
                walk.crosses.push_back({root_, other.root_});
            while (!walk.crosses.empty()) {
                const node_pair p = walk.crosses.back();
                walk.crosses.pop_back();
                cross_step(other, mine, theirs, p, walk, emit);
            }
            sort_pairs(out);
            return out;
        }
    }

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
    std::size_t height() const {
        if (root_ == no_node) return 0;
        std::size_t h = 0;
        std::vector<std::pair<node_index, std::size_t>> stack{{root_, 0}};
        while (!stack.empty()) {
            const auto [n, d] = stack.back();
            stack.pop_back();
            h = std::max(h, d);
            if (!nodes_[n].is_leaf())
                for (std::size_t b = 0; b < fanout; ++b) stack.push_back({nodes_[n].first_child + static_cast<node_index>(b), d + 1});
        }
        return h;
    }
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
    std::string check_invariants() const {
        if (root_ == no_node) return slots_.size() == 0 ? "" : "no root but size() > 0";
        std::size_t seen = 0;
        std::vector<node_index> stack{root_};
        while (!stack.empty()) {
            const node_index n = stack.back();
            stack.pop_back();
            const node& nd = nodes_[n];
            for (std::size_t i = 0; i < nd.items.size(); ++i) {
                const slot_index s = nd.items[i];
                if (!slots_.occupied(s) || slots_.meta(s) != n || pos_[s] != i)
                    return "back-link broken at node " + std::to_string(n);
                if (!loose_contains(nd, extent_of(slots_.value(s))))
                    return "object outside its node's loose cell at node " + std::to_string(n);
            }
            seen += nd.items.size();
            if (nd.is_leaf()) continue;
            for (std::size_t b = 0; b < fanout; ++b) {
                const node_index c = nd.first_child + static_cast<node_index>(b);
                const node& cn = nodes_[c];
                if (cn.parent != n) return "parent link broken below node " + std::to_string(n);
                for (std::size_t i = 0; i < D; ++i)
                    if (cn.llo[i] < nd.llo[i] || cn.lhi[i] > nd.lhi[i]) return "loose cells do not nest";
                stack.push_back(c);
            }
        }
        if (seen != slots_.size())
            return "tree holds " + std::to_string(seen) + " objects but size() is " + std::to_string(slots_.size());
        return "";
    }

private:
    // ================= geometry helpers ====================================================
    static coords coords_of(const point_type& p) {
        coords c;
        for (std::size_t i = 0; i < D; ++i) c[i] = p[i];
        return c;
    }
    static extent extent_of(const O& x) {
        extent e;
        for (std::size_t i = 0; i < D; ++i) {
            e.lo[i] = object_lower(x, i);
            e.hi[i] = object_upper(x, i);
            e.c[i] = object_center(x, i);
        }
        return e;
    }
    static void merge_into(extent& a, const extent& b) {
        for (std::size_t i = 0; i < D; ++i) {
            a.lo[i] = std::min(a.lo[i], b.lo[i]);
            a.hi[i] = std::max(a.hi[i], b.hi[i]);
        }
    }
    static bool loose_contains(const node& nd, const extent& e) {
        for (std::size_t i = 0; i < D; ++i)
            if (e.lo[i] < nd.llo[i] || e.hi[i] > nd.lhi[i]) return false;
        return true;
    }
    // Squared distance from q to the loose cell (0 inside); same arithmetic as a box object's.
    static T cell_distance2(const node& nd, const coords& q) {
        T s = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const T d = q[i] < nd.llo[i] ? nd.llo[i] - q[i] : (q[i] > nd.lhi[i] ? q[i] - nd.lhi[i] : T(0));
            s += d * d;
        }
        return s;
    }
    // Sets the cell and the loose cell (the cell scaled by k about its centre).
    static void set_cell(node& nd, const coords& lo, T size) {
        nd.lo = lo;
        nd.size = size;
        const T extra = static_cast<T>((Config::loose_factor - 1.0) / 2.0) * size;
        for (std::size_t i = 0; i < D; ++i) {
            nd.llo[i] = lo[i] - extra;
            nd.lhi[i] = lo[i] + size + extra;
        }
    }
    static T mid(const node& nd, std::size_t i) { return nd.lo[i] + nd.size / 2; }
    static std::size_t child_bits(const node& nd, const coords& c) {
        std::size_t b = 0;
        for (std::size_t i = 0; i < D; ++i)
            if (c[i] >= mid(nd, i)) b |= std::size_t(1) << i;
        return b;
    }

    void swap_contents(octree& o) {
        this->swap_base(o);
        std::swap(pos_, o.pos_);
        std::swap(nodes_, o.nodes_);
        std::swap(free_blocks_, o.free_blocks_);
        std::swap(root_, o.root_);
    }

    // ================= node and item bookkeeping ==========================================
    slot_index allocate(const O& x) {
        const slot_index s = slots_.allocate(x, 0);
        if (pos_.size() <= s) pos_.resize(std::max<std::size_t>(s + 1, slots_.capacity()));
        return s;
    }
    void add_item(node_index n, slot_index s) {
        pos_[s] = static_cast<std::uint32_t>(nodes_[n].items.size());
        nodes_[n].items.push_back(s);
        slots_.set_meta(s, n);
    }
    void remove_item(node_index n, slot_index s) {
        auto& items = nodes_[n].items;
        const std::uint32_t i = pos_[s];
        items[i] = items.back();
        pos_[items[i]] = i;
        items.pop_back();
    }

    node_index new_block() {
        if (!free_blocks_.empty()) {
            const node_index b = free_blocks_.back();
            free_blocks_.pop_back();
            return b;
        }
        if (nodes_.size() + fanout >= static_cast<std::size_t>(no_node)) throw std::length_error("octree: too many nodes");
        const node_index b = static_cast<node_index>(nodes_.size());
        nodes_.resize(nodes_.size() + fanout);
        return b;
    }
    // Creates n's children; their loose cells are clipped to n's so that they nest exactly.
    void make_children(node_index n) {
        const node_index first = new_block();
        const node parent_copy_geometry = geometry_of(nodes_[n]);
        const T half = parent_copy_geometry.size / 2;
        for (std::size_t b = 0; b < fanout; ++b) {
            node& c = nodes_[first + b];
            c.items.clear();
            c.first_child = no_node;
            c.parent = n;
            c.split_retry = 0;
            coords lo = parent_copy_geometry.lo;
            for (std::size_t i = 0; i < D; ++i)
                if ((b >> i) & 1) lo[i] = mid(parent_copy_geometry, i);
            set_cell(c, lo, half);
            for (std::size_t i = 0; i < D; ++i) {
                c.llo[i] = std::max(c.llo[i], parent_copy_geometry.llo[i]);
                c.lhi[i] = std::min(c.lhi[i], parent_copy_geometry.lhi[i]);
            }
        }
        nodes_[n].first_child = first;
    }
    static node geometry_of(const node& nd) {
        node g;
        g.lo = nd.lo;
        g.size = nd.size;
        g.llo = nd.llo;
        g.lhi = nd.lhi;
        return g;
    }

    // Whether a child of nd would still be a meaningful cell.
    bool may_split(const node& nd) const {
        const T half = nd.size / 2;
        const T floor_by_depth = std::ldexp(nodes_[root_].size, -static_cast<int>(Config::max_depth));
        T magnitude = 0;
        for (std::size_t i = 0; i < D; ++i) magnitude = std::max({magnitude, std::abs(nd.lo[i]), std::abs(nd.lo[i] + nd.size)});
        return half >= floor_by_depth && half > 64 * std::numeric_limits<T>::epsilon() * magnitude &&
               half > std::numeric_limits<T>::min();
    }
    // The child of nd that would take the object, or fanout if it stays in nd.
    std::size_t target_of(const node& nd, const extent& e) const {
        const std::size_t b = child_bits(nd, e.c);
        node probe;
        coords lo = nd.lo;
        for (std::size_t i = 0; i < D; ++i)
            if ((b >> i) & 1) lo[i] = mid(nd, i);
        set_cell(probe, lo, nd.size / 2);
        for (std::size_t i = 0; i < D; ++i) {
            probe.llo[i] = std::max(probe.llo[i], nd.llo[i]);
            probe.lhi[i] = std::min(probe.lhi[i], nd.lhi[i]);
        }
        return loose_contains(probe, e) ? b : fanout;
    }

    // Splits leaf n if useful (see the header comment); returns whether it split.
    bool split(node_index n) {
        node& nd = nodes_[n];
        const std::size_t m = nd.items.size();
        if (m <= leaf_capacity || m < nd.split_retry || !may_split(nd)) return false;
        bool moves = false, distinct = false;
        const extent first = extent_of(slots_.value(nd.items[0]));
        std::vector<std::uint8_t> target(m);
        for (std::size_t i = 0; i < m; ++i) {
            const extent e = extent_of(slots_.value(nd.items[i]));
            const std::size_t t = target_of(nd, e);
            target[i] = static_cast<std::uint8_t>(t);
            moves |= t != fanout;
            distinct |= e.c != first.c;
        }
        if (!moves || !distinct) {
            nd.split_retry = 2 * m;  // retry only after doubling: O(1) amortised per insert
            return false;
        }
        make_children(n);
        node& me = nodes_[n];  // make_children may have reallocated nodes_
        std::vector<slot_index> keep;
        for (std::size_t i = 0; i < m; ++i) {
            const slot_index s = me.items[i];
            if (target[i] == fanout) keep.push_back(s);
            else add_item(me.first_child + target[i], s);
        }
        nodes_[n].items = std::move(keep);
        for (std::size_t i = 0; i < nodes_[n].items.size(); ++i) pos_[nodes_[n].items[i]] = static_cast<std::uint32_t>(i);
        nodes_[n].split_retry = 0;
        return true;
    }
    void split_recursive(node_index n) {
        std::vector<node_index> work{n};
        while (!work.empty()) {
            const node_index x = work.back();
            work.pop_back();
            if (!split(x)) continue;
            for (std::size_t b = 0; b < fanout; ++b) {
                const node_index c = nodes_[x].first_child + static_cast<node_index>(b);
                if (nodes_[c].items.size() > leaf_capacity) work.push_back(c);
            }
        }
    }

    // Descends from `start` (whose loose cell contains e) to the deepest node that takes x.
    slot_index place(node_index start, const O& x, const extent& e) {
        const slot_index s = allocate(x);
        node_index n = start;
        while (!nodes_[n].is_leaf()) {
            const std::size_t b = child_bits(nodes_[n], e.c);
            const node_index c = nodes_[n].first_child + static_cast<node_index>(b);
            if (!loose_contains(nodes_[c], e)) break;
            n = c;
        }
        add_item(n, s);
        if (nodes_[n].is_leaf() && nodes_[n].items.size() > leaf_capacity) split_recursive(n);
        return s;
    }

    // Top-down distribution of fresh slots below n (bulk insert).
    void distribute(node_index n, std::vector<slot_index>& batch) {
        if (batch.empty()) return;
        if (nodes_[n].is_leaf()) {
            for (slot_index s : batch) add_item(n, s);
            if (nodes_[n].items.size() > leaf_capacity) split_recursive(n);
            return;
        }
        std::array<std::vector<slot_index>, fanout> parts;
        for (slot_index s : batch) {
            const extent e = extent_of(slots_.value(s));
            const std::size_t b = child_bits(nodes_[n], e.c);
            const node_index c = nodes_[n].first_child + static_cast<node_index>(b);
            if (loose_contains(nodes_[c], e)) parts[b].push_back(s);
            else add_item(n, s);
        }
        batch.clear();
        batch.shrink_to_fit();
        for (std::size_t b = 0; b < fanout; ++b) distribute(nodes_[n].first_child + static_cast<node_index>(b), parts[b]);
    }

    // A node whose children are all leaves and whose subtree fits in one leaf absorbs them.
    bool try_collapse(node_index x) {
        node& nd = nodes_[x];
        if (nd.is_leaf()) return false;
        std::size_t total = nd.items.size();
        for (std::size_t b = 0; b < fanout; ++b) {
            const node& c = nodes_[nd.first_child + b];
            if (!c.is_leaf()) return false;
            total += c.items.size();
        }
        if (total > leaf_capacity) return false;
        const node_index first = nd.first_child;
        for (std::size_t b = 0; b < fanout; ++b) {
            node& c = nodes_[first + b];
            for (slot_index s : c.items) add_item(x, s);
            c.items.clear();
            c.items.shrink_to_fit();
            c.parent = no_node;
        }
        nodes_[x].first_child = no_node;
        nodes_[x].split_retry = 0;
        free_blocks_.push_back(first);
        return true;
    }
    void collapse_from(node_index n) {
        node_index x = nodes_[n].is_leaf() ? nodes_[n].parent : n;
        while (x != no_node && try_collapse(x)) x = nodes_[x].parent;
    }

    // ================= root management =====================================================
    // Makes the root's loose cell contain e (growing or rebuilding); returns true if node
    // indices changed (a rebuild), false if existing nodes kept their indices.
    bool ensure_root_contains(const extent& e) {
        if (root_ == no_node || slots_.size() == 0) {
            rebuild_all(&e);
            return true;
        }
        if (loose_contains(nodes_[root_], e)) return false;
        if (nodes_[root_].is_leaf()) {
            rebuild_all(&e);
            return true;
        }
        for (int levels = 0; !loose_contains(nodes_[root_], e); ++levels) {
            if (levels == 8) {
                rebuild_all(&e);
                return true;
            }
            grow_once(e);
        }
        return false;
    }
    // Re-roots outward: a root of twice the size whose child on the far side from e is the
    // old root (moved into the new child block; the root keeps its index).
    void grow_once(const extent& e) {
        const node old = geometry_of(nodes_[root_]);
        std::size_t bit = 0;
        coords lo = old.lo;
        for (std::size_t i = 0; i < D; ++i)
            if (e.c[i] < mid(old, i)) {  // grow toward negative i: the old root is the upper half
                lo[i] = old.lo[i] - old.size;
                bit |= std::size_t(1) << i;
            }
        const node_index first = new_block();
        node& slot_for_old = nodes_[first + bit];
        slot_for_old = std::move(nodes_[root_]);
        const node_index moved = first + static_cast<node_index>(bit);
        node& nr = nodes_[root_];
        nr = node{};
        set_cell(nr, lo, old.size * 2);
        for (std::size_t i = 0; i < D; ++i) {  // contain the old root's loose cell exactly
            nr.llo[i] = std::min(nr.llo[i], old.llo[i]);
            nr.lhi[i] = std::max(nr.lhi[i], old.lhi[i]);
        }
        nr.first_child = first;
        node& mv = nodes_[moved];
        mv.parent = root_;
        for (slot_index s : mv.items) slots_.set_meta(s, moved);
        if (!mv.is_leaf())
            for (std::size_t b = 0; b < fanout; ++b) nodes_[mv.first_child + b].parent = moved;
        const node geo = geometry_of(nodes_[root_]);
        const T half = geo.size / 2;
        for (std::size_t b = 0; b < fanout; ++b) {
            if (b == bit) continue;
            node& c = nodes_[first + b];
            c = node{};
            c.parent = root_;
            coords clo = geo.lo;
            for (std::size_t i = 0; i < D; ++i)
                if ((b >> i) & 1) clo[i] = mid(geo, i);
            set_cell(c, clo, half);
            for (std::size_t i = 0; i < D; ++i) {
                c.llo[i] = std::max(c.llo[i], geo.llo[i]);
                c.lhi[i] = std::min(c.lhi[i], geo.lhi[i]);
            }
        }
    }

    // Rebuilds the whole tree around the bounding box of every stored object (and `extra`).
    void rebuild_all(const extent* extra = nullptr) {
        std::vector<slot_index> live;
        live.reserve(slots_.size());
        bool any = extra != nullptr;
        extent box{};
        if (extra) box = *extra;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
            live.push_back(s);
            const extent e = extent_of(slots_.value(s));
            if (!any) box = e;
            any = true;
            merge_into(box, e);
        }
        nodes_.clear();
        free_blocks_.clear();
        root_ = no_node;
        if (!any) return;
        T edge = 0, magnitude = 0;
        for (std::size_t i = 0; i < D; ++i) {
            edge = std::max(edge, box.hi[i] - box.lo[i]);
            magnitude = std::max({magnitude, std::abs(box.lo[i]), std::abs(box.hi[i])});
        }
        // Pad so that lo + edge >= hi after rounding; a degenerate box (one point, or all
        // objects identical) gets a cell a little larger than the ulps of its position.
        edge = edge * (1 + 8 * std::numeric_limits<T>::epsilon()) + 64 * std::numeric_limits<T>::epsilon() * magnitude;
        if (!(edge > 0)) edge = std::numeric_limits<T>::min() * T(1024);
        if (!std::isfinite(edge)) edge = std::numeric_limits<T>::max();
        nodes_.emplace_back();
        root_ = 0;
        set_cell(nodes_[root_], box.lo, edge);
        for (std::size_t i = 0; i < D; ++i) {  // contain the box exactly, whatever the rounding
            nodes_[root_].llo[i] = std::min(nodes_[root_].llo[i], box.lo[i]);
            nodes_[root_].lhi[i] = std::max(nodes_[root_].lhi[i], box.hi[i]);
        }
        for (slot_index s : live) add_item(root_, s);
        if (live.size() > leaf_capacity) split_recursive(root_);
    }

    // ================= lookup ==============================================================
    void collect_equal(const O& x, std::vector<slot_index>& out, bool first_only) const {
        if (root_ == no_node || slots_.size() == 0) return;
        const extent e = extent_of(x);
        std::vector<node_index> stack{root_};
        while (!stack.empty()) {
            const node& nd = nodes_[stack.back()];
            stack.pop_back();
            if (!loose_contains(nd, e)) continue;
            for (slot_index s : nd.items)
                if (slots_.value(s) == x) {
                    out.push_back(s);
                    if (first_only) return;
                }
            if (!nd.is_leaf())
                for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
        }
    }

    // ================= collision pairs (the descent of self_pairs / pairs_with) ============
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
    pair_layout pair_layout_of() const {
        std::vector<node_index> order{root_};  // pre-order
        for (std::size_t k = 0; k < order.size(); ++k)
            if (!nodes_[order[k]].is_leaf()) push_children(nodes_[order[k]], order);
        return pair_layout(
            order, nodes_.size(), slots_.size(),
            [this](node_index n, auto&& f) {
                for (slot_index s : nodes_[n].items) f(s);
            },
            [this](node_index n) { return nodes_[n].parent; },
            [this](slot_index s) -> const O& { return slots_.value(s); });
    }
    static void push_children(const node& nd, std::vector<node_index>& stack) {
        for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
    }
    // hit(j) for the layout position j of every object of `tree` stored below the nodes on
    // `stack` (emptied) in a subtree whose box meets `box`; the caller tests the objects.
    template <class Hit>
    static void walk_subtrees(const octree& tree, const pair_layout& lay, const bounds& box,
                              std::vector<node_index>& stack, Hit&& hit) {
        while (!stack.empty()) {
            const node_index n = stack.back();
            stack.pop_back();
            if (!collide::closed_boxes_overlap(box, lay.subtree[n])) continue;
            const node& nd = tree.nodes_[n];
            const std::uint32_t first = lay.first[n], last = first + static_cast<std::uint32_t>(nd.items.size());
            for (std::uint32_t j = first; j < last; ++j) hit(j);
            if (!nd.is_leaf()) push_children(nd, stack);
        }
    }
    // One step of cross(A, B), A = p.a of *this, B = p.b of other: every object below A
    // against every object below B, split so that each pair has one place:
    //   A and B both opened (inner, same size): A's items against B's subtree, B's items
    //     against A's children's subtrees, cross(a, b) for the children;
    //   only A opened (B a leaf or smaller): A's items against B's subtree, cross(a, B);
    //   only B opened: B's items against A's subtree, cross(A, b);
    //   two leaves: their items pairwise.
    // A cross is queued only when its two subtree boxes overlap. emit(position in mine,
    // position in theirs).
    template <class Emit>
    void cross_step(const octree& other, const pair_layout& mine, const pair_layout& theirs, node_pair p,
                    pair_descent& walk, Emit& emit) const {
        const node& na = nodes_[p.a];
        const node& nb = other.nodes_[p.b];
        const std::uint32_t a0 = mine.first[p.a], a1 = a0 + static_cast<std::uint32_t>(na.items.size());
        const std::uint32_t b0 = theirs.first[p.b], b1 = b0 + static_cast<std::uint32_t>(nb.items.size());
        const bool open_a = !na.is_leaf() && (nb.is_leaf() || na.size >= nb.size);
        const bool open_b = !nb.is_leaf() && (na.is_leaf() || nb.size >= na.size);
        if (!open_a && !open_b) {
            for (std::uint32_t i = a0; i < a1; ++i)
                for (std::uint32_t j = b0; j < b1; ++j) emit(i, j);
            return;
        }
        if (open_a) {
            for (std::uint32_t i = a0; i < a1; ++i) {
                walk.nodes.push_back(p.b);
                walk_subtrees(other, theirs, mine.box[i], walk.nodes, [&](std::uint32_t j) { emit(i, j); });
            }
        }
        if (open_b) {
            for (std::uint32_t j = b0; j < b1; ++j) {
                if (open_a)
                    push_children(na, walk.nodes);
                else
                    walk.nodes.push_back(p.a);
                walk_subtrees(*this, mine, theirs.box[j], walk.nodes, [&](std::uint32_t i) { emit(i, j); });
            }
        }
        // The children of an opened side that meet the other side's box (empty subtrees never
        // do), then those pairs: 2 * 2^D tests and the survivors' pairs, not 4^D tests.
        std::array<node_index, fanout> as, bs;
        const std::size_t ma = meeting_children(na, p.a, mine, theirs.subtree[p.b], open_a, as);
        const std::size_t mb = meeting_children(nb, p.b, theirs, mine.subtree[p.a], open_b, bs);
        for (std::size_t i = 0; i < ma; ++i)
            for (std::size_t j = 0; j < mb; ++j)
                if (collide::closed_boxes_overlap(mine.subtree[as[i]], theirs.subtree[bs[j]]))
                    walk.crosses.push_back({as[i], bs[j]});
    }
    // n's children whose subtree box meets `box` if n is opened, else n itself.
    static std::size_t meeting_children(const node& nd, node_index n, const pair_layout& lay, const bounds& box,
                                        bool opened, std::array<node_index, fanout>& out) {
        if (!opened) {
            out[0] = n;
            return 1;
        }
        std::size_t m = 0;
        for (std::size_t b = 0; b < fanout; ++b) {
            const node_index c = nd.first_child + static_cast<node_index>(b);
            if (collide::closed_boxes_overlap(lay.subtree[c], box)) out[m++] = c;
        }
        return m;
    }

    // The range-erase hooks of container_base: a range under a quarter of the tree is erased
    // one by one; a larger one rebuilds the survivors once (O(n depth)).
    void erase_slots(std::span<const slot_index> doomed) {
        for (slot_index s : doomed) erase(make(s));
    }
    void rebuild_survivors() { rebuild_all(); }

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

#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"
static_assert(spatial::spatial_container<spatial::octree<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::octree<spatial::point<float, 2>>>);
static_assert(spatial::spatial_container<spatial::octree<spatial::objects::box<double, 3>>>);
