#pragma once
// spatial::octree — bulk construction and bulk merging by partitioning ARRAYS of records
// (slot, box) top-down, one counting-sort pass per level, instead of moving slot lists
// between per-node vectors.
//
// The technique is a most-significant-digit radix sort on the objects' implicit Morton keys
// (Warren & Salmon 1993, "A parallel hashed oct-tree N-body algorithm", build the tree by
// sorting particles on their keys; Karras 2012, "Maximizing parallelism in the construction of
// BVHs, octrees, and k-d trees", reads the tree off the sorted order): at each node, the next
// digit of an object's key is the child its centre falls in (child_bits), so scattering the
// node's range by that digit sorts it one digit further and each child's objects become a
// contiguous range. Unlike a sort on integer keys computed up front, the digit is decided at
// each level by the same floating-point comparisons (child_bits, then loose containment in the
// child's loose cell) as a single insertion's descent and a leaf's split, so every object ends
// in exactly the node the one-by-one code would give the same set: answers, heights and the
// split rules (capacity, refused splits of duplicates, max_depth, ulps floor) are unchanged.
//
// Cost: O((n) depth) record moves, sequential in memory (two buffers used in turn), no
// allocation per partition; each node's item list is allocated once, at its final size.
// A split of a node is decided exactly as octree::split decides it (octree_update.hpp).

#include <array>
#include <cstdint>
#include <vector>

#include "spatial/core/reserve_for_push.hpp"
#include "spatial/octree/octree.hpp"

namespace spatial {

namespace detail {
// The counting-sort pass both bulk builds make at a node: records [b, e) of src go to dst grouped
// by group[i] (count[g] of them in group g), the last group (the records that stay in the node)
// first, then groups 0, 1, ... (the children); returns where each group starts in dst. O(e - b).
template <std::size_t Groups, class Record>
std::array<std::size_t, Groups> scatter_grouped(const Record* src, Record* dst, const std::uint8_t* group,
                                                std::size_t b, std::size_t e,
                                                const std::array<std::size_t, Groups>& count) {
    constexpr std::size_t stay = Groups - 1;
    std::array<std::size_t, Groups> start{};
    start[stay] = b;
    std::size_t at = b + count[stay];
    for (std::size_t g = 0; g < stay; ++g) {
        start[g] = at;
        at += count[g];
    }
    std::array<std::size_t, Groups> next = start;
    for (std::size_t i = b; i < e; ++i) dst[next[group[i]]++] = src[i];
    return start;
}
}  // namespace detail

// Starts loading a node's cache lines (its cells and its child and item fields).
template <stored_object O, class Config>
inline void octree<O, Config>::prefetch(const node* nd) {
#if defined(__GNUC__) || defined(__clang__)
    const char* p = reinterpret_cast<const char*>(nd);
    for (std::size_t off = 0; off < sizeof(node); off += 64) __builtin_prefetch(p + off);
#else
    (void)nd;
#endif
}

template <stored_object O, class Config>
inline auto octree<O, Config>::record_of(slot_index s) const -> record {
    const O& x = slots_.value(s);
    record r;
    r.s = s;
    if constexpr (bounded_object<O>) {
        r.e = extent_of(x);
    } else {
        for (std::size_t i = 0; i < D; ++i) r.c[i] = x[i];
    }
    return r;
}

// Builds the subtree of node `root` — a leaf holding no item — over `recs` (slots not in any
// node). Not all-or-nothing: the caller (rebuild_all) sets the old tree aside and puts it back
// if this throws.
template <stored_object O, class Config>
inline void octree<O, Config>::build_subtree(node_index root, std::vector<record>& recs) {
    std::vector<record> other(recs.size());
    std::vector<std::uint8_t> target(recs.size());
    struct task {
        node_index n;
        std::size_t b, e;
        bool in_other;  // the range lies in `other` (else in `recs`)
    };
    std::vector<task> work{{root, 0, recs.size(), false}};
    std::array<node, fanout> probe;  // the children's cells, before the children exist
    while (!work.empty()) {
        const task t = work.back();
        work.pop_back();
        record* src = (t.in_other ? other : recs).data();
        record* dst = (t.in_other ? recs : other).data();
        const std::size_t m = t.e - t.b;
        auto make_leaf = [&](std::size_t retry) {
            nodes_[t.n].items.reserve(m);
            for (std::size_t i = t.b; i < t.e; ++i) add_item(t.n, src[i].s);
            nodes_[t.n].split_retry = retry;
        };
        if (m <= leaf_capacity || !may_split(nodes_[t.n])) {
            make_leaf(0);
            continue;
        }
        // The next digit of every record (fanout: the record stays in this node), and
        // octree::split's two refusals: nothing would move, or all centres coincide.
        {
            const node& nd = nodes_[t.n];
            for (std::size_t b = 0; b < fanout; ++b) set_child_cell(probe[b], nd, b);
        }
        std::array<std::size_t, fanout + 1> count{};
        bool moves = false, distinct = false;
        const coords first = src[t.b].centre();
        for (std::size_t i = t.b; i < t.e; ++i) {
            const extent e = src[i].box();
            const std::size_t b = child_bits(nodes_[t.n], e.c);
            const std::size_t k = loose_contains(probe[b], e) ? b : fanout;
            target[i] = static_cast<std::uint8_t>(k);
            ++count[k];
            moves |= k != fanout;
            distinct |= e.c != first;
        }
        if (!moves || !distinct) {
            make_leaf(2 * m);  // as octree::split: retried only once the count doubles
            continue;
        }
        // Scatter by digit: the records that stay first, then child 0, 1, ...
        const auto start = detail::scatter_grouped(src, dst, target.data(), t.b, t.e, count);
        make_children(t.n);
        const node_index first_child = nodes_[t.n].first_child;
        nodes_[t.n].items.reserve(count[fanout]);
        for (std::size_t i = start[fanout]; i < start[fanout] + count[fanout]; ++i) add_item(t.n, dst[i].s);
        for (std::size_t b = fanout; b-- > 0;)  // child 0 is built first: depth-first node order
            if (count[b] > 0)
                work.push_back({first_child + static_cast<node_index>(b), start[b], start[b] + count[b], !t.in_other});
    }
}

// Places fresh slots (meta `unplaced`, boxes inside the root's loose cell) top-down: each node
// scatters its share of the batch by child once; a leaf takes its share with one reservation
// and then splits as a single insertion would (split_recursive). Each object is routed by
// the tests of a single insertion's descent (octree::place). Strong guarantee with the caller (octree::insert): every
// step that allocates leaves each slot either unplaced or in exactly one node's list, so a
// failure is undone by taking out the placed slots; splits already made stay (each split is
// all-or-nothing and the tree is valid with it).
template <stored_object O, class Config>
inline void octree<O, Config>::merge_batch(std::vector<record>& recs) {
    std::vector<record> other(recs.size());
    std::vector<std::uint8_t> target(recs.size());
    struct task {
        node_index n;
        std::size_t b, e;
        bool in_other;
    };
    std::vector<task> work{{root_, 0, recs.size(), false}};
    while (!work.empty()) {
        const task t = work.back();
        work.pop_back();
        record* src = (t.in_other ? other : recs).data();
        record* dst = (t.in_other ? recs : other).data();
        const std::size_t m = t.e - t.b;
        node_index n = t.n;
        if (m == 1) {  // one record left (the common case near the leaves): a plain descent
            const extent e = src[t.b].box();
            while (!nodes_[n].is_leaf()) {
                const node_index c = nodes_[n].first_child + static_cast<node_index>(child_bits(nodes_[n], e.c));
                if (!loose_contains(nodes_[c], e)) break;
                n = c;
            }
            if (!nodes_[n].is_leaf()) {
                add_item(n, src[t.b].s);
                continue;
            }
        }
        if (nodes_[n].is_leaf()) {
            detail::reserve_for_push(nodes_[n].items, m);
            for (std::size_t i = t.b; i < t.e; ++i) add_item(n, src[i].s);
            if (nodes_[n].items.size() > leaf_capacity) split_recursive(n);
            continue;
        }
        const node_index first_child = nodes_[t.n].first_child;
        // Two passes: the children the records head for, then (those children fetched from
        // memory together, not one dependent miss after another as in a descent) whether
        // each record fits its child's loose cell.
        std::array<bool, fanout> used{};
        for (std::size_t i = t.b; i < t.e; ++i) {
            const std::size_t b = child_bits(nodes_[t.n], src[i].centre());
            target[i] = static_cast<std::uint8_t>(b);
            used[b] = true;
        }
        for (std::size_t b = 0; b < fanout; ++b)
            if (used[b]) prefetch(&nodes_[first_child + b]);
        std::array<std::size_t, fanout + 1> count{};
        for (std::size_t i = t.b; i < t.e; ++i) {
            const std::size_t b = target[i];
            const std::size_t k = loose_contains(nodes_[first_child + b], src[i].box()) ? b : fanout;
            target[i] = static_cast<std::uint8_t>(k);
            ++count[k];
        }
        const auto start = detail::scatter_grouped(src, dst, target.data(), t.b, t.e, count);
        detail::reserve_for_push(nodes_[t.n].items, count[fanout]);
        for (std::size_t i = start[fanout]; i < start[fanout] + count[fanout]; ++i) add_item(t.n, dst[i].s);
        for (std::size_t b = fanout; b-- > 0;)
            if (count[b] > 0)
                work.push_back({first_child + static_cast<node_index>(b), start[b], start[b] + count[b], !t.in_other});
    }
}
}  // namespace spatial
