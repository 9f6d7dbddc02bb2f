#pragma once
// spatial::collide::tree_pair_snapshot<T, D> — what a tree's own broad phase (octree and
// kd_tree self_pairs / pairs_with: the tree descended against itself, Gottschalk, Lin &
// Manocha 1996) reads instead of the tree's nodes and slots:
//  * the objects' slots and bounding boxes copied node by node in pre-order (node n's objects
//    at positions first[n], first[n] + 1, ...), so that a node's boxes are read in sequence
//    rather than through slots scattered over the storage, and each is computed once;
//  * each node's SUBTREE box: the exact bounding box of the objects stored at and below it
//    (min / max of object_lower / object_upper, nothing rounded), or empty (overlapping
//    nothing) when there are none. It lies inside the node's cell or stored extent, often
//    well inside (a loose octree cell is up to k times wider; a kd-tree's extents stay loose
//    after erasure), so pruning node pairs by it tests fewer pairs and never loses one:
//    every object's box lies inside the subtree boxes of its node and its ancestors.
// Built in O(objects + nodes) time and memory per query.
//
// snapshot_self_pairs / snapshot_pairs_between turn a descent over snapshots into the pair
// list both trees return: the descent proposes positions, these keep the pairs whose boxes
// overlap (and, for pair_filter::exact, that the narrow phase confirms) and sort them.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "spatial/collide/box_bounds.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial::collide {

template <class T, std::size_t D>
struct tree_pair_snapshot {
    using bounds = box_bounds<T, D>;
    std::vector<slot_index> slot;      // by position
    std::vector<bounds> box;           // by position: the object's bounding box
    std::vector<std::uint32_t> first;  // by node index: the position of its first object
    std::vector<bounds> subtree;       // by node index

    // preorder: the tree's nodes, each after its parent (the root first); node_count: one
    // more than the largest node index; objects: how many are stored (a capacity hint);
    // for_each_item(n, f): calls f(slot) for every object stored AT node n; parent(n): its
    // parent; value(s): the object in slot s.
    template <class NodeIndex, class ForEachItem, class Parent, class Value>
    tree_pair_snapshot(const std::vector<NodeIndex>& preorder, std::size_t node_count, std::size_t objects,
                       ForEachItem&& for_each_item, Parent&& parent, Value&& value)
        : first(node_count, 0), subtree(node_count, bounds::empty()) {
        slot.reserve(objects);
        box.reserve(objects);
        for (const NodeIndex n : preorder) {
            first[n] = static_cast<std::uint32_t>(slot.size());
            for_each_item(n, [&](slot_index s) {
                const auto& x = value(s);
                bounds b;
                for (std::size_t i = 0; i < D; ++i) b.lo[i] = object_lower(x, i), b.hi[i] = object_upper(x, i);
                slot.push_back(s);
                box.push_back(b);
                subtree[n].grow(b);
            });
        }
        for (std::size_t k = preorder.size(); k-- > 1;)  // children before their parents
            subtree[parent(preorder[k])].grow(subtree[preorder[k]]);
    }
};

// Self pairs of one tree: descend(emit) calls emit(i, j) for positions i != j of `lay`, each
// pair of objects at most once. Returns (lower slot, higher slot), sorted by slots.
template <class O, class T, std::size_t D, class Descend>
std::vector<std::pair<slot_iterator<O>, slot_iterator<O>>> snapshot_self_pairs(const slot_storage<O>& slots,
                                                                                const tree_pair_snapshot<T, D>& lay,
                                                                                pair_filter filter, Descend&& descend) {
    std::vector<std::pair<slot_iterator<O>, slot_iterator<O>>> out;
    auto emit = [&](std::uint32_t i, std::uint32_t j) {
        if (!closed_boxes_overlap(lay.box[i], lay.box[j])) return;
        slot_index s = lay.slot[i], t = lay.slot[j];
        if (filter == pair_filter::exact && !narrow_phase(slots.value(s), slots.value(t))) return;
        if (s > t) std::swap(s, t);
        out.emplace_back(slot_iterator<O>(&slots, s), slot_iterator<O>(&slots, t));
    };
    descend(emit);
    sort_pairs(out);
    return out;
}

// Pairs between two trees of one type: descend(emit) calls emit(i, j) for position i of
// `mine` and j of `theirs`, each pair at most once. Returns (object of mine, object of
// theirs), sorted by slots.
template <class O, class T, std::size_t D, class Descend>
std::vector<std::pair<slot_iterator<O>, slot_iterator<O>>> snapshot_pairs_between(
    const slot_storage<O>& my_slots, const tree_pair_snapshot<T, D>& mine, const slot_storage<O>& their_slots,
    const tree_pair_snapshot<T, D>& theirs, pair_filter filter, Descend&& descend) {
    std::vector<std::pair<slot_iterator<O>, slot_iterator<O>>> out;
    auto emit = [&](std::uint32_t i, std::uint32_t j) {
        if (!closed_boxes_overlap(mine.box[i], theirs.box[j])) return;
        const slot_index s = mine.slot[i], t = theirs.slot[j];
        if (filter == pair_filter::exact && !narrow_phase(my_slots.value(s), their_slots.value(t))) return;
        out.emplace_back(slot_iterator<O>(&my_slots, s), slot_iterator<O>(&their_slots, t));
    };
    descend(emit);
    sort_pairs(out);
    return out;
}

}  // namespace spatial::collide
