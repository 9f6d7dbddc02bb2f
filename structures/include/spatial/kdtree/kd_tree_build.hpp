#pragma once
// spatial::kd_tree — (re)building: the median build of a subtree over copied-out entries
// (build_node, splits chosen by Config::splitter), the bulk build into an empty tree that lays
// the points out in leaf order, the full rebuild from the live slots, and the scapegoat rule
// (Galperin & Rivest 1993) that picks which subtree to rebuild when a leaf gets too deep.

#include <mutex>
#include <new>

#include "spatial/kdtree/kd_tree.hpp"

namespace spatial {

template <stored_object O, class Config>
inline std::uint16_t kd_tree<O, Config>::depth_limit() const {
    const double n = std::max<double>(static_cast<double>(slots_.size()), leaf_capacity);
    return static_cast<std::uint16_t>(
        std::ceil(std::log(n / leaf_capacity) / std::log(1.0 / Config::balance_alpha)) + 2);
}

// Collect the points below n as build entries and free every node and bucket below n
// (n itself is kept).
template <stored_object O, class Config>
inline void kd_tree<O, Config>::gather(node_index n, std::vector<entry>& es) {
    node& nd = nodes_[n];
    if (nd.is_leaf) {
        const bucket& b = buckets_[nd.first];
        for (std::uint32_t i = 0; i < nd.leaf.count; ++i) es.push_back(make_entry(slots_.value(b.items[i]), b.items[i]));
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
template <stored_object O, class Config>
inline std::uint16_t kd_tree<O, Config>::rebuild_subtree(node_index n, std::vector<entry>& es) {
    coords lo, hi;
    // n's cell: it is intact in n's ancestors (restores) but its own bucket may be
    // freed already, so recompute from the parent chain.
    cell_from_ancestors(n, lo, hi);
    ++maintenance_.subtree_rebuilds;
    return build_node(n, es.data(), es.size(), lo, hi, nodes_[n].depth, false, 0).deepest;
}

// The cell of n from the root down (O(depth)), valid even when n's subtree is gone.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::cell_from_ancestors(node_index n, coords& lo, coords& hi) const {
    lo.fill(-std::numeric_limits<T>::infinity());
    hi.fill(std::numeric_limits<T>::infinity());
    std::vector<node_index> path;
    for (node_index c = n; c != root; c = links_[c].parent) path.push_back(c);
    for (auto it = path.rbegin(); it != path.rend(); ++it) {
        const node_index p = links_[*it].parent;
        const unsigned d = nodes_[p].dim;
        if (*it == nodes_[p].first) hi[d] = nodes_[p].split;
        else lo[d] = nodes_[p].split;
    }
}

// Build over entries e[0, n) into node index `at` (already allocated) with cell [lo, hi].
// fresh: slot ids are positions (base + index into e), used by build_fresh to lay points
// out in leaf order. Returns the deepest leaf depth and the keys' bounding box, from which
// each inner node takes its children's ranges along its cut (O(D) per node on top of the
// leaves' O(n) pass, so the ranges cost no extra pass per level).
// `split` gives each inner node's split: the splitter's, or the planned one (the parallel build).
template <stored_object O, class Config>
template <class SplitSource>
inline auto kd_tree<O, Config>::build_node(node_index at, entry* e, std::size_t n, const coords& lo,
                                           const coords& hi, std::uint16_t depth, bool fresh, std::size_t base,
                                           SplitSource& split) -> built_subtree {
    nodes_[at].depth = depth;
    if (n <= leaf_capacity) {
        const node_index b = new_bucket(at, lo, hi);
        node& L = nodes_[at];
        L.is_leaf = 1;
        L.first = b;
        L.leaf.count = static_cast<std::uint32_t>(n);
        built_subtree out{depth, extent::empty()};
        for (std::size_t i = 0; i < n; ++i) {
            const slot_index s = fresh ? static_cast<slot_index>(base + i) : e[i].slot;
            buckets_[b].items[i] = s;
            if (fresh) e[i].bucket = b;  // build_fresh sets the slot metadata afterwards
            else slots_.set_meta(s, b);
            out.keys.grow(e[i].c);
        }
        L.leaf.run = run_of(buckets_[b].items.data(), L.leaf.count);
        if constexpr (has_extent) {
            extent ex = extent::empty();
            for (std::size_t i = 0; i < n; ++i) ex.grow(e[i].bounds);
            extents_[at] = ex;
        }
        ++leaves_;
        return out;
    }
    const split_choice<T> sc = split(e, n);
    const node_index first = new_pair();
    {
        node& nd = nodes_[at];
        nd.is_leaf = 0;
        nd.dim = static_cast<std::uint8_t>(sc.dim);
        nd.split = sc.value;
        nd.first = first;
    }
    nodes_[first] = node{};
    nodes_[first + 1] = node{};
    links_[first] = {hi[sc.dim], at};
    links_[first + 1] = {lo[sc.dim], at};
    coords lhi = hi, rlo = lo;
    lhi[sc.dim] = sc.value;
    rlo[sc.dim] = sc.value;
    const built_subtree l = build_node(first, e, sc.left, lo, lhi, static_cast<std::uint16_t>(depth + 1), fresh, base, split);
    const built_subtree r = build_node(first + 1, e + sc.left, n - sc.left, rlo, hi,
                                       static_cast<std::uint16_t>(depth + 1), fresh, base + sc.left, split);
    using detail_rounding::round_down, detail_rounding::round_up;
    nodes_[at].ranges = {round_down<float>(l.keys.lo[sc.dim]), round_up<float>(l.keys.hi[sc.dim]),
                         round_down<float>(r.keys.lo[sc.dim]), round_up<float>(r.keys.hi[sc.dim])};
    if constexpr (has_extent) {
        extents_[at] = extents_[first];
        extents_[at].grow(extents_[first + 1]);
    }
    built_subtree out{std::max(l.deepest, r.deepest), l.keys};
    out.keys.grow(r.keys);
    return out;
}

// ---- the parallel build's plan (see insert(first, last, par)) --------------------------
// One inner node of the plan: its entries [begin, begin + count) and the split made there.
template <stored_object O, class Config>
struct kd_tree<O, Config>::split_record {
    std::size_t begin, count;
    split_choice<T> split;
};
// The plan replayed in preorder, the order in which build_node asks for splits; each record
// is checked against the range build_node asks about (a plan out of step is a bug).
template <stored_object O, class Config>
struct kd_tree<O, Config>::planned_splits {
    const entry* base;
    typename std::vector<split_record>::const_iterator next, end;
    split_choice<T> operator()(entry* e, std::size_t n) {
        if (next == end || next->begin != static_cast<std::size_t>(e - base) || next->count != n)
            throw std::logic_error("kd_tree: the parallel build's plan is out of step with the layout");
        return (next++)->split;
    }
};
// The splits of entries [begin, begin + count), made in place, appended to `plan` in chunks
// (core/preorder_plan.hpp). Ranges of at least parallel_grain on both sides of a split are
// planned concurrently (a skewed split plans its small side on this thread and iterates on the
// large one, so the recursion stays shallow).
template <stored_object O, class Config>
inline void kd_tree<O, Config>::plan_splits(entry* es, std::size_t begin, std::size_t count, split_plan& plan) {
    const auto plan_sequentially = [&](std::size_t b0, std::size_t m0) {
        std::vector<split_record> local;
        std::vector<std::pair<std::size_t, std::size_t>> todo{{b0, m0}};
        while (!todo.empty()) {
            const auto [b, m] = todo.back();
            todo.pop_back();
            if (m <= leaf_capacity) continue;
            const split_choice<T> sc = split_by_config{}(es + b, m);
            local.push_back({b, m, sc});
            todo.push_back({b + sc.left, m - sc.left});
            todo.push_back({b, sc.left});
        }
        plan.append(std::move(local));
    };
    for (;;) {
        if (count <= parallel_grain) {
            plan_sequentially(begin, count);
            return;
        }
        const split_choice<T> sc = split_by_config{}(es + begin, count);
        plan.append({split_record{begin, count, sc}});
        const std::size_t left = sc.left, right = count - sc.left;
        if (left >= parallel_grain && right >= parallel_grain) {
            detail::parallel_invoke([&] { plan_splits(es, begin, left, plan); },
                                    [&] { plan_splits(es, begin + left, right, plan); });
            return;
        }
        if (left < right) {
            plan_sequentially(begin, left);
            begin += left;
            count = right;
        } else {
            plan_sequentially(begin + left, right);
            count = left;
        }
    }
}

// Bulk build into an empty tree. Slots are assigned in leaf order, so each leaf's points
// are contiguous in memory (sequential access when a query scans a leaf).
// Strong guarantee: the empty tree is moved aside and put back if the build cannot allocate;
// the slots are assigned last, in one step that either happens whole or not at all.
template <stored_object O, class Config>
template <class RandomIt>
inline void kd_tree<O, Config>::build_fresh(RandomIt batch, std::size_t count, bool parallel) {
    tree_backup backup = backup_all();
    try {
        build_fresh_in_place(batch, count, parallel);
    } catch (const std::bad_alloc&) {
        restore(backup);
        throw;
    }
}
// parallel: the entries are made, the splits planned, the points gathered in leaf order and
// their slots' bucket words written on every core; the nodes are laid out on this thread
// (O(m) for m points, about 2m / leaf_capacity nodes), from the plan, by the same build_node.
template <stored_object O, class Config>
template <class RandomIt>
inline void kd_tree<O, Config>::build_fresh_in_place(RandomIt batch, std::size_t count, bool parallel) {
    reset_to_empty();
    free_buckets_.push_back(nodes_[root].first);
    leaves_ = 0;
    std::vector<entry> es(count);
    constexpr std::size_t chunk = std::size_t(1) << 14;
    if (parallel) {
        // Bounds are a min / max over all keys: the same whatever the chunks' order.
        std::mutex bounds_mutex;
        detail::parallel_chunks(count, chunk, [&](std::size_t b, std::size_t e) {
            coords lo, hi;
            lo.fill(std::numeric_limits<T>::infinity());
            hi.fill(-std::numeric_limits<T>::infinity());
            for (std::size_t i = b; i < e; ++i) {
                es[i] = make_entry(batch[i], static_cast<slot_index>(i));
                for (std::size_t d = 0; d < D; ++d) {
                    lo[d] = std::min(lo[d], es[i].c[d]);
                    hi[d] = std::max(hi[d], es[i].c[d]);
                }
            }
            const std::lock_guard<std::mutex> lock(bounds_mutex);
            grow_bounds(lo);
            grow_bounds(hi);
        });
    } else {
        for (std::size_t i = 0; i < count; ++i) {
            es[i] = make_entry(batch[i], static_cast<slot_index>(i));
            grow_bounds(es[i].c);
        }
    }
    coords lo, hi;
    lo.fill(-std::numeric_limits<T>::infinity());
    hi.fill(std::numeric_limits<T>::infinity());
    if (parallel) {
        split_plan chunks;
        plan_splits(es.data(), 0, count, chunks);
        chunks.sort_to_preorder();
        std::vector<split_record> plan;
        for (const auto& c : chunks.chunks) plan.insert(plan.end(), c.begin(), c.end());
        // Exactly what the layout allocates: a pair of nodes per split, a bucket per leaf
        // (the sequential build's shrink_to_fit below then has nothing to give back).
        nodes_.reserve(1 + 2 * plan.size());
        links_.reserve(1 + 2 * plan.size());
        if constexpr (has_extent) extents_.reserve(1 + 2 * plan.size());
        buckets_.reserve(1 + plan.size());
        planned_splits split{es.data(), plan.cbegin(), plan.cend()};
        build_node(root, es.data(), es.size(), lo, hi, 0, true, 0, split);
        if (split.next != split.end) throw std::logic_error("kd_tree: the parallel build left planned splits unused");
    } else {
        build_node(root, es.data(), es.size(), lo, hi, 0, true, 0);
    }
    // After partitioning, position i of `es` is the i-th point in leaf order.
    typename slot_storage<O>::value_vector ordered;  // resize leaves trivial objects unwritten
    if constexpr (std::is_default_constructible_v<O>) {
        if (parallel) {
            ordered.resize(count);
            detail::parallel_chunks(count, chunk, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) ordered[i] = batch[es[i].slot];
            });
        }
    }
    if (ordered.size() != count) {
        ordered.reserve(count);
        for (const entry& e : es) ordered.push_back(batch[e.slot]);
    }
    slots_.assign(std::move(ordered), 0);
    if (parallel) {
        detail::parallel_chunks(count, chunk, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) slots_.set_meta(static_cast<slot_index>(i), es[i].bucket);
        });
    } else {
        for (std::size_t i = 0; i < es.size(); ++i) slots_.set_meta(static_cast<slot_index>(i), es[i].bucket);
    }
    size_at_rebuild_ = slots_.size();
    ++maintenance_.full_rebuilds;
    nodes_.shrink_to_fit();
    links_.shrink_to_fit();
    if constexpr (has_extent) extents_.shrink_to_fit();  // grown with nodes_ (new_pair)
    buckets_.shrink_to_fit();
}

// Rebuild everything from the live slots (slots keep their ids). Strong guarantee: the old
// tree is moved aside and put back if the new one cannot be built.
template <stored_object O, class Config>
inline void kd_tree<O, Config>::rebuild_all() {
    tree_backup backup = backup_all();
    try {
        rebuild_all_in_place();
    } catch (const std::bad_alloc&) {
        restore(backup);
        throw;
    }
}
template <stored_object O, class Config>
inline void kd_tree<O, Config>::rebuild_all_in_place() {
    std::vector<entry> es;
    es.reserve(slots_.size());
    bounds_lo_.fill(std::numeric_limits<T>::infinity());
    bounds_hi_.fill(-std::numeric_limits<T>::infinity());
    for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
        es.push_back(make_entry(slots_.value(s), s));
        grow_bounds(es.back().c);
    }
    nodes_.assign(1, node{});
    links_.assign(1, node_link{});
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
template <stored_object O, class Config>
inline void kd_tree<O, Config>::rebalance_from(node_index n) {
    // n was just rebuilt; find its deepest leaf's ancestor chain from n upward.
    std::size_t size_child = subtree_size(n);
    node_index child = n;
    while (child != root) {
        const node_index p = links_[child].parent;
        const node_index first = nodes_[p].first;
        const node_index sib = child == first ? first + 1 : first;
        const std::size_t size_p = size_child + subtree_size(sib);
        const std::size_t heavy = std::max(size_child, size_p - size_child);
        if (static_cast<double>(heavy) > Config::balance_alpha * static_cast<double>(size_p) &&
            size_p > 2 * leaf_capacity) {
            std::vector<entry> es;
            es.reserve(size_p);
            subtree_backup backup = backup_subtree(p, size_p);  // strong guarantee, as for a leaf split
            try {
                gather(p, es);
                rebuild_subtree(p, es);
            } catch (const std::bad_alloc&) {
                restore(backup);
                throw;
            }
            return;
        }
        size_child = size_p;
        child = p;
    }
    rebuild_all();
}

template <stored_object O, class Config>
inline std::size_t kd_tree<O, Config>::subtree_size(node_index n) const {
    if (nodes_[n].is_leaf) return nodes_[n].leaf.count;
    return subtree_size(nodes_[n].first) + subtree_size(nodes_[n].first + 1);
}
}  // namespace spatial
