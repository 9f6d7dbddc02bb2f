#pragma once
// spatial::kd_tree — collision pairs of objects with extent: the tree descended against itself
// or against another kd_tree as a BVH (Gottschalk, Lin & Manocha 1996) over a per-query
// snapshot of exact subtree boxes (collide/tree_pair_snapshot.hpp).

#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

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
template <stored_object O, class Config>
inline auto kd_tree<O, Config>::self_pairs(pair_filter filter) const -> std::vector<std::pair<iterator, iterator>> {
    if constexpr (!has_extent) {
        return self_pairs_by_queries(*this, filter);
    } else {
        if (slots_.size() < 2) return {};
        const pair_layout lay = pair_layout_of();
        return collide::snapshot_self_pairs(slots_, lay, filter, [&](auto& emit) {
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
                    const std::uint32_t first = lay.first[p.a], last = first + nd.leaf.count;
                    for (std::uint32_t i = first; i < last; ++i)
                        for (std::uint32_t j = i + 1; j < last; ++j) emit(i, j);
                    continue;
                }
                if (collide::closed_boxes_overlap(lay.subtree[nd.first], lay.subtree[nd.first + 1]))
                    todo.push_back({nd.first, nd.first + 1});
                todo.push_back({nd.first + 1, nd.first + 1});
                todo.push_back({nd.first, nd.first});
            }
        });
    }
}

// Pairs (object of *this, object of other). With another kd_tree of the same type over
// objects with extent: the two trees descended together (cross(root, root) above); with
// any other container, or over points: collide/pairs.hpp's pairs_between (a box query of
// *this per object of other). Candidates as for self_pairs.
template <stored_object O, class Config>
template <class Other>
inline auto kd_tree<O, Config>::pairs_with(const Other& other, pair_filter filter) const
    -> std::vector<std::pair<iterator, typename Other::iterator>> {
    if constexpr (!has_extent || !std::is_same_v<Other, kd_tree>) {
        return pairs_between(*this, other, filter);
    } else {
        if (slots_.size() == 0 || other.slots_.size() == 0) return {};
        const pair_layout mine = pair_layout_of(), theirs = other.pair_layout_of();
        return collide::snapshot_pairs_between(slots_, mine, other.slots_, theirs, filter, [&](auto& emit) {
            std::vector<node_pair> todo;
            if (collide::closed_boxes_overlap(mine.subtree[root], theirs.subtree[root])) todo.push_back({root, root});
            while (!todo.empty()) {
                const node_pair p = todo.back();
                todo.pop_back();
                cross_step(other, mine, theirs, p, todo, emit);
            }
        });
    }
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::pair_layout_of() const -> pair_layout {
    std::vector<node_index> order{root};  // pre-order: a parent before its children
    for (std::size_t k = 0; k < order.size(); ++k)
        if (!nodes_[order[k]].is_leaf)
            order.push_back(nodes_[order[k]].first), order.push_back(nodes_[order[k]].first + 1);
    return pair_layout(
        order, nodes_.size(), slots_.size(),
        [this](node_index n, auto&& f) {
            if (nodes_[n].is_leaf) scan_leaf(nodes_[n], f);
        },
        [this](node_index n) { return links_[n].parent; },
        [this](slot_index s) -> const O& { return slots_.value(s); });
}

template <stored_object O, class Config>
inline auto kd_tree<O, Config>::half_perimeter(const extent& e) -> T {
    T s = 0;
    for (std::size_t i = 0; i < D; ++i) s += e.hi[i] - e.lo[i];
    return s;
}

// One step of cross(A, B), A = p.a of *this, B = p.b of other (their boxes overlap):
// two leaves give their objects pairwise (emit(position in mine, position in theirs));
// otherwise the inner node with the larger box is opened and each child whose box
// meets the other node's is crossed with it — the rule that keeps the two sides of a
// node pair of similar size (Gottschalk, Lin & Manocha 1996).
template <stored_object O, class Config>
template <class Emit>
inline void kd_tree<O, Config>::cross_step(const kd_tree& other, const pair_layout& mine, const pair_layout& theirs,
                                           node_pair p, std::vector<node_pair>& todo, Emit& emit) const {
    const node& na = nodes_[p.a];
    const node& nb = other.nodes_[p.b];
    if (na.is_leaf && nb.is_leaf) {
        // Only objects that meet the other leaf's box can pair across: filtering both
        // sides first costs |A| + |B| tests and often spares most of the |A| x |B|.
        std::array<std::uint32_t, leaf_capacity> as, bs;
        std::size_t ma = 0, mb = 0;
        for (std::uint32_t i = mine.first[p.a], stop = i + na.leaf.count; i < stop; ++i)
            if (collide::closed_boxes_overlap(mine.box[i], theirs.subtree[p.b])) as[ma++] = i;
        for (std::uint32_t j = theirs.first[p.b], stop = j + nb.leaf.count; j < stop; ++j)
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
}  // namespace spatial
