#pragma once
// spatial::octree — cell geometry: an object's bounding box and centre, cells and loose cells
// (a cell scaled by Config::loose_factor about its centre, Ulrich 2000), which child a centre
// falls in, whether a loose cell contains a box, the squared distance to a loose cell, and
// whether a cell may still be split.

#include "spatial/octree/octree.hpp"

namespace spatial {

template <stored_object O, class Config>
inline auto octree<O, Config>::extent_of(const O& x) -> extent {
    extent e;
    for (std::size_t i = 0; i < D; ++i) {
        e.lo[i] = object_lower(x, i);
        e.hi[i] = object_upper(x, i);
        e.c[i] = object_center(x, i);
    }
    return e;
}

template <stored_object O, class Config>
inline void octree<O, Config>::merge_into(extent& a, const extent& b) {
    for (std::size_t i = 0; i < D; ++i) {
        a.lo[i] = std::min(a.lo[i], b.lo[i]);
        a.hi[i] = std::max(a.hi[i], b.hi[i]);
    }
}

template <stored_object O, class Config>
inline bool octree<O, Config>::loose_contains(const node& nd, const extent& e) {
    for (std::size_t i = 0; i < D; ++i)
        if (e.lo[i] < nd.llo[i] || e.hi[i] > nd.lhi[i]) return false;
    return true;
}

// Squared distance from q to the loose cell (0 inside); same arithmetic as a box object's.
template <stored_object O, class Config>
inline auto octree<O, Config>::cell_distance2(const node& nd, const coords& q) -> T {
    return box_squared_distance<T, D>(q, nd.llo, nd.lhi);
}

// Sets the cell and the loose cell (the cell scaled by k about its centre).
template <stored_object O, class Config>
inline void octree<O, Config>::set_cell(node& nd, const coords& lo, T size) {
    nd.lo = lo;
    nd.size = size;
    const T extra = static_cast<T>((Config::loose_factor - 1.0) / 2.0) * size;
    for (std::size_t i = 0; i < D; ++i) {
        nd.llo[i] = lo[i] - extra;
        nd.lhi[i] = lo[i] + size + extra;
    }
}

template <stored_object O, class Config>
inline auto octree<O, Config>::mid(const node& nd, std::size_t i) -> T { return nd.lo[i] + nd.size / 2; }

template <stored_object O, class Config>
inline std::size_t octree<O, Config>::child_bits(const node& nd, const coords& c) {
    std::size_t b = 0;
    for (std::size_t i = 0; i < D; ++i)
        if (c[i] >= mid(nd, i)) b |= std::size_t(1) << i;
    return b;
}

template <stored_object O, class Config>
inline auto octree<O, Config>::geometry_of(const node& nd) -> node {
    node g;
    g.lo = nd.lo;
    g.size = nd.size;
    g.llo = nd.llo;
    g.lhi = nd.lhi;
    return g;
}

// Whether a child of nd would still be a meaningful cell.
template <stored_object O, class Config>
inline bool octree<O, Config>::may_split(const node& nd) const {
    const T half = nd.size / 2;
    const T floor_by_depth = std::ldexp(nodes_[root_].size, -static_cast<int>(Config::max_depth));
    T magnitude = 0;
    for (std::size_t i = 0; i < D; ++i)
        magnitude = std::max({magnitude, std::abs(nd.lo[i]), std::abs(nd.lo[i] + nd.size)});
    return half >= floor_by_depth && half > 64 * std::numeric_limits<T>::epsilon() * magnitude &&
           half > std::numeric_limits<T>::min();
}

// Sets c's cell to the child cell b (bit i set: the upper half along axis i) of `parent`
// (a node or its geometry_of), and its loose cell clipped to the parent's, so that loose
// cells nest exactly despite rounding.
template <stored_object O, class Config>
inline void octree<O, Config>::set_child_cell(node& c, const node& parent, std::size_t b) {
    coords lo = parent.lo;
    for (std::size_t i = 0; i < D; ++i)
        if ((b >> i) & 1) lo[i] = mid(parent, i);
    set_cell(c, lo, parent.size / 2);
    for (std::size_t i = 0; i < D; ++i) {
        c.llo[i] = std::max(c.llo[i], parent.llo[i]);
        c.lhi[i] = std::min(c.lhi[i], parent.lhi[i]);
    }
}

// The child of nd that would take the object, or fanout if it stays in nd.
template <stored_object O, class Config>
inline std::size_t octree<O, Config>::target_of(const node& nd, const extent& e) const {
    const std::size_t b = child_bits(nd, e.c);
    node probe;
    set_child_cell(probe, nd, b);
    return loose_contains(probe, e) ? b : fanout;
}
}  // namespace spatial
