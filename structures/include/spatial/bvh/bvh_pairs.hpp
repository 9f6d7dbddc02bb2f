#pragma once
// spatial::bvh — collision pairs (collide/pairs.hpp): self_pairs and pairs_with by descending
// the tree against itself or against another bvh of the same type, opening the larger node of
// each overlapping pair (Gottschalk, Lin & Manocha 1996 descend two OBB trees this way).

#include "spatial/bvh/bvh.hpp"

namespace spatial {

template <stored_object O, class BV, class Config>
inline auto bvh<O, BV, Config>::self_pairs(pair_filter filter) const -> std::vector<std::pair<iterator, iterator>> {
    require_fresh(site("self_pairs"));
    stats_ = {};
    std::vector<std::pair<iterator, iterator>> out;
    if (slots_.size() < 2) return out;
    auto emit = [&](slot_index s, slot_index t) {
        if (!leaf_objects_may_meet(slots_.value(s), slots_.value(t))) return;
        ++stats_.objects_tested;
        if (s > t) std::swap(s, t);
        if (filter == pair_filter::candidates || collide::narrow_phase(slots_.value(s), slots_.value(t)))
            out.emplace_back(make(s), make(t));
    };
    std::vector<std::pair<node_index, node_index>> todo{{root, root}};
    while (!todo.empty()) {
        const auto [a, b] = todo.back();
        todo.pop_back();
        const node& na = nodes_[a];
        if (a == b) {
            if (na.leaf) {
                const slot_index* blk = block(na.first);
                for (std::uint32_t i = 0; i < na.count; ++i)
                    for (std::uint32_t j = i + 1; j < na.count; ++j) emit(blk[i], blk[j]);
            } else {
                todo.push_back({na.first, na.first + 1});
                todo.push_back({na.first + 1, na.first + 1});
                todo.push_back({na.first, na.first});
            }
            continue;
        }
        descend_pair(*this, a, b, todo, [&](const node& x, const node& y) {
            const slot_index* bx = block(x.first);
            const slot_index* by = block(y.first);
            for (std::uint32_t i = 0; i < x.count; ++i)
                for (std::uint32_t j = 0; j < y.count; ++j) emit(bx[i], by[j]);
        });
    }
    sort_pairs(out);
    return out;
}

template <stored_object O, class BV, class Config>
template <class Other>
inline auto bvh<O, BV, Config>::pairs_with(const Other& other, pair_filter filter) const
    -> std::vector<std::pair<iterator, typename Other::iterator>> {
    if constexpr (!std::is_same_v<Other, bvh>) {
        return pairs_between(*this, other, filter);
    } else {
        require_fresh(site("pairs_with"));
        other.require_fresh(site("pairs_with"));
        stats_ = {};
        std::vector<std::pair<iterator, iterator>> out;
        if (slots_.size() == 0 || other.slots_.size() == 0) return out;
        std::vector<std::pair<node_index, node_index>> todo{{root, root}};
        while (!todo.empty()) {
            const auto [a, b] = todo.back();
            todo.pop_back();
            descend_pair(other, a, b, todo, [&](const node& x, const node& y) {
                const slot_index* bx = block(x.first);
                const slot_index* by = other.block(y.first);
                for (std::uint32_t i = 0; i < x.count; ++i)
                    for (std::uint32_t j = 0; j < y.count; ++j) {
                        if (!leaf_objects_may_meet(slots_.value(bx[i]), other.slots_.value(by[j]))) continue;
                        ++stats_.objects_tested;
                        if (filter == pair_filter::candidates ||
                            collide::narrow_phase(slots_.value(bx[i]), other.slots_.value(by[j])))
                            out.emplace_back(make(bx[i]), other.make(by[j]));
                    }
            });
        }
        sort_pairs(out);
        return out;
    }
}

// ---- collision descent ----------------------------------------------------------------
// One step of the two-tree descent for node a of *this and node b of `other`: nothing when
// their boxes or volumes are disjoint, leaves(x, y) for two leaves, otherwise the larger
// inner node is opened (both children paired with the other node).
template <stored_object O, class BV, class Config>
template <class Leaves>
inline void bvh<O, BV, Config>::descend_pair(const bvh& other, node_index a, node_index b,
                                              std::vector<std::pair<node_index, node_index>>& todo,
                                              Leaves&& leaves) const {
    const node& na = nodes_[a];
    const node& nb = other.nodes_[b];
    ++stats_.nodes_visited;
    if (!box_of(na).overlaps(box_of(nb))) return;
    if constexpr (!volume_is_box)
        if (!na.volume.overlaps(nb.volume)) return;
    if (na.leaf && nb.leaf) {
        leaves(na, nb);
        return;
    }
    const bool open_a = nb.leaf || (!na.leaf && box_of(na).surface_area() >= box_of(nb).surface_area());
    if (open_a) {
        todo.push_back({na.first, b});
        todo.push_back({na.first + 1, b});
    } else {
        todo.push_back({a, nb.first});
        todo.push_back({a, nb.first + 1});
    }
}

// Inside overlapping leaves, an aabb tree carries its test down to the objects: a pair is
// a candidate only when the objects' boxes overlap (closed), as the octree and kd_tree
// filter their leaves. Its leaves hold up to 4 triangles when the SAH counts blocks
// (sah_block), and without the filter every pair of them would reach the narrow phase.
// Other volumes pass every pair of their (per-object SAH, small) leaves on.
template <stored_object O, class BV, class Config>
template <class A, class B>
inline bool bvh<O, BV, Config>::leaf_objects_may_meet(const A& a, const B& b) {
    if constexpr (volume_is_box)
        return object_boxes_overlap(a, b);
    else
        return true;
}

}  // namespace spatial
