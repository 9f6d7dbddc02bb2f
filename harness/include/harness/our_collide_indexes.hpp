#pragma once
// Any of our containers of boxes behind harness::collide_index — the same interface as the
// peers (harness/collide_adapters.hpp), so the collide suite and the scene runner time and
// validate ours and theirs by one code path.
//
// build(): a bulk insert of the boxes (the container's best build). Box i keeps its handle
// (iterator) for the container's life, so pairs map back to indices.
// update(): the moved boxes, restored as `motion` says:
//   * bvh: bvh::update(first, last, strategy) — refit, rebuild, reinsert or automatic;
//   * collision_grid: its bulk update(first, last), O(m); sweep_and_prune: update(pos, v), O(1) each;
//   * the others (kd_tree, octree, grids): erase + insert of every moved box (their
//     incremental path), or with motion = rebuild, clear + bulk insert.
// self_pairs(): the container's self_pairs(exact) (boxes: the narrow phase is the box test),
// mapped to indices, sorted.

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "harness/collide_index.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/collide/pairs.hpp"
#include "spatial/core/motion.hpp"
#include "spatial/objects/box.hpp"

namespace harness {

using collide_box3 = spatial::objects::box<double, 3>;

inline collide_box3 to_object(const collide_box& b) {
    collide_box3 o;
    o.lo = b.lo;
    o.hi = b.hi;
    return o;
}

template <class Container>
class container_collide_index final : public collide_index {
public:
    static_assert(std::is_same_v<typename Container::value_type, collide_box3>,
                  "container_collide_index: the container must store spatial::objects::box<double, 3>");
    container_collide_index(std::string name, spatial::motion_strategy motion = spatial::motion_strategy::automatic)
        : name_(std::move(name)), motion_(motion) {}
    std::string name() const override { return name_; }

    void build(std::span<const collide_box> boxes) override {
        std::vector<collide_box3> objects;
        objects.reserve(boxes.size());
        for (const auto& b : boxes) objects.push_back(to_object(b));
        c_.clear();
        c_.insert(objects.begin(), objects.end());
        map_handles(objects);
    }
    void update(std::span<const collide_box> boxes) override {
        if (boxes.size() != handles_.size()) throw std::invalid_argument(name_ + ": update() with a different count");
        if constexpr (spatial::motion_with_strategy<Container>) {
            moves_.clear();
            for (std::size_t i = 0; i < boxes.size(); ++i) moves_.emplace_back(handles_[i], to_object(boxes[i]));
            last_motion_ = c_.update(moves_.begin(), moves_.end(), motion_);
        } else if constexpr (spatial::batched_motion<Container>) {  // collision_grid: bulk O(m)
            moves_.clear();
            for (std::size_t i = 0; i < boxes.size(); ++i) moves_.emplace_back(handles_[i], to_object(boxes[i]));
            c_.update(moves_.begin(), moves_.end());
            last_motion_ = spatial::motion_strategy::reinsert;
        } else if constexpr (spatial::single_motion<Container>) {
            for (std::size_t i = 0; i < boxes.size(); ++i) c_.update(handles_[i], to_object(boxes[i]));
            last_motion_ = spatial::motion_strategy::reinsert;
        } else if (motion_ == spatial::motion_strategy::rebuild) {
            build(boxes);
            last_motion_ = spatial::motion_strategy::rebuild;
        } else {
            for (std::size_t i = 0; i < boxes.size(); ++i) {
                c_.erase(handles_[i]);
                handles_[i] = c_.insert(to_object(boxes[i]));
            }
            remap_slots();
            last_motion_ = spatial::motion_strategy::reinsert;
        }
    }
    std::vector<index_pair> self_pairs(const exact_test& exact = {}) override {
        std::vector<index_pair> out;
        out.reserve(last_pair_count_);
        auto add = [&](const auto& a, const auto& b) {
            std::uint32_t i = index_of(a.slot()), j = index_of(b.slot());
            if (i > j) std::swap(i, j);
            if (!exact || exact(i, j)) out.emplace_back(i, j);
        };
        // An unsorted callback when the container has one (collision_grid): the pairs are
        // sorted once, by index, instead of by slot and then again by index.
        if constexpr (spatial::streamed_self_pairs<Container>)
            c_.for_each_self_pair(spatial::pair_filter::exact, add);
        else
            for (const auto& [a, b] : c_.self_pairs(spatial::pair_filter::exact)) add(a, b);
        sort_unique_pairs(out);
        last_pair_count_ = out.size();
        return out;
    }
    std::vector<index_pair> pairs_with(std::span<const collide_box> others, const exact_test& exact = {}) override {
        Container other;
        std::vector<collide_box3> objects;
        for (const auto& b : others) objects.push_back(to_object(b));
        other.insert(objects.begin(), objects.end());
        std::vector<std::uint32_t> other_index(other.end().slot() + 1, 0);
        std::uint32_t k = 0;
        for (auto it = other.begin(); it != other.end(); ++it) other_index[it.slot()] = k++;
        std::vector<index_pair> out;
        for (const auto& [a, b] : c_.pairs_with(other, spatial::pair_filter::exact)) {
            const std::uint32_t i = index_of_slot_[a.slot()], j = other_index[b.slot()];
            if (!exact || exact(i, j)) out.emplace_back(i, j);
        }
        sort_unique_pairs(out);
        return out;
    }
    std::size_t memory_bytes() const override { return c_.memory_bytes(); }

    const Container& container() const { return c_; }
    Container& container() { return c_; }
    // What the last update() ran (automatic resolves to refit, rebuild or reinsert).
    spatial::motion_strategy last_motion() const { return last_motion_; }

private:
    // After a bulk insert into an empty container most of our containers iterate in
    // insertion order (slots are allocated in order): checked in O(n). Otherwise (kd_tree
    // stores slots in its own order) handles are matched to boxes by value: both sorted
    // lexicographically, O(n log n). Identical boxes are interchangeable (they have the same
    // partners), so the index pair set does not depend on how they are matched.
    void map_handles(const std::vector<collide_box3>& objects) {
        handles_.clear();
        for (auto it = c_.begin(); it != c_.end(); ++it) handles_.push_back(it);
        if (handles_.size() != objects.size()) throw std::logic_error(name_ + ": the container lost boxes");
        bool in_order = true;
        for (std::size_t i = 0; i < objects.size() && in_order; ++i) in_order = *handles_[i] == objects[i];
        if (!in_order) {
            auto key = [](const collide_box3& b) { return std::pair(b.lo, b.hi); };
            std::vector<std::uint32_t> order(objects.size());
            for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
            std::sort(order.begin(), order.end(), [&](auto a, auto b) { return key(objects[a]) < key(objects[b]); });
            auto found = handles_;
            std::sort(found.begin(), found.end(), [&](const auto& a, const auto& b) { return key(*a) < key(*b); });
            for (std::size_t k = 0; k < order.size(); ++k) {
                if (!(*found[k] == objects[order[k]])) throw std::logic_error(name_ + ": stored boxes differ from the input");
                handles_[order[k]] = found[k];
            }
        }
        remap_slots();
    }
    void remap_slots() {
        std::uint32_t top = 0;
        for (const auto& h : handles_) top = std::max(top, static_cast<std::uint32_t>(h.slot()));
        index_of_slot_.assign(static_cast<std::size_t>(top) + 1, 0);
        slots_are_indices_ = true;
        for (std::uint32_t i = 0; i < handles_.size(); ++i) {
            index_of_slot_[handles_[i].slot()] = i;
            slots_are_indices_ &= handles_[i].slot() == i;
        }
    }
    // Box i is in slot i after a bulk build of most containers: no lookup per pair then.
    std::uint32_t index_of(std::size_t slot) const {
        return slots_are_indices_ ? static_cast<std::uint32_t>(slot) : index_of_slot_[slot];
    }

    std::string name_;
    spatial::motion_strategy motion_, last_motion_ = spatial::motion_strategy::refit;
    Container c_;
    std::vector<typename Container::iterator> handles_;
    std::vector<std::uint32_t> index_of_slot_;
    bool slots_are_indices_ = false;
    std::size_t last_pair_count_ = 0;  // the last answer's size: the next one's reservation
    std::vector<std::pair<typename Container::iterator, collide_box3>> moves_;
};

}  // namespace harness
