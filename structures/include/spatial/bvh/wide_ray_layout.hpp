#pragma once
// spatial::bvh_detail::wide_ray_layout<O, T, D, W> — a read-only copy of a binary aabb BVH
// laid out for ray casting the way fast ray tracers lay out theirs:
//  * W-wide nodes, W = 4 or 8 (Dammertz, Hanika & Keller 2008, "Shallow bounding volume
//    hierarchies for fast SIMD ray tracing of incoherent rays"; Wald, Benthin & Boulos 2008,
//    "Getting rid of packets"): the binary tree is collapsed by repeatedly opening the child
//    of largest surface area until a node has W children, so one SIMD slab test per axis
//    tests W boxes and a ray visits far fewer nodes (log_W instead of log_2 levels);
//  * the child boxes in single precision, stored axis by axis (lo[axis][lane],
//    hi[axis][lane]), rounded OUTWARD from the double boxes (a float box always contains
//    the double one): 128 (W = 4) or 256 (W = 8) bytes per node, a quarter of the memory
//    traffic of W double boxes;
//  * the objects COPIED in leaf order, so a leaf's objects are contiguous in memory (no
//    per-object indirection through the stable slot storage), with their slot ids alongside
//    so a hit is reported as the container's iterator; children about to be visited are
//    prefetched (incoherent rays are bound by cache misses).
// Answers are exactly those of the binary tree: the leaves run the same exact object test
// (O::intersect, in T) and boxes are only ever grown. The float slab test is conservative
// by growth: each box is grown by the caller's thickness-and-rounding slack plus
// 2^-18 (|origin|_inf + |scene|_inf), which bounds the float rounding of the origin, of
// the direction's reciprocal and of the slab parameters (a few 2^-24 relative each; see
// docs/design.md §12.6). Rays or scenes outside float's comfortable range (coordinates
// above 1e30, nonzero direction components outside [1e-30, 1e30]) are refused by
// accepts() and take the binary double path instead.
//
// Built in O(n) from a binary tree (collapse + copy) and immutable afterwards; the bvh
// rebuilds it lazily after any change (see bvh::prepare_rays). Memory: one wide node per
// about (W - 1) / W of the binary inner nodes' worth of levels (roughly n / (leaf_size W / 2)
// nodes) plus a copy of every object and a 32-bit id.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "spatial/bv/rounding.hpp"
#include "spatial/bvh/traversal_stack.hpp"

namespace spatial::bvh_detail {

// SIMD lanes (GCC/Clang vector extensions: element-wise arithmetic and comparisons, lowered
// to SSE / AVX / NEON as the target allows).
typedef float float_lanes4 __attribute__((vector_size(16)));
typedef float float_lanes8 __attribute__((vector_size(32)));

#if defined(__AVX__)
inline constexpr std::size_t default_wide_ray_width = 8;
#else
inline constexpr std::size_t default_wide_ray_width = 4;
#endif

template <class O, class T, std::size_t D, std::size_t Width = default_wide_ray_width>
class wide_ray_layout {
public:
    static constexpr std::size_t width = Width;
    static_assert(width == 4 || width == 8, "wide_ray_layout: 4 or 8 lanes");
    using object_index = std::uint32_t;
    static constexpr object_index no_object = std::numeric_limits<object_index>::max();
    // Coordinates and reciprocals beyond this are left to the double path (float's range
    // ends at 3.4e38; the margin keeps every intermediate finite).
    static constexpr double float_range = 1e30;

    struct alignas(64) wide_node {
        float lo[D][width];           // empty lane: +inf (its slab interval is empty)
        float hi[D][width];           // empty lane: -inf
        std::uint32_t child[width];   // inner lane: wide node index; leaf lane: first object
        std::uint8_t count[width];    // 0: inner lane (or empty); k > 0: a leaf of k objects
    };

    // Collapses a binary tree. Tree provides: root(), is_leaf(n), left(n) (right = left + 1),
    // lower(n, axis) / upper(n, axis) of node n's box, leaf_size(n), leaf_slot(n, i),
    // value(slot) and object_count(). Leaves hold at most 255 objects. O(nodes + objects).
    template <class Tree>
    void build(const Tree& tree) {
        nodes_.clear();
        objects_.clear();
        slots_.clear();
        magnitude_ = 0;
        usable_ = false;
        if (tree.is_leaf(tree.root()) && tree.leaf_size(tree.root()) == 0) return;  // empty: never queried
        for (std::size_t a = 0; a < D; ++a)
            magnitude_ = std::max({magnitude_, std::abs(static_cast<double>(tree.lower(tree.root(), a))),
                                   std::abs(static_cast<double>(tree.upper(tree.root(), a)))});
        usable_ = magnitude_ <= float_range;
        objects_.reserve(tree.object_count());
        slots_.reserve(tree.object_count());
        nodes_.reserve(tree.object_count() / 4 + 1);
        struct task {
            typename Tree::node_index binary;
            std::uint32_t wide;
        };
        std::vector<task> todo;
        nodes_.push_back(empty_node());
        if (tree.is_leaf(tree.root())) {
            set_lane(tree, 0, 0, tree.root(), todo);
        } else {
            todo.push_back({tree.root(), 0});
        }
        while (!todo.empty()) {
            const task tk = todo.back();
            todo.pop_back();
            // Open the largest-area inner child until there are `width` children.
            std::array<typename Tree::node_index, width> kids{};
            std::size_t k = 2;
            kids[0] = tree.left(tk.binary);
            kids[1] = tree.left(tk.binary) + 1;
            while (k < width) {
                std::size_t best = width;
                double best_area = -1;
                for (std::size_t i = 0; i < k; ++i) {
                    if (tree.is_leaf(kids[i])) continue;
                    const double area = half_area(tree, kids[i]);
                    if (area > best_area) best_area = area, best = i;
                }
                if (best == width) break;
                const auto opened = kids[best];
                kids[best] = tree.left(opened);
                kids[k++] = tree.left(opened) + 1;
            }
            for (std::size_t i = 0; i < k; ++i) set_lane(tree, tk.wide, i, kids[i], todo);
        }
    }

    bool empty() const { return nodes_.empty(); }
    std::size_t node_count() const { return nodes_.size(); }
    std::size_t memory_bytes() const {
        return nodes_.capacity() * sizeof(wide_node) + objects_.capacity() * sizeof(O) +
               slots_.capacity() * sizeof(std::uint32_t);
    }
    // The slot id (container handle) of a copied object.
    std::uint32_t slot_of(object_index i) const { return slots_[i]; }

    // A ray prepared for the float slab tests; see accepts().
    struct float_ray {
        std::array<float, D> near_origin, far_origin, inverse;
        std::array<bool, D> negative;
    };
    // Whether the float path is exact-safe for this ray (see the header comment), and if so
    // its float form. grow: the caller's growth of every box (thickness + rounding slack).
    bool accepts(const std::array<T, D>& origin, const std::array<T, D>& direction, T grow, float_ray& r) const {
        if (!usable_) return false;
        double m = magnitude_;
        for (std::size_t a = 0; a < D; ++a) {
            const double o = static_cast<double>(origin[a]), d = static_cast<double>(direction[a]);
            if (!(std::abs(o) <= float_range)) return false;
            if (d != 0 && !(std::abs(d) >= 1 / float_range && std::abs(d) <= float_range)) return false;
            m = std::max(m, std::abs(o));
        }
        const double g = static_cast<double>(grow) + 0x1p-18 * m + std::numeric_limits<float>::min();
        if (!(g <= float_range)) return false;
        for (std::size_t a = 0; a < D; ++a) {
            const double o = static_cast<double>(origin[a]), d = static_cast<double>(direction[a]);
            r.negative[a] = std::signbit(d);
            // near plane of a grown box: lo - g (hi + g when the direction is negative), so
            // (near - origin) * inverse = (box bound - shifted origin) * inverse.
            r.near_origin[a] = static_cast<float>(r.negative[a] ? o - g : o + g);
            r.far_origin[a] = static_cast<float>(r.negative[a] ? o + g : o - g);
            r.inverse[a] = 1.0f / static_cast<float>(d);  // +-inf for a +-0 component
        }
        return true;
    }

    // The nearest hit before info.hit_time: index of the object hit or no_object. test(obj)
    // runs the exact object test (which lowers info.hit_time on a hit). visited counts the
    // child boxes the ray entered (as the binary tree counts its nodes), tested the objects
    // tested.
    template <class Info, class Test>
    object_index intersect(const float_ray& r, Info& info, Test&& test, std::size_t& visited,
                           std::size_t& tested) const {
        using lanes = std::conditional_t<width == 8, float_lanes8, float_lanes4>;
        struct entry {
            std::uint32_t ref;
            std::uint32_t count;
            float t;
        };
        traversal_stack<entry> stack;
        object_index hit = no_object;
        float limit = detail_rounding::round_up<float>(static_cast<double>(info.hit_time));
        auto test_leaf = [&](std::uint32_t first, std::uint32_t count) {
            tested += count;
            for (std::uint32_t i = first; i < first + count; ++i)
                if (test(objects_[i])) hit = i;
            if (hit != no_object) limit = detail_rounding::round_up<float>(static_cast<double>(info.hit_time));
        };
        entry cur{0, 0, 0.0f};
        for (;;) {
            if (cur.count != 0) {
                test_leaf(cur.ref, cur.count);
            } else {
                const wide_node& nd = nodes_[cur.ref];
                lanes tmin = lanes{} + 0.0f;
                lanes tmax = lanes{} + limit;
                for (std::size_t a = 0; a < D; ++a) {
                    lanes near_plane, far_plane;
                    std::memcpy(&near_plane, r.negative[a] ? nd.hi[a] : nd.lo[a], sizeof(lanes));
                    std::memcpy(&far_plane, r.negative[a] ? nd.lo[a] : nd.hi[a], sizeof(lanes));
                    const lanes tn = (near_plane - r.near_origin[a]) * r.inverse[a];
                    const lanes tf = (far_plane - r.far_origin[a]) * r.inverse[a];
                    // A NaN (0 * inf: the origin on a slab plane of a parallel ray) fails
                    // both comparisons and leaves the interval as it was.
                    tmin = tn > tmin ? tn : tmin;
                    tmax = tf < tmax ? tf : tmax;
                }
                const auto inside = tmin <= tmax;
                // One bit per lane hit; the lanes are then read without a branch per lane
                // (whether a lane is hit is unpredictable for incoherent rays).
                unsigned mask = lane_mask(inside);
                float entry_t[width];
                std::memcpy(entry_t, &tmin, sizeof(entry_t));
                entry near_hits[width];
                std::size_t h = 0;
                for (; mask != 0; mask &= mask - 1) {
                    const auto i = static_cast<std::size_t>(__builtin_ctz(mask));
                    near_hits[h++] = {nd.child[i], nd.count[i], entry_t[i]};
                    prefetch(nd.child[i], nd.count[i]);
                }
                visited += h;
                // Nearest first: push the others farthest first, go on with the nearest.
                for (std::size_t i = 1; i < h; ++i)
                    for (std::size_t j = i; j > 0 && near_hits[j].t < near_hits[j - 1].t; --j)
                        std::swap(near_hits[j], near_hits[j - 1]);
                if (h > 0) {
                    for (std::size_t i = h; i-- > 1;) stack.push(near_hits[i]);
                    cur = near_hits[0];
                    continue;
                }
            }
            // Next: the nearest pending entry whose entry parameter is not beyond the best hit.
            for (;;) {
                if (stack.empty()) return hit;
                cur = stack.pop();
                if (cur.t <= limit) break;
            }
        }
    }

private:
    // Bit i set iff lane i of a comparison result is true.
    template <class Cmp>
    static unsigned lane_mask(const Cmp& c) {
#if defined(__AVX__)
        if constexpr (width == 8) return static_cast<unsigned>(_mm256_movemask_ps(reinterpret_cast<__m256>(c)));
#endif
#if defined(__SSE__)
        if constexpr (width == 4) return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(c)));
#endif
        unsigned m = 0;
        for (std::size_t i = 0; i < width; ++i) m |= unsigned(c[i] & 1) << i;
        return m;
    }
    // Incoherent rays are bound by cache misses: start loading every child that will be
    // visited (its node, or its leaf's objects) while the nearest one is processed.
    void prefetch(std::uint32_t ref, std::uint32_t count) const {
        const char* p;
        std::size_t bytes;
        if (count == 0) {
            p = reinterpret_cast<const char*>(&nodes_[ref]);
            bytes = sizeof(wide_node);
        } else {
            p = reinterpret_cast<const char*>(&objects_[ref]);
            bytes = count * sizeof(O);
        }
        for (std::size_t off = 0; off < bytes; off += 64) __builtin_prefetch(p + off);
    }
    static wide_node empty_node() {
        wide_node n;
        for (std::size_t a = 0; a < D; ++a)
            for (std::size_t i = 0; i < width; ++i) {
                n.lo[a][i] = std::numeric_limits<float>::infinity();
                n.hi[a][i] = -std::numeric_limits<float>::infinity();
            }
        for (std::size_t i = 0; i < width; ++i) n.child[i] = 0, n.count[i] = 0;
        return n;
    }
    template <class Tree>
    static double half_area(const Tree& tree, typename Tree::node_index n) {
        double e[D];
        for (std::size_t a = 0; a < D; ++a)
            e[a] = static_cast<double>(tree.upper(n, a)) - static_cast<double>(tree.lower(n, a));
        if constexpr (D == 2) return e[0] + e[1];
        else if constexpr (D == 3) return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
        else {
            double s = 0;
            for (std::size_t a = 0; a < D; ++a) s += e[a];
            return s;
        }
    }
    // Fills lane i of wide node `parent` with binary node n: a leaf's objects are copied now,
    // an inner node gets a wide node of its own (filled later from `todo`).
    template <class Tree, class Task>
    void set_lane(const Tree& tree, std::size_t parent, std::size_t i, typename Tree::node_index n,
                  std::vector<Task>& todo) {
        // By index: nodes_ may grow (and move) below.
        for (std::size_t a = 0; a < D; ++a) {
            nodes_[parent].lo[a][i] = detail_rounding::round_down<float>(static_cast<double>(tree.lower(n, a)));
            nodes_[parent].hi[a][i] = detail_rounding::round_up<float>(static_cast<double>(tree.upper(n, a)));
        }
        if (tree.is_leaf(n)) {
            const std::size_t m = tree.leaf_size(n);
            nodes_[parent].child[i] = static_cast<std::uint32_t>(objects_.size());
            nodes_[parent].count[i] = static_cast<std::uint8_t>(m);
            for (std::size_t j = 0; j < m; ++j) {
                const auto s = tree.leaf_slot(n, j);
                objects_.push_back(tree.value(s));
                slots_.push_back(static_cast<std::uint32_t>(s));
            }
        } else {
            const auto w = static_cast<std::uint32_t>(nodes_.size());
            nodes_.push_back(empty_node());
            nodes_[parent].child[i] = w;
            nodes_[parent].count[i] = 0;
            todo.push_back({n, w});
        }
    }

    std::vector<wide_node> nodes_;
    std::vector<O> objects_;
    std::vector<std::uint32_t> slots_;
    double magnitude_ = 0;
    bool usable_ = false;
};

}  // namespace spatial::bvh_detail
