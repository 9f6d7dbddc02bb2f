#pragma once
// spatial::octree — collision pairs: the tree descended against itself or another octree
// (simultaneous traversal of node pairs, Gottschalk, Lin & Manocha 1996) over a per-query
// snapshot of exact subtree boxes (collide/tree_pair_snapshot.hpp).

#include "spatial/octree/octree.hpp"

namespace spatial {

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
template <stored_object O, class Config>
inline auto octree<O, Config>::self_pairs(pair_filter filter) const -> std::vector<std::pair<iterator, iterator>> {
    if (slots_.size() < 2) return {};
    const pair_layout lay = pair_layout_of();
    return collide::snapshot_self_pairs(slots_, lay, filter, [&](auto& emit) { self_descent(lay, emit); });
}

// The descent of self_pairs: self(root) as defined in self_pairs' comment above, emit(i, j)
// for every candidate pair of layout positions.
template <stored_object O, class Config>
template <class Emit>
inline void octree<O, Config>::self_descent(const pair_layout& lay, Emit& emit) const {
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
}

// Pairs (object of *this, object of other). With another octree of the same type: the two
// trees descended together (cross(root, root) above, the larger node opened first); with
// any other container: collide/pairs.hpp's pairs_between (a box query of *this per object
// of other). Candidates as for self_pairs.
template <stored_object O, class Config>
template <class Other>
inline auto octree<O, Config>::pairs_with(const Other& other, pair_filter filter) const
    -> std::vector<std::pair<iterator, typename Other::iterator>> {
    if constexpr (!std::is_same_v<Other, octree>) {
        return pairs_between(*this, other, filter);
    } else {
        if (slots_.size() == 0 || other.slots_.size() == 0) return {};
        const pair_layout mine = pair_layout_of(), theirs = other.pair_layout_of();
        return collide::snapshot_pairs_between(slots_, mine, other.slots_, theirs, filter, [&](auto& emit) {
            pair_descent walk;
            if (collide::closed_boxes_overlap(mine.subtree[root_], theirs.subtree[other.root_]))
                walk.crosses.push_back({root_, other.root_});
            while (!walk.crosses.empty()) {
                const node_pair p = walk.crosses.back();
                walk.crosses.pop_back();
                cross_step(other, mine, theirs, p, walk, emit);
            }
        });
    }
}

template <stored_object O, class Config>
inline auto octree<O, Config>::pair_layout_of() const -> pair_layout {
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

template <stored_object O, class Config>
inline void octree<O, Config>::push_children(const node& nd, std::vector<node_index>& stack) {
    for (std::size_t b = 0; b < fanout; ++b) stack.push_back(nd.first_child + static_cast<node_index>(b));
}

// hit(j) for the layout position j of every object of `tree` stored below the nodes on
// `stack` (emptied) in a subtree whose box meets `box`; the caller tests the objects.
template <stored_object O, class Config>
template <class Hit>
inline void octree<O, Config>::walk_subtrees(const octree& tree, const pair_layout& lay, const bounds& box,
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
template <stored_object O, class Config>
template <class Emit>
inline void octree<O, Config>::cross_step(const octree& other, const pair_layout& mine, const pair_layout& theirs,
                                          node_pair p, pair_descent& walk, Emit& emit) const {
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
template <stored_object O, class Config>
inline std::size_t octree<O, Config>::meeting_children(const node& nd, node_index n, const pair_layout& lay,
                                                       const bounds& box, bool opened,
                                                       std::array<node_index, fanout>& out) {
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
}  // namespace spatial
