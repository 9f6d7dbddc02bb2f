#pragma once
// BVH builders: given the items of one node (each an axis-aligned box and its centre), decide
// whether the node is a leaf and, if not, partition the items in place into two non-empty
// halves. Like madmann91/bvh's builders they see only boxes and centres, never objects or
// bounding volumes of other types: the SAH cost below uses the objects' AABBs even when the
// tree's node volume is a sphere, an obb, ... (the surface area of an AABB is cheap, exact and
// monotone; documented in docs/structures/bvh.md, builders).
//
//   median_split  object median along the widest axis of the centroids' box: nth_element,
//                 O(m) per node, O(n log n) per build, depth ceil(log2(n / leaf_size)).
//   binned_sah    Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"
//                 (IEEE RT'07): the centroids' box is cut into B equal bins per axis, each
//                 bin accumulates the AABB and count of its objects, and a sweep evaluates the
//                 surface area heuristic (Goldsmith & Salmon 1987; MacDonald & Booth 1990)
//                     cost(split) = C_trav + C_isect (A_L N_L + A_R N_R) / A_node
//                 (N counted in blocks of sah_costs::block objects where leaves are tested
//                 a block at a time)
//                 at the B - 1 bin boundaries of every axis (every axis binned in one pass
//                 over the items, the sweeps over the non-empty bins only); O(m D + B D) per
//                 node, O(n log n) per build for balanced splits. A node with at most
//                 leaf_size items becomes a leaf when C_isect N is not more than the best
//                 split; a node with more items is always split. When every centroid coincides (no axis to bin along) the
//                 object median is used, so identical objects still give a balanced tree.
//
// Both take the node's bounds (range_bounds: the items' box and their centres' box) from the
// caller and return the two parts' bounds, computed while partitioning, so each level of a
// build reads its items twice (binning and partitioning).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "spatial/core/parallel.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial {

enum class bvh_build_method { median_split, binned_sah };

namespace bvh_detail {

template <class T, std::size_t D>
struct build_item {
    std::array<T, D> lo, hi;  // the object's AABB
    std::array<T, D> c;       // its centre (object_center)
    slot_index slot;
};

// Surface area (perimeter in 2D) of the box [lo, hi], 0 for an empty one, in double: AABB
// areas of 1e15-sized boxes overflow float.
template <class T, std::size_t D>
double box_area(const std::array<T, D>& lo, const std::array<T, D>& hi) {
    if (!(lo[0] <= hi[0])) return 0;
    double s = 0;
    for (std::size_t i = 0; i < D; ++i) {
        double face = 1;
        for (std::size_t j = 0; j < D; ++j)
            if (j != i) face *= static_cast<double>(hi[j]) - static_cast<double>(lo[j]);
        s += face;
    }
    return D == 1 ? 1 : 2 * s;
}

// Grows the box [lo, hi] to contain [a, b] (the one min/max union of the builders and of
// bvh::place; min(lo, a) in this order, so an infinite empty box takes [a, b] exactly).
template <class T, std::size_t D>
void extend_box(std::array<T, D>& lo, std::array<T, D>& hi, const std::array<T, D>& a, const std::array<T, D>& b) {
    for (std::size_t i = 0; i < D; ++i) lo[i] = std::min(lo[i], a[i]), hi[i] = std::max(hi[i], b[i]);
}

template <class T, std::size_t D>
struct box_accumulator {
    std::array<T, D> lo, hi;
    box_accumulator() {
        lo.fill(std::numeric_limits<T>::infinity());
        hi.fill(-std::numeric_limits<T>::infinity());
    }
    void add(const std::array<T, D>& a, const std::array<T, D>& b) { extend_box(lo, hi, a, b); }
    double area() const { return box_area<T, D>(lo, hi); }
};

// The box of a range of items and the box of their centres: what a split decision needs of a
// node before it reads the node's items. A split computes its two parts' bounds while it
// partitions them, and the builder hands them down with the parts, so a build reads a node's
// items twice (binning, partitioning) rather than four times (these bounds, binning,
// partitioning, the node's box). The items of the upper levels do not fit in cache: those
// passes over memory were most of a build's time.
template <class T, std::size_t D>
struct range_bounds {
    box_accumulator<T, D> box, centres;
    // Inlined by force: GCC 12 left it a call in partition_with_bounds's loops (1e8 calls on a
    // build of 2e5 points, which then ran more instructions than the passes it replaced).
    [[gnu::always_inline]] void add(const build_item<T, D>& it) { box.add(it.lo, it.hi), centres.add(it.c, it.c); }
    // Then the bounds of items that come after this one's (min and max keep the first of equal
    // values, so merging in item order gives what adding each item in that order gives).
    void merge(const range_bounds& later) { box.add(later.box.lo, later.box.hi), centres.add(later.centres.lo, later.centres.hi); }
    static range_bounds of(const build_item<T, D>* first, std::size_t m) {
        range_bounds r;
        for (std::size_t i = 0; i < m; ++i) r.add(first[i]);
        return r;
    }
};
// The bounds of both parts of [first, first + m) split at `left`.
template <class T, std::size_t D>
void bounds_of_parts(const build_item<T, D>* first, std::size_t m, std::size_t left, std::array<range_bounds<T, D>, 2>& parts) {
    parts[0] = range_bounds<T, D>::of(first, left);
    parts[1] = range_bounds<T, D>::of(first + left, m - left);
}

// std::partition (the bidirectional algorithm of libstdc++: the same order of the items) that
// adds each item to the bounds of the part it goes to. Returns the size of the first part.
template <class T, std::size_t D, class GoesFirst>
std::size_t partition_with_bounds(build_item<T, D>* first, std::size_t m, GoesFirst goes_first,
                                  std::array<range_bounds<T, D>, 2>& parts) {
    parts = {};
    build_item<T, D>*lo = first, *hi = first + m;
    for (;;) {
        for (;; ++lo) {
            if (lo == hi) return static_cast<std::size_t>(lo - first);
            if (!goes_first(*lo)) break;
            parts[0].add(*lo);
        }
        --hi;
        for (;; --hi) {
            if (lo == hi) {
                parts[1].add(*lo);  // the item the first scan stopped at
                return static_cast<std::size_t>(lo - first);
            }
            if (goes_first(*hi)) break;
            parts[1].add(*hi);
        }
        parts[0].add(*hi), parts[1].add(*lo);
        std::swap(*lo, *hi);
        ++lo;
    }
}

// Splits [first, first + m) at the object median of the widest axis of `cb`, the box of their
// centres. Returns m / 2.
template <class T, std::size_t D>
std::size_t median_split(build_item<T, D>* first, std::size_t m, const box_accumulator<T, D>& cb) {
    std::size_t axis = 0;
    for (std::size_t i = 1; i < D; ++i)
        if (cb.hi[i] - cb.lo[i] > cb.hi[axis] - cb.lo[axis]) axis = i;
    const std::size_t half = m / 2;
    std::nth_element(first, first + half, first + m,
                     [axis](const build_item<T, D>& a, const build_item<T, D>& b) { return a.c[axis] < b.c[axis]; });
    return half;
}

struct sah_costs {
    double traversal = 1;     // C_trav: cost of visiting an inner node
    double intersection = 1;  // C_isect: cost of testing one block of objects
    // Objects tested together (one SIMD step): a leaf's cost counts blocks, ceil(N / block),
    // not objects, as Embree's builders do with their sahBlockSize (Wald, Woop, Benthin,
    // Johnson & Ernst 2014, "Embree: a kernel framework for efficient CPU ray tracing").
    // With block = 4 a leaf of 1 to 4 triangles costs the same, so the SAH makes full
    // leaves of 4 instead of 1-2 triangles that waste SIMD lanes and the bytes padding
    // them (docs/structures/bvh.md; figures: docs/experiments/bvh-rays.md). 1: the classic per-object cost.
    std::size_t block = 1;
    // (No division for block 1: the sweeps call this twice per boundary of every node.)
    double blocks(std::size_t n) const { return static_cast<double>(block == 1 ? n : (n + block - 1) / block); }
};

// Binned SAH decision for [first, first + m), whose bounds are `bounds`. Returns 0 for "make a
// leaf", else the size of the left part after partitioning the items in place (0 < left < m),
// with the bounds of both parts in `parts`.
// on_every_core: a node of at least parallel_split_items items (the top of a parallel build,
// which no other thread can share) is binned on every core of the parallel back end, to the
// same bins (below).
inline constexpr std::size_t parallel_split_items = std::size_t{1} << 17;
template <std::size_t Bins, class T, std::size_t D>
std::size_t binned_sah_split(build_item<T, D>* first, std::size_t m, std::size_t leaf_size, sah_costs costs,
                             const range_bounds<T, D>& bounds, std::array<range_bounds<T, D>, 2>& parts,
                             bool on_every_core = false) {
    static_assert(Bins >= 2, "binned SAH needs at least 2 bins");
    // One item is a leaf (what the code below decides too, its centroids' box being a point):
    // half the nodes of a point tree, whose SAH splits down to single points, skip the setup.
    if (m <= 1) return 0;
    const box_accumulator<T, D>&node_box = bounds.box, &cb = bounds.centres;
    // Bin index of a centroid along `axis`: the same function for binning and partitioning.
    auto bin_of = [&](const build_item<T, D>& it, std::size_t axis, double scale) {
        const double x = (static_cast<double>(it.c[axis]) - static_cast<double>(cb.lo[axis])) * scale;
        if (!(x > 0)) return std::size_t(0);  // also NaN
        if (!(x < static_cast<double>(Bins))) return Bins - 1;
        return static_cast<std::size_t>(x);
    };
    double best_cost = std::numeric_limits<double>::infinity();
    std::size_t best_axis = D, best_boundary = 0;
    const double parent_area = node_box.area();
    // Every axis is binned in one pass over the items (each item is read once, not once per
    // axis: the items of a large node do not stay in cache between passes, and these passes
    // were most of a build's time). The bins get the same items in the same order as one
    // pass per axis would, so the tree is the same.
    std::array<double, D> scale{};
    std::array<bool, D> binned{};
    for (std::size_t axis = 0; axis < D; ++axis) {
        const double extent = static_cast<double>(cb.hi[axis]) - static_cast<double>(cb.lo[axis]);
        binned[axis] = extent > 0;
        scale[axis] = binned[axis] ? static_cast<double>(Bins) / extent : 0;
    }
    // A bin's box is set by its first item and read only once it has one (the sweeps below
    // skip empty bins), so in a small node the D * Bins boxes are not initialised: for the many
    // small nodes of a build (and every leaf split of an insertion) that initialisation cost
    // more than the binning itself. A large node starts them empty instead, and its items
    // extend them without the unpredictable branch on the bin's first item (extending the
    // empty box by a box gives that box exactly: the same bins either way).
    struct bin_box {
        std::array<T, D> lo, hi;
    };
    using axis_bins = std::array<std::array<bin_box, Bins>, D>;
    using axis_counts = std::array<std::array<std::uint32_t, Bins>, D>;  // a node holds < 2^32 items (slot_index)
    axis_bins bins;
    axis_counts counts{};
    auto bin_items = [&](std::size_t b, std::size_t e, axis_bins& into, axis_counts& n, auto&& into_bin) {
        for (std::size_t i = b; i < e; ++i)
            for (std::size_t axis = 0; axis < D; ++axis) {
                if (!binned[axis]) continue;
                const std::size_t k = bin_of(first[i], axis, scale[axis]);
                into_bin(into[axis][k], n[axis][k]++, first[i]);
            }
    };
    auto start_empty = [](axis_bins& into) {
        for (auto& one_axis : into)
            for (bin_box& box : one_axis) box.lo.fill(std::numeric_limits<T>::infinity()), box.hi.fill(-std::numeric_limits<T>::infinity());
    };
    auto extend = [](bin_box& box, std::uint32_t, const build_item<T, D>& it) { extend_box(box.lo, box.hi, it.lo, it.hi); };
    if (on_every_core && m >= parallel_split_items) {
        // Each chunk of items into bins of its own, merged in chunk order: counts add, and
        // min/max keep the first of equal values (extend_box), so the merged bins are those
        // of one pass in item order, signed zeros included. The root of the 1e6 sphere: 9 ms
        // of binning on one thread.
        constexpr std::size_t chunk = std::size_t{1} << 14;
        const std::size_t chunks = (m + chunk - 1) / chunk;
        std::vector<axis_bins> chunk_bins(chunks);
        std::vector<axis_counts> chunk_counts(chunks, axis_counts{});
        detail::parallel_chunks(chunks, 1, [&](std::size_t b, std::size_t e) {
            for (std::size_t k = b; k < e; ++k) {
                // Binned into local arrays (the compiler keeps them apart from the items it reads).
                axis_bins local;
                axis_counts local_counts{};
                start_empty(local);
                bin_items(k * chunk, std::min(m, (k + 1) * chunk), local, local_counts, extend);
                chunk_bins[k] = local;
                chunk_counts[k] = local_counts;
            }
        });
        start_empty(bins);
        for (std::size_t k = 0; k < chunks; ++k)
            for (std::size_t axis = 0; axis < D; ++axis)
                for (std::size_t j = 0; j < Bins; ++j) {
                    const bin_box& part = chunk_bins[k][axis][j];
                    extend_box(bins[axis][j].lo, bins[axis][j].hi, part.lo, part.hi);
                    counts[axis][j] += chunk_counts[k][axis][j];
                }
    } else if (m >= 8 * Bins) {
        start_empty(bins);
        bin_items(0, m, bins, counts, extend);
    } else {
        bin_items(0, m, bins, counts, [](bin_box& box, std::uint32_t before, const build_item<T, D>& it) {
            if (before == 0) box.lo = it.lo, box.hi = it.hi;
            else extend_box(box.lo, box.hi, it.lo, it.hi);
        });
    }
    // The sweeps visit the non-empty bins only: a boundary between two empty bins splits the
    // items as the boundary right after the last non-empty bin on its left does, at the same
    // cost, and that earlier boundary is the one kept on ties. So the split is the one every
    // boundary's sweep would choose, at O(non-empty bins) instead of O(Bins) per axis: most
    // nodes of a large tree hold a few items (a point tree's nodes down to one), where the
    // Bins-wide sweeps dominated.
    for (std::size_t axis = 0; axis < D; ++axis) {
        if (!binned[axis]) continue;
        // Written before read (no zeroing: these arrays are set up for every node of a build).
        std::array<std::size_t, Bins> used;  // the non-empty bins, in order
        std::size_t k = 0;
        for (std::size_t b = 0; b < Bins; ++b)
            if (counts[axis][b] != 0) used[k++] = b;
        // Sweep from the right: area and count of the non-empty bins [j, k).
        std::array<double, Bins> right_area;
        std::array<std::size_t, Bins> right_count;
        box_accumulator<T, D> acc;
        std::size_t n = 0;
        for (std::size_t j = k; j-- > 1;) {
            acc.add(bins[axis][used[j]].lo, bins[axis][used[j]].hi);
            n += counts[axis][used[j]];
            right_area[j] = acc.area();
            right_count[j] = n;
        }
        box_accumulator<T, D> left;
        std::size_t nl = 0;
        for (std::size_t j = 1; j < k; ++j) {  // boundary used[j - 1] + 1: bins [0, used[j - 1]] | the rest
            left.add(bins[axis][used[j - 1]].lo, bins[axis][used[j - 1]].hi);
            nl += counts[axis][used[j - 1]];
            const double c = left.area() * costs.blocks(nl) + right_area[j] * costs.blocks(right_count[j]);
            if (c < best_cost) best_cost = c, best_axis = axis, best_boundary = used[j - 1] + 1;
        }
    }
    auto median = [&] {
        const std::size_t half = median_split(first, m, cb);
        bounds_of_parts(first, m, half, parts);
        return half;
    };
    if (best_axis == D) {  // all centroids coincide
        return m <= leaf_size ? 0 : median();
    }
    const double split_cost =
        costs.traversal + costs.intersection * (parent_area > 0 ? best_cost / parent_area : costs.blocks(m));
    if (m <= leaf_size && costs.intersection * costs.blocks(m) <= split_cost) return 0;
    auto goes_left = [&](const build_item<T, D>& it) { return bin_of(it, best_axis, scale[best_axis]) < best_boundary; };
    const std::size_t left = partition_with_bounds(first, m, goes_left, parts);
    if (left == 0 || left == m) return median();  // cannot happen; safety net
    return left;
}

}  // namespace bvh_detail
}  // namespace spatial
