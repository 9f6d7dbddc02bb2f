#pragma once
// spatial::bvh — full builds: rebuild(), rebuild(par) and the subtree builder that insertion
// uses to split a full leaf. The split decisions come from bvh/builders.hpp (object-median
// split along the widest centroid axis, or binned SAH, Wald 2007), which sees only the items'
// boxes and centres; here they become nodes. O(n log n) for balanced splits (fits included,
// except convex_hull whose Quickhull makes it O(n log^2 n)).
//
// Every node a build creates is written by the node writer below (write_leaf, write_inner):
// the sequential builder (build_subtree, used by rebuild() and by insertion) and the parallel
// one (rebuild(par), which replays a plan of split records in preorder) differ only in when
// they fit volumes, never in how a leaf or an inner node is laid out, so both emit the same
// nodes in the same order.

#include <new>

#include "spatial/bvh/bvh.hpp"
#include "spatial/core/capacity_headroom.hpp"

namespace spatial {

// ================= the node writer =======================================================
// Makes `at` a leaf holding the slots of items [first, first + m) (m <= leaf_size) in a
// newly allocated block; each slot's meta word points back at the leaf. Volume and box are
// left to the caller (make_leaf fits them; rebuild(par) stores the planned ones).
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::write_leaf(node_index at, const item* first, std::size_t m) {
    open_leaf(at, m);
    fill_leaf(at, first);
}
// write_leaf in two steps: the node and its block (allocations), then the block's slots and
// their meta words (no allocation; rebuild(par) fills the leaves on every core once every
// node and block is allocated: each leaf writes its own block and its own slots' words).
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::open_leaf(node_index at, std::size_t m) {
    open_leaf_on(at, alloc_block(), m);
}
// open_leaf with its block already allocated (rebuild(par) numbers the blocks in advance).
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::open_leaf_on(node_index at, node_index block, std::size_t m) {
    node& nd = nodes_[at];
    nd.leaf = true;
    nd.first = block;
    nd.count = static_cast<std::uint32_t>(m);
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::fill_leaf(node_index at, const item* first) {
    const node& nd = nodes_[at];
    slot_index* b = block(nd.first);
    for (std::size_t i = 0; i < nd.count; ++i) {
        b[i] = first[i].slot;
        slots_.set_meta(first[i].slot, at);
    }
}
// Makes `at` an inner node over a newly allocated child pair (c, c + 1) whose parent links
// point at it; returns c. Volume and box are left to the caller.
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::write_inner(node_index at) -> node_index {
    const node_index c = alloc_pair();
    write_inner_over(at, c);
    return c;
}
// write_inner with the pair already allocated (rebuild(par) numbers the pairs in advance).
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::write_inner_over(node_index at, node_index c) {
    node& nd = nodes_[at];
    nd.leaf = false;
    nd.first = c;
    nd.count = 0;
    nodes_[c].parent = at;
    nodes_[c + 1].parent = at;
}

// ================= building ============================================================
// Makes `at` a leaf holding items [first, first + m) (m <= leaf_size) and fits it.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::make_leaf(node_index at, const item* first, std::size_t m) {
    write_leaf(at, first, m);
    refit_node(at);
}
// Builds the subtree rooted at `at` over the items (in place), iteratively (an explicit
// task stack: a skewed SAH split sequence cannot overflow the call stack). Each inner
// node's volume is fitted to ALL hull points below it (tighter than merging).
// Each task carries its items' bounds, computed by its parent's split (builders.hpp,
// range_bounds); a box-volume node takes its box from them instead of reading its items (or,
// for a leaf, its objects) again.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::build_subtree(node_index at, item* first, std::size_t m) {
    struct task {
        node_index n;
        std::size_t begin, count;
        item_bounds bounds;
    };
    std::vector<task> tasks{{at, 0, m, item_bounds::of(first, m)}};
    std::array<item_bounds, 2> parts;
    while (!tasks.empty()) {
        const task t = tasks.back();
        tasks.pop_back();
        item* f = first + t.begin;
        const std::size_t left = choose_split(f, t.count, t.bounds, parts);
        if (left == 0) {
            if constexpr (volume_is_box) {
                write_leaf(t.n, f, t.count);
                nodes_[t.n].volume = box_from(t.bounds);
                if constexpr (wide_rays) wide_.reset();
            } else {
                make_leaf(t.n, f, t.count);
            }
            continue;
        }
        const node_index c = write_inner(t.n);
        if constexpr (volume_is_box) nodes_[t.n].volume = box_from(t.bounds);
        else fit_inner_from_items(t.n, f, t.count);
        tasks.push_back({c + 1, t.begin + left, t.count - left, parts[1]});
        tasks.push_back({c, t.begin, left, parts[0]});
    }
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::box_from(const item_bounds& b) -> box_type {
    box_type box;
    box.lo.coords = b.box.lo;
    box.hi.coords = b.box.hi;
    return box;
}
template <stored_object O, class BV, class Config>
inline std::size_t bvh<O, BV, Config>::choose_split(item* f, std::size_t m, const item_bounds& bounds,
                                                    std::array<item_bounds, 2>& parts, bool on_every_core) const {
    if constexpr (Config::builder == bvh_build_method::median_split) {
        if (m <= leaf_size) return 0;
        const std::size_t left = bvh_detail::median_split(f, m, bounds.centres);
        bvh_detail::bounds_of_parts(f, m, left, parts);
        return left;
    } else {
        return bvh_detail::binned_sah_split<Config::sah_bins>(
            f, m, leaf_size, bvh_detail::sah_costs{Config::traversal_cost, Config::intersection_cost, sah_block}, bounds,
            parts, on_every_core);
    }
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::fit_inner_from_items(node_index n, const item* f, std::size_t m) {
    box_type b;
    fit_items(f, m, scratch_, b, nodes_[n].volume);
    if constexpr (!volume_is_box) nodes_[n].own_box = b;
}
// The box of items [f, f + m) and the volume fitted to all their hull points (in item
// order), with a caller-owned scratch buffer (so concurrent planners can fit). For
// BV = aabb the volume is the box.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::fit_items(const item* f, std::size_t m, std::vector<bv_point>& scratch, box_type& box,
                                            BV& volume) const {
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
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::add_hull_points(const O& v) {
    object_hull_points(v, [&](const auto& hp) { scratch_.push_back(to_bv(hp)); });
}

// ---- full builds -------------------------------------------------------------------------
// Strong guarantee (both builds): the old tree is moved aside and put back if the new one
// cannot be built (bvh_backup.hpp).
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::rebuild() {
    tree_backup backup = backup_all();
    try {
        rebuild_in_place();
    } catch (const std::bad_alloc&) {
        restore(backup);
        throw;
    }
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::rebuild(parallel_policy) {
    tree_backup backup = backup_all();
    try {
        rebuild_in_place(par);
    } catch (const std::bad_alloc&) {
        restore(backup);
        throw;
    }
}
// After an erasure the rebuild only restores quality: without memory for it the erase still
// succeeds and a later update retries.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::rebuild_if_possible() noexcept {
    try {
        rebuild();
    } catch (const std::bad_alloc&) {
    }
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::rebuild_in_place() {
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
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::rebuild_in_place(parallel_policy) {
    if (slots_.size() < 2 * parallel_grain) {
        rebuild_in_place();
        return;
    }
    clear_nodes();
    // The items in slot order, as the sequential builder lists them. Without free slots (a
    // build into an empty tree) slot i is item i, and no list of the occupied slots is needed.
    const std::size_t m = slots_.size();
    const bool dense = m == slots_.capacity();
    std::vector<slot_index> occupied;
    if (!dense) {
        occupied.reserve(m);
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            occupied.push_back(s);
    }
    // Default-initialised (build_item is trivial): a std::vector would zero all m items on this
    // thread first, and take every page fault of the fresh array there; here the threads that
    // fill the items touch their pages (on the 1e6 sphere the listing took 42 ms, now 25).
    // The root's bounds are taken in the same pass, per chunk of items, merged in item order
    // (as item_bounds::of would add them; a pass of its own took 4 ms on one thread).
    const std::unique_ptr<item[]> its(new item[m]);
    constexpr std::size_t chunk = 16384;
    std::vector<item_bounds> chunk_bounds((m + chunk - 1) / chunk);
    detail::parallel_chunks(chunk_bounds.size(), 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            item_bounds local;
            for (std::size_t i = k * chunk; i < std::min(m, (k + 1) * chunk); ++i) {
                const slot_index s = dense ? static_cast<slot_index>(i) : occupied[i];
                its[i] = item_of(slots_.value(s), s);
                local.add(its[i]);
            }
            chunk_bounds[k] = local;
        }
    });
    item_bounds root_bounds;
    for (const item_bounds& b : chunk_bounds) root_bounds.merge(b);
    nodes_.push_back(node{});

    split_plan plan;
    plan_splits(its.get(), 0, m, root_bounds, plan);
    plan.sort_to_preorder();
    const double quality_now = replay(plan, its.get());
    if constexpr (wide_rays) wide_.reset();
    finish_build(quality_now);
}
// Makes the planned nodes, numbered as the sequential builder numbers them, on every core.
// Into an empty node array, the sequential builder's allocations are in preorder: the k-th
// inner node of the preorder gets the child pair (1 + 2k, 2 + 2k), the k-th leaf block k. So
// once each chunk of the plan (a whole subtree, or a single split above them) knows how many
// inner nodes and leaves come before it, and which node its first record is, the chunks are
// written concurrently, each with its own stack: the same nodes, blocks and slot back-links
// as the sequential replay, which took 10 ms of the 1e6 sphere's build on one thread.
// Returns the new tree's quality(): the records are in the preorder quality() sums in, so each
// node's box area is written at its record's position as the node is written, and the areas
// are then added up in that order (the same sum, bit for bit; the preorder walk of quality()
// took 4-5 ms on one thread).
template <stored_object O, class BV, class Config>
inline double bvh<O, BV, Config>::replay(split_plan& plan, const item* its) {
    struct chunk_start {
        std::size_t inner = 0, leaves = 0;  // counts within the chunk, then ranks of its first
        std::size_t position = 0;           // its first record's position in the preorder
        node_index node = 0;                // the node of its first record
    };
    const std::size_t chunks = plan.chunks.size();
    std::vector<chunk_start> starts(chunks);
    detail::parallel_chunks(chunks, 16, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k)
            for (const split_record& r : plan.chunks[k]) ++(r.left == 0 ? starts[k].leaves : starts[k].inner);
    });
    // Ranks by prefix sums; the first record's node by the sequential replay's stack, run over
    // the chunks (a whole subtree pushes and pops its own nodes; a single split pushes its pair).
    std::size_t inner = 0, leaves = 0, records = 0;
    std::vector<node_index> pending{root};
    for (std::size_t k = 0; k < chunks; ++k) {
        chunk_start& c = starts[k];
        c.position = records;
        records += plan.chunks[k].size();
        c.node = pending.back();
        pending.pop_back();
        const auto& chunk = plan.chunks[k];
        if (chunk.size() == 1 && chunk.front().left != 0) {
            const auto pair = static_cast<node_index>(1 + 2 * inner);
            pending.push_back(pair + 1);
            pending.push_back(pair);
        }
        const std::size_t in_chunk_inner = c.inner, in_chunk_leaves = c.leaves;
        c.inner = inner, c.leaves = leaves;
        inner += in_chunk_inner, leaves += in_chunk_leaves;
    }
    // Allocated as the sequential replay would grow them, with the build's headroom reserved
    // at once (finish_build would otherwise copy both arrays into it).
    const std::size_t nodes = 1 + 2 * inner;
    nodes_.reserve(capacity_after_build(nodes));
    items_.reserve(capacity_after_build(leaves * leaf_size));
    nodes_.resize(nodes);
    items_.resize(leaves * leaf_size, no_slot);
    const std::unique_ptr<double[]> areas(new double[records]);
    detail::parallel_chunks(chunks, 1, [&](std::size_t b, std::size_t e) {
        std::vector<node_index> stack;
        for (std::size_t k = b; k < e; ++k) {
            std::size_t next_inner = starts[k].inner, next_leaf = starts[k].leaves, position = starts[k].position;
            stack.assign(1, starts[k].node);
            for (split_record& r : plan.chunks[k]) {
                const node_index at = stack.back();
                stack.pop_back();
                nodes_[at].volume = std::move(r.volume);
                if constexpr (!volume_is_box) nodes_[at].own_box = r.box;
                areas[position++] = static_cast<double>(box_of(nodes_[at]).surface_area());
                if (r.left == 0) {
                    open_leaf_on(at, static_cast<node_index>(next_leaf++), r.count);
                    fill_leaf(at, its + r.begin);
                    continue;
                }
                const auto c = static_cast<node_index>(1 + 2 * next_inner++);
                write_inner_over(at, c);
                stack.push_back(c + 1);  // (a single split's pair is left on the stack: later chunks)
                stack.push_back(c);
            }
        }
    });
    double sum = 0;
    for (std::size_t i = 0; i < records; ++i) sum += areas[i];
    return quality_from(sum);
}
// The bookkeeping after a full build (rebuild() and rebuild(par)); quality_now: the new tree's
// quality() when the build has it already.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::finish_build(std::optional<double> quality_now) {
    // The sequential builder grows the arrays by doubling (up to half of them spare: on 1e5
    // triangles 28 % of the nodes, 9 bytes a triangle of memory_bytes()), the parallel one
    // reserves them exactly. Both leave an eighth spare (core/capacity_headroom.hpp): an exact
    // fit, as from 2026-11-27 to 11-28, made the first insertion after a build copy the whole
    // node array, a batch of n/10 insertions into 1e6 points half again as slow. Without
    // Config::build_headroom the arrays are fitted exactly (best-effort, as the headroom is).
    detail::set_capacity(nodes_, capacity_after_build(nodes_.size()));
    detail::set_capacity(items_, capacity_after_build(items_.size()));
    size_at_build_ = slots_.size();
    updates_since_build_ = 0;
    stale_ = false;
    ++full_rebuilds_;
    quality_at_build_ = quality_now ? *quality_now : quality();
}

// After a bulk insert into an empty tree (bulk_insert): the slots renumbered in leaf order,
// the depth-first, left-before-right walk of the leaves, as kd_tree's bulk build stores its
// points (docs/contract.md, iteration order). The objects of any subtree are then
// consecutive slots: a leaf's objects are read sequentially, and the wide ray layout tests
// them where they are instead of copying them (wide_ray_layout.hpp, leaves in place). No
// iterator into the new objects exists yet, so none is invalidated; each slot keeps its leaf
// (the meta word moves with it) and the leaf blocks are renumbered. O(n). Without memory for
// the new arrays (or if an object's copy throws) the slots keep their insertion order:
// nothing else depends on the order.
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::store_in_leaf_order(bool parallel) noexcept {
    std::vector<node_index> order;
    try {
        preorder(order);
        std::vector<slot_index> old_of_new;
        old_of_new.reserve(slots_.capacity());
        for (const node_index n : order)
            if (nodes_[n].leaf) old_of_new.insert(old_of_new.end(), block(nodes_[n].first), block(nodes_[n].first) + nodes_[n].count);
        if (old_of_new.size() != slots_.capacity()) return;  // a free slot: not a build into an empty tree
        slots_.permute(old_of_new, parallel);
    } catch (...) {  // std::bad_alloc, or an object's copy: nothing was changed
        return;
    }
    slot_index next = 0;
    for (const node_index n : order)
        if (nodes_[n].leaf)
            for (slot_index* b = block(nodes_[n].first), *e = b + nodes_[n].count; b != e; ++b) *b = next++;
    if constexpr (wide_rays) wide_.reset();
}

// ---- the parallel builder's plan (see rebuild(parallel_policy)) -----------------------
// A node of the plan: its items, its split, and its box and volume fitted when the
// sequential builder fits them (right after the node's own split: order-dependent fits
// such as Ritter's sphere then see the items in the same order).
template <stored_object O, class BV, class Config>
struct bvh<O, BV, Config>::split_record {
    std::uint32_t begin, count, left;  // items [begin, begin + count) (< 2^32); left == 0: a leaf
    [[no_unique_address]] std::conditional_t<volume_is_box, no_box, box_type> box;  // the volume's box
    BV volume;
};
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::make_record(const item* base, std::size_t b, std::size_t m, std::size_t left,
                                            const item_bounds& bounds, std::vector<bv_point>& scratch) const
    -> split_record {
    split_record r{static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(m), static_cast<std::uint32_t>(left), {}, BV{}};
    if constexpr (volume_is_box) r.volume = box_from(bounds);  // the box the sequential builder gives it
    else fit_items(base + b, m, scratch, r.box, r.volume);
    return r;
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::plan_splits(item* base, std::size_t b, std::size_t m, item_bounds bounds,
                                            split_plan& plan) const {
    // The builder's decisions for a range, sequentially (an explicit stack).
    std::vector<bv_point> scratch;
    auto plan_sequentially = [&](std::size_t b0, std::size_t m0, const item_bounds& bounds0) {
        std::array<item_bounds, 2> parts;
        struct range {
            std::size_t begin, count;
            item_bounds bounds;
        };
        std::vector<split_record> local;
        std::vector<range> todo{{b0, m0, bounds0}};
        while (!todo.empty()) {
            const range t = todo.back();
            todo.pop_back();
            const std::size_t left = choose_split(base + t.begin, t.count, t.bounds, parts);
            local.push_back(make_record(base, t.begin, t.count, left, t.bounds, scratch));
            if (left == 0) continue;
            todo.push_back({t.begin + left, t.count - left, parts[1]});
            todo.push_back({t.begin, left, parts[0]});
        }
        plan.append(std::move(local));
    };
    for (;;) {
        if (m <= parallel_grain) {
            plan_sequentially(b, m, bounds);
            return;
        }
        std::array<item_bounds, 2> parts;
        const std::size_t left = choose_split(base + b, m, bounds, parts, true);
        std::vector<split_record> single;
        single.push_back(make_record(base, b, m, left, bounds, scratch));
        plan.append(std::move(single));
        if (left == 0) return;
        if (left >= parallel_grain && m - left >= parallel_grain) {
            detail::parallel_invoke([&] { plan_splits(base, b, left, parts[0], plan); },
                                    [&] { plan_splits(base, b + left, m - left, parts[1], plan); });
            return;
        }
        if (left < m - left) {
            plan_sequentially(b, left, parts[0]);
            b += left;
            m -= left;
            bounds = parts[1];
        } else {
            plan_sequentially(b + left, m - left, parts[1]);
            m = left;
            bounds = parts[0];
        }
    }
}

}  // namespace spatial
