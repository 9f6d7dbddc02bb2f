#pragma once
// spatial::bvh_detail::wide_ray_layout<O, T, D, W> — a read-only copy of a binary aabb BVH
// laid out for ray casting the way fast ray tracers lay out theirs:
//  * W-wide nodes, W = 4 or 8 (Dammertz, Hanika & Keller 2008, "Shallow bounding volume
//    hierarchies for fast SIMD ray tracing of incoherent rays"; Wald, Benthin & Boulos 2008,
//    "Getting rid of packets"): the binary tree is collapsed by repeatedly opening the child
//    of largest SAH cost (surface area x objects) until a node has W children, so one SIMD
//    slab test per axis tests W boxes and a ray visits far fewer nodes (log_W instead of
//    log_2 levels);
//  * the child boxes quantised to 8 bits per plane relative to a per-node float frame
//    (Ylitie, Karras & Laine 2017), rounded OUTWARD from the double boxes (a quantised box
//    always contains the double one): 128 bytes per 8-wide node (64 for W = 4), half of a
//    node with float boxes;
//  * small subtrees (at most merged_leaf_objects objects) merged into one leaf lane, so
//    leaves are fuller and the bottom of the tree has no nearly empty wide nodes;
//  * the leaves' objects contiguous in leaf order, with their slot ids alongside so a hit is
//    reported as the container's iterator: a COPY of each object, or, where the object has
//    a compact ray form (compact_ray_form.hpp: triangles as SIMD blocks of 4, 72 bytes of
//    vertices each instead of 120), only that form; children about to be visited are
//    prefetched (incoherent rays are bound by cache misses);
//  * the arrays on transparent huge pages (core/huge_page_allocator.hpp): fewer TLB misses.
// Answers are exactly those of the binary tree: the leaves run the same exact object test
// (in T, with the same floating-point operations) and boxes are only ever grown. The float
// slab test is conservative by growth: each box is grown by the caller's
// thickness-and-rounding slack plus 2^-18 (|origin|_inf + |scene|_inf), which bounds the
// float rounding of the origin, of the node frame, of the direction's reciprocal and of the
// slab parameters (a few 2^-24 relative each; see docs/structures/bvh.md, wide ray layout). Rays or scenes
// outside float's comfortable range (coordinates above 1e30, nonzero direction components
// outside [1e-30, 1e30]) are refused by accepts() and take the binary double path instead.
//
// Built in O(n) from a binary tree (collapse, then the copy: on every core with
// bvh::prepare_rays(par)) and immutable afterwards; the bvh rebuilds it lazily after any
// change (see bvh::prepare_rays). Memory: one wide node per
// about W - 1 binary inner nodes, plus per object its copy (or compact form) and a 32-bit id.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "spatial/bv/rounding.hpp"
#include "spatial/bvh/compact_ray_form.hpp"
#include "spatial/bvh/traversal_stack.hpp"
#include "spatial/core/huge_page_allocator.hpp"
#include "spatial/core/parallel.hpp"

namespace spatial::bvh_detail {

// SIMD lanes (GCC/Clang vector extensions: element-wise arithmetic and comparisons, lowered
// to SSE / AVX / NEON as the target allows).
typedef float float_lanes4 __attribute__((vector_size(16)));
typedef float float_lanes8 __attribute__((vector_size(32)));
typedef std::int32_t int_lanes4 __attribute__((vector_size(16)));
typedef std::int32_t int_lanes8 __attribute__((vector_size(32)));
typedef std::uint8_t byte_lanes4 __attribute__((vector_size(4)));
typedef std::uint8_t byte_lanes8 __attribute__((vector_size(8)));

#if defined(__AVX__)
inline constexpr std::size_t default_wide_ray_width = 8;
#else
inline constexpr std::size_t default_wide_ray_width = 4;
#endif

}  // namespace spatial::bvh_detail

namespace spatial {
// Where the wide layout's leaves find their objects (bvh_config::ray_leaves).
enum class bvh_ray_leaves {
    // Copies in the layout, in leaf order (triangles: SIMD blocks of their vertices, 80
    // bytes a double triangle with its id). The fastest.
    copies,
    // The container's own objects where it stores them, tested one by one, when every leaf's
    // objects are consecutive slots (after a bulk build into an empty bvh, which stores its
    // objects in leaf order); copies otherwise. The layout is then its wide nodes alone.
    in_place,
};
}  // namespace spatial

namespace spatial::bvh_detail {

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

    // Child boxes quantised to 8 bits per plane (Ylitie, Karras & Laine 2017, "Efficient
    // incoherent ray traversal on GPUs through compressed wide BVHs"): on axis a, lane i's box
    // is origin[a] + [q_lo[a][i], q_hi[a][i]] * 2^exponent[a], rounded OUTWARD from the
    // child's double box, so it contains it. 128 bytes for W = 8 (two cache lines; a quarter
    // of W double boxes, half of W float boxes), 64 for W = 4 in 3D.
    struct alignas(64) wide_node {
        float origin[D];          // rounded down from the lower corner of the union
        std::int8_t exponent[D];  // scale 2^exponent, a normal float: in [-126, 127]
        std::uint8_t lanes = 0;   // bit i: lane i holds a child (empty lanes never hit)
        std::uint8_t q_lo[D][width];
        std::uint8_t q_hi[D][width];
        std::uint32_t child[width];  // inner lane: wide node index; leaf lane: first object
        std::uint8_t count[width];   // 0: inner lane; k > 0: a leaf of k objects
        friend bool operator==(const wide_node&, const wide_node&) = default;
    };
    // A binary subtree of at most this many objects (two SIMD blocks of triangles) becomes
    // one leaf lane when it is not opened to fill a node: fewer, fuller leaves (the binary SAH
    // stops at 1-2 triangles) and no nearly empty wide nodes at the bottom of the tree. 8
    // against 2, 4, 6, 12, 16 on the 1e6 sphere and soup: docs/structures/bvh.md.
    static constexpr std::size_t merged_leaf_objects = 8;

    // Collapses a binary tree. Tree provides: root(), is_leaf(n), left(n) (right = left + 1),
    // lower(n, axis) / upper(n, axis) of node n's box, leaf_size(n), leaf_slot(n, i),
    // value(slot) and object_count(). Leaves hold at most 255 objects. O(nodes + objects).
    // parallel: gather the leaves' objects on every core of the parallel back end
    // (core/parallel.hpp; bvh::prepare_rays(par)).
    template <class Tree>
    void build(const Tree& tree, bool parallel = false, bvh_ray_leaves leaves_wanted = bvh_ray_leaves::copies) {
        using node_index = typename Tree::node_index;
        nodes_.clear();
        objects_.clear();
        slots_.clear();
        forms_.clear();
        magnitude_ = 0;
        usable_ = false;
        in_place_ = false;
        if (tree.is_leaf(tree.root()) && tree.leaf_size(tree.root()) == 0) return;  // empty: never queried
        for (std::size_t a = 0; a < D; ++a)
            magnitude_ = std::max({magnitude_, std::abs(static_cast<double>(tree.lower(tree.root(), a))),
                                   std::abs(static_cast<double>(tree.upper(tree.root(), a)))});
        usable_ = magnitude_ <= float_range;
        if (!usable_) return;  // every ray takes the double path
        const std::vector<std::size_t> objects_below = subtree_object_counts(tree, parallel);
        // Pass 1 builds the wide nodes; leaf lanes hold their binary node and object count
        // until pass 2 stores the objects (so that the arrays can be sized exactly).
        std::vector<std::uint32_t> fill_order{0};
        nodes_.push_back(wide_node{});
        if (tree.is_leaf(tree.root())) {
            const std::array<node_index, width> only{tree.root()};
            std::vector<collapse_task<node_index>> none;
            fill_node(tree, nodes_, 0, only, 1, objects_below, none);
        } else if (parallel && objects_below[tree.root()] > 2 * collapse_grain) {
            collapse_on_every_core(tree, objects_below, fill_order);
        } else {
            collapse(tree, tree.root(), objects_below, nodes_, filling(fill_order));
        }
        // Pass 1 pushed the wide nodes one at a time: release the doubling's spare room (up
        // to 40 % of the array; immutable from here on). A failed reallocation keeps it.
        try {
            nodes_.shrink_to_fit();
        } catch (const std::bad_alloc&) {
        }
        // Pass 2: the leaves' objects, in the order the nodes were filled (depth first: a
        // subtree's leaves end up near each other). Each leaf lane's first object is known
        // from the counts (leaves padded to whole blocks), so the lanes are gathered
        // independently: on every core when `parallel` and the objects have compact forms
        // (each lane writes its own blocks; the layout is the same as on one thread).
        struct leaf_lane {
            std::uint32_t node;
            std::uint32_t lane;
            node_index binary;
            std::size_t first;
        };
        std::vector<leaf_lane> leaves;
        std::size_t stored = 0;  // slots, leaves padded to whole blocks
        for (const std::uint32_t n : fill_order) {
            const wide_node& nd = nodes_[n];
            for (std::uint32_t i = 0; i < width; ++i)
                if (nd.count[i] != 0) {
                    leaves.push_back({n, i, static_cast<node_index>(nd.child[i]), stored});
                    stored += (nd.count[i] + form_lanes - 1) / form_lanes * form_lanes;
                }
        }
        // Leaves in place (bvh_ray_leaves::in_place): when every leaf lane's objects are
        // consecutive slots of the container (after a bulk build into an empty bvh, which
        // stores its objects in leaf order: bvh::store_in_leaf_order), each lane refers to its
        // first slot and the objects are tested where the container keeps them; nothing is
        // copied.
        std::vector<std::uint32_t> first_slots(leaves.size());
        std::atomic<bool> consecutive{leaves_wanted == bvh_ray_leaves::in_place};
        auto check_range = [&](std::size_t b, std::size_t e) {
            gather_scratch<node_index> scratch;
            for (std::size_t l = b; l < e && consecutive.load(std::memory_order_relaxed); ++l) {
                subtree_slots(tree, leaves[l].binary, scratch);
                const auto& slots = scratch.leaf_slots;
                first_slots[l] = slots.front();
                for (std::size_t j = 1; j < slots.size(); ++j)
                    if (slots[j] != slots.front() + j) consecutive.store(false, std::memory_order_relaxed);
            }
        };
        if (consecutive.load()) {
            if (parallel) detail::parallel_chunks(leaves.size(), leaf_grain, check_range);
            else check_range(0, leaves.size());
        }
        in_place_ = consecutive.load();
        if (in_place_) {
            for (std::size_t l = 0; l < leaves.size(); ++l) nodes_[leaves[l].node].child[leaves[l].lane] = first_slots[l];
            return;
        }
        for (const leaf_lane& l : leaves) nodes_[l.node].child[l.lane] = static_cast<std::uint32_t>(l.first);
        if constexpr (has_ray_forms) {
            forms_.resize(stored / form_lanes);
            auto gather_range = [&](std::size_t b, std::size_t e) {
                gather_scratch<node_index> scratch;
                for (std::size_t l = b; l < e; ++l) gather_forms(tree, leaves[l].binary, leaves[l].first, scratch);
            };
            if (parallel) detail::parallel_chunks(leaves.size(), leaf_grain, gather_range);
            else gather_range(0, leaves.size());
        } else {
            objects_.reserve(stored);
            slots_.reserve(stored);
            gather_scratch<node_index> scratch;
            for (const leaf_lane& l : leaves) gather_objects(tree, l.binary, scratch);
        }
    }

    // Whether the leaves refer to the container's objects where they are (consecutive slots
    // per leaf lane; object index = slot) rather than to copies or blocks in this layout.
    bool leaves_in_place() const { return in_place_; }
    bool empty() const { return nodes_.empty(); }
    std::size_t node_count() const { return nodes_.size(); }
    // The wide nodes, root first, in the order build() lays them out (tests compare layouts).
    std::span<const wide_node> nodes() const { return nodes_; }
    std::size_t memory_bytes() const {
        std::size_t b = nodes_.capacity() * sizeof(wide_node) + objects_.capacity() * sizeof(O) +
                        slots_.capacity() * sizeof(std::uint32_t);
        if constexpr (has_ray_forms) b += forms_.capacity() * sizeof(typename ray_form::block);
        return b;
    }
    // Objects with a compact ray form (compact_ray_form.hpp) are kept as blocks of
    // form_lanes objects tested together (each leaf padded to whole blocks) instead of copies.
    using ray_form = compact_ray_form<O>;
    static constexpr bool has_ray_forms = ray_form::enabled;
    static constexpr std::size_t form_lanes = ray_form::lanes;
    // The slot id (container handle) of object i (in leaf order), and its copy (objects
    // without a compact ray form only).
    std::uint32_t slot_of(object_index i) const {
        if (in_place_) return i;
        if constexpr (has_ray_forms) return forms_[i / form_lanes].id[i % form_lanes];
        else return slots_[i];
    }
    const O& object(object_index i) const requires(!has_ray_forms) { return objects_[i]; }
    // The thin-ray test of the leaf of objects [first, first + count) on their blocks, in
    // object order: the object hit (info lowered) or no_object. O::prepared_ray ray.
    template <class Ray, class Info>
    object_index intersect_forms(object_index first, std::size_t count, const Ray& ray,
                                 Info& info) const requires has_ray_forms {
        object_index hit = no_object;
        for (std::size_t j = 0; j < count; j += form_lanes) {
            const int lane =
                ray_form::intersect(forms_[(first + j) / form_lanes], std::min(form_lanes, count - j), ray, info);
            if (lane >= 0) hit = static_cast<object_index>(first + j + static_cast<std::size_t>(lane));
        }
        return hit;
    }

    // A ray prepared for the float slab tests; see accepts().
    struct float_ray {
        std::array<float, D> near_origin, far_origin, inverse;
        // Byte offsets in a wide_node of the near and far planes' bytes per axis: q_lo and
        // q_hi, swapped where the direction is negative (no branch on the sign per node).
        std::array<std::uint32_t, D> near_planes, far_planes;
    };
    // max |bound| over the root box's bounds (0 for an empty tree).
    double scene_magnitude() const { return magnitude_; }
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
            const bool negative = std::signbit(d);
            // near plane of a grown box: lo - g (hi + g when the direction is negative), so
            // (near - origin) * inverse = (box bound - shifted origin) * inverse.
            r.near_origin[a] = static_cast<float>(negative ? o - g : o + g);
            r.far_origin[a] = static_cast<float>(negative ? o + g : o - g);
            const auto lo_planes = static_cast<std::uint32_t>(offsetof(wide_node, q_lo) + a * width);
            const auto hi_planes = static_cast<std::uint32_t>(offsetof(wide_node, q_hi) + a * width);
            r.near_planes[a] = negative ? hi_planes : lo_planes;
            r.far_planes[a] = negative ? lo_planes : hi_planes;
            r.inverse[a] = 1.0f / static_cast<float>(d);  // +-inf for a +-0 component
        }
        return true;
    }

    // The nearest hit before info.hit_time: index of the object hit or no_object.
    // test_leaf(first, count) runs the exact test of the leaf's objects [first, first +
    // count) in order (lowering info.hit_time on a hit) and returns the object hit or
    // no_object: on object(i), or on the blocks with intersect_forms, or with leaves in place
    // on the container's objects by slot, `objects` (what the leaves then prefetch). visited
    // counts the child boxes the ray entered (as the binary tree counts its nodes), tested
    // the objects tested. Objects is std::nullptr_t for leaves of this layout and const O*
    // for leaves in place, so that each traversal is compiled for one kind of leaf: a
    // run-time branch between them in the prefetch made the default's rays slower.
    template <class Info, class TestLeaf, class Objects = std::nullptr_t>
    object_index intersect(const float_ray& r, Info& info, TestLeaf&& leaf_test, std::size_t& visited,
                           std::size_t& tested, Objects objects = nullptr) const {
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
            const object_index h = leaf_test(first, count);
            if (h != no_object) {
                hit = h;
                limit = detail_rounding::round_up<float>(static_cast<double>(info.hit_time));
            }
        };
        lanes inverse[D];  // broadcast once per ray
        for (std::size_t a = 0; a < D; ++a) inverse[a] = lanes{} + r.inverse[a];
        entry cur{0, 0, 0.0f};
        for (;;) {
            if (cur.count != 0) {
                test_leaf(cur.ref, cur.count);
            } else {
                const wide_node& nd = nodes_[cur.ref];
                const auto* node_bytes = reinterpret_cast<const std::uint8_t*>(&nd);
                lanes tmin = lanes{} + 0.0f;
                lanes tmax = lanes{} + limit;
                for (std::size_t a = 0; a < D; ++a) {
                    // The planes relative to the shifted origins: q 2^e (exact in float) plus
                    // (node origin - shifted ray origin), one rounding each (docs/structures/bvh.md).
                    const float scale = power_of_two(nd.exponent[a]);
                    const lanes tn = exact_product_plus(to_lanes(node_bytes + r.near_planes[a]), scale,
                                                        nd.origin[a] - r.near_origin[a]) *
                                     inverse[a];
                    const lanes tf = exact_product_plus(to_lanes(node_bytes + r.far_planes[a]), scale,
                                                        nd.origin[a] - r.far_origin[a]) *
                                     inverse[a];
                    // A NaN (0 * inf: the origin on a slab plane of a parallel ray) fails
                    // both comparisons and leaves the interval as it was.
                    tmin = tn > tmin ? tn : tmin;
                    tmax = tf < tmax ? tf : tmax;
                }
                // One bit per lane hit; the lanes are then read without a branch per lane
                // (whether a lane is hit is unpredictable for incoherent rays).
                unsigned mask = lane_mask(tmin <= tmax) & nd.lanes;
                if (mask != 0) {
                    float entry_t[width];
                    std::memcpy(entry_t, &tmin, sizeof(entry_t));
                    auto lane_entry = [&](unsigned i) { return entry{nd.child[i], nd.count[i], entry_t[i]}; };
                    const auto first = static_cast<unsigned>(__builtin_ctz(mask));
                    mask &= mask - 1;
                    if (mask == 0) {  // one child hit (the common case deep in the tree): go there
                        ++visited;
                        cur = lane_entry(first);
                        continue;
                    }
                    // Several: start loading them all, then go on with the nearest and push
                    // the others farthest first.
                    entry near_hits[width];
                    near_hits[0] = lane_entry(first);
                    prefetch(near_hits[0], objects);
                    std::size_t h = 1;
                    for (; mask != 0; mask &= mask - 1) {
                        near_hits[h] = lane_entry(static_cast<unsigned>(__builtin_ctz(mask)));
                        prefetch(near_hits[h++], objects);
                    }
                    visited += h;
                    for (std::size_t i = 1; i < h; ++i)
                        for (std::size_t j = i; j > 0 && near_hits[j].t < near_hits[j - 1].t; --j)
                            std::swap(near_hits[j], near_hits[j - 1]);
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
    template <class Entry, class Objects>
    void prefetch(const Entry& e, Objects objects) const {
        const std::uint32_t ref = e.ref, count = e.count;
        const char* p;
        std::size_t bytes;
        if (count == 0) {
            p = reinterpret_cast<const char*>(&nodes_[ref]);
            bytes = sizeof(wide_node);
        } else if constexpr (!std::is_same_v<Objects, std::nullptr_t>) {
            // Leaves in place: the objects need not start on a cache line.
            p = reinterpret_cast<const char*>(objects + ref);
            const std::size_t misalignment = reinterpret_cast<std::uintptr_t>(p) & 63;
            p -= misalignment;
            bytes = count * sizeof(O) + misalignment;
        } else if constexpr (has_ray_forms) {
            p = reinterpret_cast<const char*>(&forms_[ref / form_lanes]);
            bytes = (count + form_lanes - 1) / form_lanes * sizeof(typename ray_form::block);
        } else {
            p = reinterpret_cast<const char*>(&objects_[ref]);
            bytes = count * sizeof(O);
        }
        for (std::size_t off = 0; off < bytes; off += 64) __builtin_prefetch(p + off);
    }
    // q * scale + offset with one rounding, q * scale being exact (8-bit integers times a power
    // of two): a fused multiply-add where the target has one (the same value either way).
    template <class Lanes>
    static Lanes exact_product_plus(Lanes q, float scale, float offset) {
#if defined(__FMA__)
        if constexpr (width == 8)
            return reinterpret_cast<Lanes>(
                _mm256_fmadd_ps(reinterpret_cast<__m256>(q), _mm256_set1_ps(scale), _mm256_set1_ps(offset)));
        else
            return reinterpret_cast<Lanes>(
                _mm_fmadd_ps(reinterpret_cast<__m128>(q), _mm_set1_ps(scale), _mm_set1_ps(offset)));
#else
        return q * scale + offset;
#endif
    }
    // 2^e as a float, e in [-126, 127], from its bits (no ldexp in the inner loop).
    static float power_of_two(std::int8_t e) {
        const std::uint32_t bits = static_cast<std::uint32_t>(static_cast<int>(e) + 127) << 23;
        float f;
        std::memcpy(&f, &bits, sizeof f);
        return f;
    }
    // W bytes to W floats (exact).
    static auto to_lanes(const std::uint8_t* q) {
        using lanes = std::conditional_t<width == 8, float_lanes8, float_lanes4>;
#if defined(__AVX2__)
        // One widening load and one conversion (the generic form below is assembled byte by
        // byte through scalar registers by GCC 12).
        if constexpr (width == 8)
            return reinterpret_cast<lanes>(
                _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(q)))));
#endif
#if defined(__SSE4_1__)
        if constexpr (width == 4) {
            std::int32_t four;
            std::memcpy(&four, q, sizeof four);
            return reinterpret_cast<lanes>(_mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(four))));
        }
#endif
        using byte_lanes = std::conditional_t<width == 8, byte_lanes8, byte_lanes4>;
        using int_lanes = std::conditional_t<width == 8, int_lanes8, int_lanes4>;
        byte_lanes b;
        std::memcpy(&b, q, sizeof b);
        return __builtin_convertvector(__builtin_convertvector(b, int_lanes), lanes);
    }
    // A binary node whose children wide node `wide` will hold (collapse's work list).
    template <class NodeIndex>
    struct collapse_task {
        NodeIndex binary;
        std::uint32_t wide;
    };
    // The binary nodes wide node of binary node n gets as children: n's two children, then
    // the inner child of largest SAH cost, surface area x objects below, opened until there
    // are `width` (small subtrees are opened too while there is room: lanes are tested
    // together anyway). The greedy form of a cost-driven collapse (Ylitie, Karras & Laine
    // 2017 solve it exactly by dynamic programming): the child a random ray is most likely
    // to enter AND that costs most once entered is the one worth flattening. Against the
    // largest area alone (Wald, Benthin & Boulos 2008): 1.17 -> 1.08x Embree's time on the
    // 1e6 sphere, 1.51 -> 1.44x on the 1e6 soup (docs/experiments/bvh-rays.md, the collapse
    // by SAH cost). Returns how many.
    template <class Tree>
    static std::size_t open_children(const Tree& tree, typename Tree::node_index n,
                                     const std::vector<std::size_t>& objects_below,
                                     std::array<typename Tree::node_index, width>& kids) {
        std::size_t k = 2;
        kids[0] = tree.left(n);
        kids[1] = tree.left(n) + 1;
        while (k < width) {
            std::size_t best = width;
            double best_cost = -1;
            for (std::size_t i = 0; i < k; ++i) {
                if (tree.is_leaf(kids[i])) continue;
                const double cost = half_area(tree, kids[i]) * static_cast<double>(objects_below[kids[i]]);
                if (cost > best_cost) best_cost = cost, best = i;
            }
            if (best == width) break;
            const auto opened = kids[best];
            kids[best] = tree.left(opened);
            kids[k++] = tree.left(opened) + 1;
        }
        return k;
    }
    // Collapses the binary subtree of inner node `top` into `nodes`, whose entry 0 (already
    // there) becomes top's wide node, depth first from a stack: a node's inner children get
    // consecutive indices when it is filled, and the last one is filled next. This order is
    // the layout's, on every core too. take(task) is told of each node as it is taken and says
    // whether to fill it (false: its subtree is not entered; collapse_on_every_core defers it).
    template <class Tree, class Nodes, class Take>
    static void collapse(const Tree& tree, typename Tree::node_index top, const std::vector<std::size_t>& objects_below,
                         Nodes& nodes, Take&& take) {
        using node_index = typename Tree::node_index;
        std::vector<collapse_task<node_index>> todo{{top, 0}};
        while (!todo.empty()) {
            const collapse_task<node_index> tk = todo.back();
            todo.pop_back();
            if (!take(tk)) continue;
            std::array<node_index, width> kids{};
            const std::size_t k = open_children(tree, tk.binary, objects_below, kids);
            fill_node(tree, nodes, tk.wide, kids, k, objects_below, todo);
        }
    }
    // collapse()'s take for a whole (sub)tree: fills every node, appending each but the top (0)
    // to fill_order, the order in which pass 2 of build gathers the leaves.
    static auto filling(std::vector<std::uint32_t>& fill_order) {
        return [&fill_order](const auto& task) {
            if (task.wide != 0) fill_order.push_back(task.wide);
            return true;
        };
    }
    // Subtrees of at most this many objects are collapsed on their own by collapse_on_every_core.
    static constexpr std::size_t collapse_grain = 1024;
    // collapse() of the whole tree on every core of the parallel back end, to the same nodes
    // in the same order. Because the work list is a stack, collapse() finishes a node's whole
    // subtree before it takes the next node from below it: the wide nodes of a subtree are
    // one run of indices, allocated when its top is taken. So: (1) the top of the tree, the
    // nodes above more than collapse_grain objects, is collapsed in collapse()'s order with
    // provisional indices, recording each node as it is taken; a smaller subtree is recorded
    // and not entered; (2) those subtrees are collapsed concurrently, each into its own array;
    // (3) replaying the record gives every node its index (a top node's inner children the
    // next indices, a small subtree's nodes the next run, its size known from (2)); (4) the
    // nodes are copied to their indices, the subtrees concurrently.
    template <class Tree>
    void collapse_on_every_core(const Tree& tree, const std::vector<std::size_t>& objects_below,
                                std::vector<std::uint32_t>& fill_order) {
        using node_index = typename Tree::node_index;
        struct taken {
            std::uint32_t provisional;  // index in nodes_ (the top's nodes)
            std::size_t subtree;        // index in subtrees, or npos for a top node
        };
        constexpr std::size_t npos = ~std::size_t{0};
        struct subtree {
            node_index top{};              // its binary top
            std::vector<wide_node> nodes;  // [0]: the top's wide node
            std::vector<std::uint32_t> fill_order;
            std::uint32_t first = 0;  // the index of its nodes [1, size) in the layout
        };
        // (1) The top.
        std::vector<taken> record;
        std::vector<subtree> subtrees;
        collapse(tree, tree.root(), objects_below, nodes_, [&](const collapse_task<node_index>& tk) {
            if (tk.wide != 0 && objects_below[tk.binary] <= collapse_grain) {
                record.push_back({tk.wide, subtrees.size()});
                subtrees.emplace_back().top = tk.binary;
                return false;
            }
            record.push_back({tk.wide, npos});
            return true;
        });
        // (2) The subtrees.
        detail::parallel_chunks(subtrees.size(), 1, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                subtrees[i].nodes.push_back(wide_node{});
                collapse(tree, subtrees[i].top, objects_below, subtrees[i].nodes, filling(subtrees[i].fill_order));
            }
        });
        // (3) The indices.
        const auto is_inner_lane = [](const wide_node& nd, std::size_t i) {
            return ((nd.lanes >> i) & 1u) != 0 && nd.count[i] == 0;
        };
        std::vector<std::uint32_t> final_index(nodes_.size(), 0);
        std::size_t next = 1;
        for (const taken& t : record) {
            if (t.subtree != npos) {
                subtrees[t.subtree].first = static_cast<std::uint32_t>(next);
                next += subtrees[t.subtree].nodes.size() - 1;
                continue;
            }
            const wide_node& nd = nodes_[t.provisional];
            for (std::size_t i = 0; i < width; ++i)
                if (is_inner_lane(nd, i)) final_index[nd.child[i]] = static_cast<std::uint32_t>(next++);
        }
        // (4) The nodes, and the order they were filled in.
        const auto renumbered = [&](const wide_node& from, auto&& index_of) {
            wide_node nd = from;
            for (std::size_t i = 0; i < width; ++i)
                if (is_inner_lane(nd, i)) nd.child[i] = index_of(nd.child[i]);
            return nd;
        };
        ray_vector<wide_node> out(next);
        for (const taken& t : record)
            if (t.subtree == npos)
                out[final_index[t.provisional]] =
                    renumbered(nodes_[t.provisional], [&](std::uint32_t c) { return final_index[c]; });
        detail::parallel_chunks(record.size(), 64, [&](std::size_t b, std::size_t e) {
            for (std::size_t r = b; r < e; ++r) {
                if (record[r].subtree == npos) continue;
                const subtree& st = subtrees[record[r].subtree];
                const auto local = [&](std::uint32_t c) { return st.first + c - 1; };
                out[final_index[record[r].provisional]] = renumbered(st.nodes[0], local);
                for (std::size_t j = 1; j < st.nodes.size(); ++j) out[local(static_cast<std::uint32_t>(j))] = renumbered(st.nodes[j], local);
            }
        });
        for (const taken& t : record) {
            if (t.provisional != 0) fill_order.push_back(final_index[t.provisional]);
            if (t.subtree != npos)
                for (const std::uint32_t j : subtrees[t.subtree].fill_order) fill_order.push_back(subtrees[t.subtree].first + j - 1);
        }
        nodes_ = std::move(out);
    }
    // Objects below every binary node (indexed by node), without recursion (a degenerate
    // tree can be as deep as it has nodes): each node's subtree listed parents first, then
    // counted children first. With `parallel`, the top levels are listed first (at most 64
    // nodes deep enough to have a few subtrees per core), and the subtrees below them are
    // listed and counted concurrently; the counts are the same.
    template <class Tree>
    static std::vector<std::size_t> subtree_object_counts(const Tree& tree, bool parallel = false) {
        using node_index = typename Tree::node_index;
        std::vector<node_index> top{tree.root()};  // parents before children
        std::vector<node_index> roots;             // the subtrees below the top
        if (parallel) {
            std::size_t level = 0;
            while (level < top.size() && top.size() - level < 64) {
                const std::size_t end = top.size();
                for (; level < end; ++level)
                    if (!tree.is_leaf(top[level])) top.push_back(tree.left(top[level])), top.push_back(tree.left(top[level]) + 1);
            }
            roots.assign(top.begin() + static_cast<std::ptrdiff_t>(level), top.end());
            top.resize(level);
        } else {
            roots = std::move(top);
            top.clear();
        }
        std::vector<std::vector<node_index>> orders(roots.size());
        std::vector<std::size_t> largest(roots.size(), 0);
        const auto list = [&](std::size_t b, std::size_t e) {
            for (std::size_t r = b; r < e; ++r) {
                std::vector<node_index>& order = orders[r];
                order.push_back(roots[r]);
                for (std::size_t i = 0; i < order.size(); ++i) {
                    const auto n = order[i];
                    largest[r] = std::max<std::size_t>(largest[r], n);
                    if (!tree.is_leaf(n)) order.push_back(tree.left(n)), order.push_back(tree.left(n) + 1);
                }
            }
        };
        std::size_t size = 0;
        for (const node_index n : top) size = std::max<std::size_t>(size, n);
        if (parallel) detail::parallel_chunks(roots.size(), 1, list);
        else list(0, roots.size());
        for (const std::size_t l : largest) size = std::max(size, l);
        std::vector<std::size_t> count(size + 1, 0);
        const auto count_below = [&](const std::vector<node_index>& order) {
            for (std::size_t i = order.size(); i-- > 0;) {
                const auto n = order[i];
                count[n] = tree.is_leaf(n) ? tree.leaf_size(n) : count[tree.left(n)] + count[tree.left(n) + 1];
            }
        };
        const auto count_range = [&](std::size_t b, std::size_t e) {
            for (std::size_t r = b; r < e; ++r) count_below(orders[r]);
        };
        if (parallel) detail::parallel_chunks(roots.size(), 1, count_range);
        else count_range(0, roots.size());
        count_below(top);
        return count;
    }
    // Fills wide node `at` with the binary nodes kids[0, k): quantises their boxes, marks leaf
    // lanes (a leaf, or a subtree of at most merged_leaf_objects objects; their objects are
    // stored by pass 2 of build) and queues a wide node for every other lane.
    template <class Tree, class Nodes, class Task>
    static void fill_node(const Tree& tree, Nodes& nodes, std::size_t at, const std::array<typename Tree::node_index, width>& kids,
                          std::size_t k, const std::vector<std::size_t>& objects_below, std::vector<Task>& todo) {
        // The quantisation frame per axis: origin = the union's lower corner rounded down to
        // float; 2^e the smallest power of two (a normal float) with 255 2^e >= the union's
        // extent from origin, rounded up.
        wide_node& nd = nodes[at];
        for (std::size_t a = 0; a < D; ++a) {
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (std::size_t i = 0; i < k; ++i) {
                lo = std::min(lo, static_cast<double>(tree.lower(kids[i], a)));
                hi = std::max(hi, static_cast<double>(tree.upper(kids[i], a)));
            }
            const float origin = detail_rounding::round_down<float>(lo);
            const double span = detail_rounding::next_up(hi - static_cast<double>(origin));
            int e = -126;
            if (span > 0) {
                std::frexp(detail_rounding::next_up(span / 255), &e);  // span / 255 < 2^e
                e = std::max(e, -126);
            }
            nd.origin[a] = origin;
            nd.exponent[a] = static_cast<std::int8_t>(e);
            for (std::size_t i = 0; i < k; ++i) {
                // Lower plane rounded down, upper rounded up; both within [0, 255] because
                // origin <= lower and upper - origin <= span <= 255 2^e.
                const double l =
                    std::max(0.0, detail_rounding::next_down(static_cast<double>(tree.lower(kids[i], a)) - origin));
                const double h = detail_rounding::next_up(static_cast<double>(tree.upper(kids[i], a)) - origin);
                nd.q_lo[a][i] = static_cast<std::uint8_t>(std::floor(std::ldexp(l, -e)));
                nd.q_hi[a][i] = static_cast<std::uint8_t>(std::min(255.0, std::ceil(std::ldexp(h, -e))));
            }
        }
        for (std::size_t i = 0; i < k; ++i) {  // by index from here: nodes may grow (and move)
            const std::size_t objects = objects_below[kids[i]];
            if (objects == 0) continue;  // an empty leaf (possible after erasures) is no lane
            nodes[at].lanes |= static_cast<std::uint8_t>(1u << i);
            if (tree.is_leaf(kids[i]) || objects <= merged_leaf_objects) {
                // Pass 2 of build replaces the binary node by the leaf's first object.
                nodes[at].child[i] = static_cast<std::uint32_t>(kids[i]);
                nodes[at].count[i] = static_cast<std::uint8_t>(objects);
            } else {
                const auto w = static_cast<std::uint32_t>(nodes.size());
                nodes[at].child[i] = w;
                nodes[at].count[i] = 0;
                todo.push_back({kids[i], w});
                nodes.push_back(wide_node{});
            }
        }
    }
    // Stores the objects below binary node n (at most 255: a leaf or a merged subtree): their
    // copies, or their blocks (padded with copies of the block's first object, which are
    // never tested), and their slot ids.
    // Reused between the leaves one thread gathers (a leaf's binary subtree and its slots).
    template <class NodeIndex>
    struct gather_scratch {
        std::vector<NodeIndex> stack;
        std::vector<std::uint32_t> leaf_slots;
    };
    // The slots of binary subtree n's objects, in order, into scratch.leaf_slots.
    template <class Tree>
    static void subtree_slots(const Tree& tree, typename Tree::node_index n,
                              gather_scratch<typename Tree::node_index>& scratch) {
        scratch.stack.assign(1, n);
        scratch.leaf_slots.clear();
        while (!scratch.stack.empty()) {
            const auto m = scratch.stack.back();
            scratch.stack.pop_back();
            if (!tree.is_leaf(m)) {
                scratch.stack.push_back(tree.left(m) + 1);
                scratch.stack.push_back(tree.left(m));
                continue;
            }
            for (std::size_t j = 0; j < tree.leaf_size(m); ++j)
                scratch.leaf_slots.push_back(static_cast<std::uint32_t>(tree.leaf_slot(m, j)));
        }
    }
    // A leaf lane's blocks from forms_[first / form_lanes] on (the last padded with its first
    // object of the block). Only thick rays need the objects themselves: they read them from
    // the container.
    template <class Tree>
    void gather_forms(const Tree& tree, typename Tree::node_index n, std::size_t first,
                      gather_scratch<typename Tree::node_index>& scratch) requires has_ray_forms {
        subtree_slots(tree, n, scratch);
        const auto& slots = scratch.leaf_slots;
        typename ray_form::block* out = &forms_[first / form_lanes];
        for (std::size_t j = 0; j < slots.size(); j += form_lanes, ++out)
            for (std::size_t lane = 0; lane < form_lanes; ++lane) {
                const std::uint32_t s = slots[j + lane < slots.size() ? j + lane : j];
                ray_form::set(*out, lane, tree.value(s), s);
            }
    }
    // A leaf lane's copies of its objects and their slots, appended (objects without forms).
    template <class Tree>
    void gather_objects(const Tree& tree, typename Tree::node_index n, gather_scratch<typename Tree::node_index>& scratch) {
        subtree_slots(tree, n, scratch);
        for (const std::uint32_t s : scratch.leaf_slots) {
            objects_.push_back(tree.value(s));
            slots_.push_back(s);
        }
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
    // On transparent huge pages where available: see core/huge_page_allocator.hpp.
    template <class E>
    using ray_vector = std::vector<E, huge_page_allocator<E>>;
    ray_vector<wide_node> nodes_;
    ray_vector<O> objects_;  // empty with compact ray forms
    ray_vector<std::uint32_t> slots_;  // empty with compact ray forms (their blocks hold the ids)
    struct no_forms {
        void clear() {}
    };
    std::conditional_t<has_ray_forms, ray_vector<typename ray_form::block>, no_forms> forms_;
    double magnitude_ = 0;
    bool usable_ = false;
    bool in_place_ = false;  // leaves_in_place()
    // Leaf lanes checked or gathered per task on every core.
    static constexpr std::size_t leaf_grain = 1024;
};

}  // namespace spatial::bvh_detail
