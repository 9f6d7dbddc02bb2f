#pragma once
// spatial::bvh — ray casts: the public casts, the generic front-to-back traversal that every
// volume type uses, and the two fast paths for BV = aabb (the slab traversal and the wide
// ray layout of bvh/wide_ray_layout.hpp). Rays go front-to-back by the entry parameter of
// each child's volume, pruned by the best hit so far; the three paths give the same answers.

#include "spatial/bvh/bvh.hpp"

namespace spatial {

// ---- ray cast --------------------------------------------------------------------
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::intersect_object(const point_type& origin, const point_type& direction,
                                                 scalar_type thickness, info_type& info) const -> iterator {
    validate_ray(origin, direction, thickness);
    require_fresh(site("intersect"));
    bvh_stats st;
    const slot_index hit = cast_ray(origin, direction, thickness, info, st);
    stats_ = st;
    return make(hit);
}

template <stored_object O, class BV, class Config>
template <class Policy>
inline void bvh<O, BV, Config>::intersect_batch(std::span<const ray<point_type>> rays, std::span<iterator> hits,
                                                 std::span<info_type> infos, Policy) const {
    if (hits.size() != rays.size() || infos.size() != rays.size())
        throw std::invalid_argument(detail::site_text(site("intersect_batch")) + ": rays, hits and infos differ in size");
    for (const auto& r : rays) validate_ray(r.origin, r.direction, r.thickness);
    require_fresh(site("intersect_batch"));
    // Once, before the threads start.
    if constexpr (std::is_same_v<Policy, parallel_policy>) prepare_rays(par);
    else prepare_rays();
    auto cast_range = [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
            bvh_stats st;
            hits[i] = make(cast_ray(rays[i].origin, rays[i].direction, rays[i].thickness, infos[i], st));
        }
    };
    if constexpr (std::is_same_v<Policy, parallel_policy>) detail::parallel_chunks(rays.size(), 256, cast_range);
    else cast_range(0, rays.size());
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::prepare_rays() const {
    if constexpr (wide_rays)
        if (!stale_ && slots_.size() > 0) (void)wide_.get([this] { return make_wide_layout(); });
}
template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::prepare_rays(parallel_policy) const {
    if constexpr (wide_rays)
        if (!stale_ && slots_.size() > 0) (void)wide_.get([this] { return make_wide_layout(true); });
}

template <stored_object O, class BV, class Config>
inline void bvh<O, BV, Config>::validate_ray(const point_type& origin, const point_type& direction,
                                              scalar_type thickness) const {
    detail::require_finite(origin, site("intersect"), "ray origin");
    detail::require_nonzero_direction(direction, site("intersect"));
    detail::require_nonnegative(thickness, site("intersect"), "ray thickness");
}
// The slot of the first object hit (capacity() when none); st receives the statistics.
// The callers have validated the ray and checked that the tree is fresh.
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::cast_ray(const point_type& origin, const point_type& direction, scalar_type thickness,
                                          info_type& info, bvh_stats& st) const -> slot_index {
    const auto none = static_cast<slot_index>(slots_.capacity());
    if (slots_.size() == 0) return none;
    if constexpr (wide_rays) {
        typename wide_layout::float_ray r;
        const wide_layout& w = wide_.get([this] { return make_wide_layout(); });
        // slack(origin) with the root box's magnitude that the layout measured once when it
        // was built (the same value: a maximum of the same absolute values), not read from
        // the root box at every ray: a fixed cost of every ray, which decides rays that miss
        // the mesh (results/checks/ray_hits_and_misses).
        T m = static_cast<T>(w.scene_magnitude());
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, std::abs(static_cast<T>(origin[i])));
        const T grow = thickness * (1 + 16 * eps) + slack_for_magnitude(m);
        if (w.accepts(to_bv(origin).coords, to_bv(direction).coords, grow, r))
            return intersect_wide(w, r, origin, direction, thickness, info, st);
    }
    const T grow = thickness * (1 + 16 * eps) + slack(origin);
    if constexpr (volume_is_box)
        if (reciprocals_finite(direction)) return intersect_boxes(origin, direction, thickness, grow, info, st);
    const bv_point o = to_bv(origin), d = to_bv(direction);
    slot_index hit = no_slot;
    struct entry {
        node_index n;
        T t;
    };
    bvh_detail::traversal_stack<entry> stack;
    T t0 = 0, t1 = 0;
    if (!enter(root, o, d, grow, info.hit_time, t0, t1)) return none;
    stack.push({root, t0});
    while (!stack.empty()) {
        const entry e = stack.pop();
        if (e.t > info.hit_time) continue;
        ++st.nodes_visited;
        const node& nd = nodes_[e.n];
        if (nd.leaf) {
            const slot_index* b = block(nd.first);
            for (std::uint32_t i = 0; i < nd.count; ++i) {
                ++st.objects_tested;
                if (slots_.value(b[i]).intersect(origin, direction, thickness, info)) hit = b[i];
            }
            continue;
        }
        T a0 = 0, a1 = 0, b0 = 0, b1 = 0;
        const bool ha = enter(nd.first, o, d, grow, info.hit_time, a0, a1);
        const bool hb = enter(nd.first + 1, o, d, grow, info.hit_time, b0, b1);
        if (ha && hb) {  // push the farther first: the nearer is popped first
            if (a0 <= b0) stack.push({nd.first + 1, b0}), stack.push({nd.first, a0});
            else stack.push({nd.first, a0}), stack.push({nd.first + 1, b0});
        } else if (ha) {
            stack.push({nd.first, a0});
        } else if (hb) {
            stack.push({nd.first + 1, b0});
        }
    }
    return hit == no_slot ? none : hit;
}

// The child's grown ray interval clipped to [0, tmax]; false when it misses.
template <stored_object O, class BV, class Config>
inline bool bvh<O, BV, Config>::enter(node_index n, const bv_point& o, const bv_point& d, T grow, T tmax, T& t0,
                                       T& t1) const {
    const node& nd = nodes_[n];
    if (!bvh_detail::grown_ray_interval(nd.volume, box_of(nd), o, d, grow, t0, t1)) return false;
    if (t1 < 0 || t0 > tmax) return false;
    t0 = std::max(t0, T(0));
    return true;
}

// ---- the ray path for BV = aabb ------------------------------------------------------
// The same traversal and the same answers as the generic path, organised as in fast ray
// tracers (Williams, Barrus, Morley & Shirley 2005, "An efficient and robust ray-box
// intersection algorithm"; Wald, Boulos & Shirley 2007, "Ray tracing deformable scenes
// using dynamic bounding volume hierarchies"):
//  * per ray, once: the inverse direction and the direction's sign per axis, so a slab
//    test is two subtractions and two multiplications (no division, no swap) — the near
//    plane is hi when the direction is negative (-0 included: 1 / -0 = -inf);
//  * both children of a node are tested from the parent; the nearer one is visited
//    directly, the farther is pushed only if it is hit, with its entry parameter so it is
//    dropped unopened when a closer hit has been found meanwhile;
//  * the counters of last_query_stats() live in registers and are stored once.
// A zero direction component makes 1/d infinite: an origin strictly inside the grown slab
// gives (-inf, +inf), outside gives an empty interval, and on its boundary 0 * inf = NaN,
// which the comparisons below ignore (the slab imposes nothing: correct, the ray lies in
// the closed slab). Multiplying by a rounded reciprocal adds one rounding to each slab
// parameter; the grown box's slack (16 eps times the magnitudes, see slack_of) dwarfs
// those few eps, so no box the exact test would enter is ever skipped.
template <stored_object O, class BV, class Config>
struct bvh<O, BV, Config>::box_ray {
    std::array<T, D> origin, inverse;
    std::array<bool, D> negative;
    T grow;
};
// A nonzero component so small (subnormal) that 1/d overflows would make the slab
// parameters infinite where the exact ones are merely huge; such rays take the generic
// path, which divides.
template <stored_object O, class BV, class Config>
inline bool bvh<O, BV, Config>::reciprocals_finite(const point_type& d) {
    for (std::size_t i = 0; i < D; ++i) {
        const T c = static_cast<T>(d[i]);
        if (c != 0 && !std::isfinite(T(1) / c)) return false;
    }
    return true;
}
// The grown box's ray interval clipped to [0, tmax]; t0 is its entry. NaN-proof: a NaN
// slab parameter fails both comparisons and leaves the interval unchanged.
template <stored_object O, class BV, class Config>
inline bool bvh<O, BV, Config>::slab_entry(const box_type& b, const box_ray& r, T tmax, T& t0) {
    T lo = 0, hi = tmax;
    for (std::size_t i = 0; i < D; ++i) {
        const T near_plane = r.negative[i] ? b.hi[i] + r.grow : b.lo[i] - r.grow;
        const T far_plane = r.negative[i] ? b.lo[i] - r.grow : b.hi[i] + r.grow;
        const T tn = (near_plane - r.origin[i]) * r.inverse[i];
        const T tf = (far_plane - r.origin[i]) * r.inverse[i];
        lo = tn > lo ? tn : lo;
        hi = tf < hi ? tf : hi;
    }
    t0 = lo;
    return lo <= hi;
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::intersect_boxes(const point_type& origin, const point_type& direction, T thickness,
                                                 T grow, info_type& info, bvh_stats& st) const -> slot_index {
    box_ray r;
    for (std::size_t i = 0; i < D; ++i) {
        r.origin[i] = static_cast<T>(origin[i]);
        r.inverse[i] = T(1) / static_cast<T>(direction[i]);
        r.negative[i] = std::signbit(static_cast<T>(direction[i]));
    }
    r.grow = grow;
    std::size_t visited = 0, tested = 0;
    slot_index hit = no_slot;
    // An object type may offer a per-ray preparation (objects::triangle does: the shear of
    // the watertight test); it must give the same answers as the plain call.
    auto test_leaf = [&](const node& nd, const auto& ray) {
        const slot_index* b = block(nd.first);
        for (std::uint32_t i = 0; i < nd.count; ++i) {
            bool h;
            if constexpr (requires { typename O::prepared_ray; })
                h = this->slots_.value(b[i]).intersect(ray, thickness, info);
            else
                h = this->slots_.value(b[i]).intersect(origin, direction, thickness, info);
            if (h) hit = b[i];
        }
        tested += nd.count;
    };
    auto traverse = [&](const auto& ray) {
        struct entry {
            node_index n;
            T t;
        };
        bvh_detail::traversal_stack<entry> stack;
        T t_root;
        if (!slab_entry(nodes_[root].volume, r, info.hit_time, t_root)) return;
        node_index n = root;
        for (;;) {
            const node& nd = nodes_[n];
            ++visited;
            if (nd.leaf) {
                test_leaf(nd, ray);
            } else {
                T ta, tb;
                const bool ha = slab_entry(nodes_[nd.first].volume, r, info.hit_time, ta);
                const bool hb = slab_entry(nodes_[nd.first + 1].volume, r, info.hit_time, tb);
                if (ha && hb) {
                    if (ta <= tb) {
                        stack.push({nd.first + 1, tb});
                        n = nd.first;
                    } else {
                        stack.push({nd.first, ta});
                        n = nd.first + 1;
                    }
                    continue;
                }
                if (ha || hb) {
                    n = ha ? nd.first : nd.first + 1;
                    continue;
                }
            }
            // Next: the nearest pending node whose entry is not beyond the best hit.
            for (;;) {
                if (stack.empty()) return;
                const entry e = stack.pop();
                if (e.t <= info.hit_time) {
                    n = e.n;
                    break;
                }
            }
        }
    };
    if constexpr (requires { typename O::prepared_ray; })
        traverse(typename O::prepared_ray(origin, direction));
    else
        traverse(0);
    st.nodes_visited = visited;
    st.objects_tested = tested;
    return hit == no_slot ? static_cast<slot_index>(slots_.capacity()) : hit;
}

// ---- the wide ray layout (BV = aabb) --------------------------------------------------
// The binary tree as wide_ray_layout::build reads it.
template <stored_object O, class BV, class Config>
struct bvh<O, BV, Config>::binary_view {
    using node_index = typename bvh::node_index;
    const bvh& t;
    node_index root() const { return bvh::root; }
    bool is_leaf(node_index n) const { return t.nodes_[n].leaf; }
    node_index left(node_index n) const { return t.nodes_[n].first; }
    T lower(node_index n, std::size_t a) const { return box_of(t.nodes_[n]).lo[a]; }
    T upper(node_index n, std::size_t a) const { return box_of(t.nodes_[n]).hi[a]; }
    std::size_t leaf_size(node_index n) const { return t.nodes_[n].count; }
    std::size_t object_count() const { return t.slots_.size(); }
    slot_index leaf_slot(node_index n, std::size_t i) const { return t.block(t.nodes_[n].first)[i]; }
    const O& value(slot_index s) const { return t.slots_.value(s); }
};
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::make_wide_layout(bool parallel) const -> wide_layout {
    wide_layout w;
    w.build(binary_view{*this}, parallel, ray_leaves);
    return w;
}
template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::intersect_wide(const wide_layout& w, const typename wide_layout::float_ray& r,
                                                const point_type& origin, const point_type& direction, T thickness,
                                                info_type& info, bvh_stats& st) const -> slot_index {
    std::size_t visited = 0, tested = 0;
    typename wide_layout::object_index hit;
    using object_index = typename wide_layout::object_index;
    // Leaves tested object by object, in order: test(i) is the exact test of object i;
    // in_place_objects: the container's objects, which leaves in place refer to (nullptr for
    // leaves of the layout).
    auto one_by_one = [&](auto&& test, auto in_place_objects) {
        return w.intersect(
            r, info,
            [&](object_index first, std::size_t count) {
                object_index h = wide_layout::no_object;
                for (object_index i = first; i < first + count; ++i)
                    if (test(i)) h = i;
                return h;
            },
            visited, tested, in_place_objects);
    };
    // Leaves in place refer to consecutive slots (object index = slot): the stored objects
    // tested where they are, one by one (gathering triangles into SIMD blocks on the stack
    // took longer than testing them one at a time: docs/structures/bvh.md). Compiled only
    // for configurations that ask for it, so the default's traversal is not made larger.
    const auto in_place = [&] {
        if constexpr (ray_leaves == bvh_ray_leaves::in_place) {
            if (!w.leaves_in_place()) return false;
            if constexpr (requires { typename O::prepared_ray; }) {
                const typename O::prepared_ray ray(origin, direction);
                hit = one_by_one([&](object_index i) { return slots_.value(i).intersect(ray, thickness, info); },
                                 slots_.data());
            } else {
                hit = one_by_one(
                    [&](object_index i) { return slots_.value(i).intersect(origin, direction, thickness, info); },
                    slots_.data());
            }
            return true;
        } else {
            return false;
        }
    };
    if (in_place()) {
        // answered on the container's objects
    } else if constexpr (wide_layout::has_ray_forms) {
        // Thin rays on the compact blocks alone; thick rays on the stored objects.
        const typename O::prepared_ray ray(origin, direction);
        if (thickness == T(0))
            hit = w.intersect(
                r, info,
                [&](object_index first, std::size_t count) { return w.intersect_forms(first, count, ray, info); },
                visited, tested);
        else
            hit = one_by_one(
                [&](object_index i) { return slots_.value(w.slot_of(i)).intersect(ray, thickness, info); }, nullptr);
    } else if constexpr (requires { typename O::prepared_ray; }) {
        const typename O::prepared_ray ray(origin, direction);
        hit = one_by_one([&](object_index i) { return w.object(i).intersect(ray, thickness, info); }, nullptr);
    } else {
        hit = one_by_one([&](object_index i) { return w.object(i).intersect(origin, direction, thickness, info); },
                         nullptr);
    }
    st.nodes_visited = visited;
    st.objects_tested = tested;
    st.wide_ray_layout = true;
    st.wide_leaves_in_place = w.leaves_in_place();
    return hit == wide_layout::no_object ? static_cast<slot_index>(slots_.capacity()) : w.slot_of(hit);
}

}  // namespace spatial
