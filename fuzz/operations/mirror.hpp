#pragma once
// A structure under test and the brute-force oracle holding the same objects, with a handle
// table that pairs each stored object's iterator in the structure with its iterator in the
// oracle. Every mutation is applied to both and the table follows it, so answers can be
// compared by identity (which stored object was returned), not only by value: a structure
// that returns a wrong copy of an equal object, an erased object, or one object twice is
// caught. Only bulk insertion returns no iterators; after it the table is rebuilt by matching
// equal values (equal objects are interchangeable).
//
// Mutations offered: insert, hinted insert (hint: a stored object, end(), or an erased one,
// which the contract accepts), bulk insert, erase by iterator (its returned successor
// checked), by value, by range, single and batched motion where the structure has them, clear.

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "answer_comparison.hpp"
#include "operation_log.hpp"
#include "value_text.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/object_geometry.hpp"

namespace spatial_fuzz {

template <class C>
class mirror {
public:
    using O = typename C::value_type;
    using Q = spatial::point_type_of<O>;
    using oracle_type = spatial::brute_force<O>;
    using mine_iterator = typename C::iterator;
    using oracle_iterator = typename oracle_type::iterator;
    struct element {
        mine_iterator mine;
        oracle_iterator oracle;
    };

    // `name` tells the two mirrors of a run apart in the trace.
    mirror(const operation_log& log, std::string_view name) : log_(log), name_(name) {}

    const C& mine() const { return mine_; }
    C& mine() { return mine_; }
    const oracle_type& oracle() const { return oracle_; }
    oracle_type& oracle() { return oracle_; }
    const std::vector<element>& live() const { return live_; }
    std::size_t size() const { return live_.size(); }

    // Points on the stored objects (a point; a box's two extreme corners), of the first few:
    // what value_source reuses for equal, collinear and coplanar points and rays through vertices.
    std::vector<Q> anchors() const {
        std::vector<Q> out;
        for (std::size_t i = 0; i < live_.size() && i < 32; ++i) {
            Q lo{}, hi{};
            for (std::size_t d = 0; d < C::dimension; ++d)
                lo[d] = spatial::object_lower(*live_[i].mine, d), hi[d] = spatial::object_upper(*live_[i].mine, d);
            out.push_back(lo);
            if (!(hi == lo)) out.push_back(hi);
        }
        return out;
    }

    // The oracle slot of each structure slot that holds a stored object (no_slot elsewhere).
    std::vector<spatial::slot_index> oracle_slots() const {
        std::vector<spatial::slot_index> map(mine_.end().slot(), spatial::no_slot);
        for (const element& e : live_) map[e.mine.slot()] = e.oracle.slot();
        return map;
    }
    // The oracle slot of an iterator the structure returned; a finding unless it is stored.
    spatial::slot_index oracle_slot(const std::vector<spatial::slot_index>& map, mine_iterator it) const {
        log_.require(it.slot() < map.size() && map[it.slot()] != spatial::no_slot,
                     "the structure returned an iterator to no stored object");
        return map[it.slot()];
    }

    // What a rejected call must leave as it was: the slot and bounds (lower, then upper) of
    // every stored object in iteration order, and end()'s slot. Taken before every insertion,
    // so it is built of fixed-size arrays (one allocation, not one per object).
    using bounds_type = std::array<typename C::scalar_type, 2 * C::dimension>;
    using state_type = std::pair<std::vector<std::pair<spatial::slot_index, bounds_type>>, spatial::slot_index>;
    state_type state() const {
        state_type st{{}, mine_.end().slot()};
        st.first.reserve(mine_.size());
        for (auto it = mine_.begin(); it != mine_.end(); ++it) {
            bounds_type b;
            for (std::size_t d = 0; d < C::dimension; ++d)
                b[d] = spatial::object_lower(*it, d), b[C::dimension + d] = spatial::object_upper(*it, d);
            st.first.emplace_back(it.slot(), b);
        }
        return st;
    }

    void insert(const O& v) {
        log_.trace([&] { return name_ + " " + value_text(v); });
        const mine_iterator it = mine_.insert(v);
        live_.push_back({it, oracle_.insert(v)});
        log_.require(*live_.back().mine == v, "insert returned an iterator to another value");
    }
    // Hint `choice`: a stored object, end(), or an erased object's iterator.
    void insert_hinted(std::size_t choice, const O& v) requires spatial::spatial_container<C> {
        const std::size_t options = live_.size() + 1 + erased_.size();
        choice %= options;
        log_.trace([&] { return name_ + " " + value_text(v) + " hint " + std::to_string(choice) + " of " + std::to_string(options); });
        const mine_iterator hint = choice < live_.size()       ? live_[choice].mine
                                   : choice == live_.size()    ? mine_.end()
                                                               : erased_[choice - live_.size() - 1];
        const mine_iterator it = mine_.insert(hint, v);
        live_.push_back({it, oracle_.insert(v)});
        log_.require(*live_.back().mine == v, "hinted insert returned an iterator to another value");
    }
    void insert_bulk(const std::vector<O>& batch) {
        log_.trace([&] {
            std::string s = name_ + " " + std::to_string(batch.size()) + ":";
            for (const O& v : batch) s += " " + value_text(v);
            return s;
        });
        mine_.insert(batch.begin(), batch.end());
        oracle_.insert(batch.begin(), batch.end());
        erased_.clear();  // a bulk build may lay the slots out afresh: old iterators mean nothing
        rematch();
    }

    void erase_at(std::size_t i) {
        const element gone = live_[i];
        log_.trace([&] { return name_ + " " + value_text(*gone.mine) + " at slot " + std::to_string(gone.mine.slot()); });
        mine_iterator expected_next = mine_.end();  // the next stored object in slot order
        for (const element& e : live_)
            if (e.mine.slot() > gone.mine.slot() && e.mine.slot() < expected_next.slot()) expected_next = e.mine;
        const mine_iterator next = mine_.erase(gone.mine);
        log_.require(next == expected_next, "erase(pos) did not return the next object in iteration order");
        oracle_.erase(gone.oracle);
        live_.erase(live_.begin() + static_cast<std::ptrdiff_t>(i));
        remember_erased(gone.mine);
    }
    void erase_value(const O& v) requires spatial::spatial_container<C> {
        log_.trace([&] { return name_ + " " + value_text(v); });
        const auto equal = [&](const element& e) { return *e.oracle == v; };
        live_.erase(std::remove_if(live_.begin(), live_.end(), equal), live_.end());  // before they dangle
        const std::size_t erased = mine_.erase(v);
        log_.require(erased == oracle_.erase(v), "erase(value) erased another number of objects than the oracle");
        log_.require(oracle_.size() == live_.size(), "the oracle lost track of erase(value)");
    }
    // Erases `count` objects from the `first`-th in the structure's iteration order.
    void erase_range(std::size_t first, std::size_t count) requires spatial::spatial_container<C> {
        log_.trace([&] { return name_ + " from " + std::to_string(first) + " count " + std::to_string(count); });
        auto from = mine_.begin();
        for (std::size_t k = 0; k < first && from != mine_.end(); ++k) ++from;
        auto to = from;
        std::vector<spatial::slot_index> doomed;
        for (std::size_t k = 0; k < count && to != mine_.end(); ++k, ++to) doomed.push_back(to.slot());
        mine_.erase(from, to);
        std::sort(doomed.begin(), doomed.end());
        std::vector<element> kept;
        for (const element& e : live_) {
            if (std::binary_search(doomed.begin(), doomed.end(), e.mine.slot())) oracle_.erase(e.oracle);
            else kept.push_back(e);
        }
        log_.require(kept.size() + doomed.size() == live_.size(), "erase(first, last): the range held unknown objects");
        live_ = std::move(kept);
    }

    // Moves the i-th object to v (update, or bvh's reinsert when `reinsert`).
    void update_at(std::size_t i, const O& v, bool reinsert) requires spatial::single_motion<C> {
        element& e = live_[i];
        log_.trace([&] { return name_ + " " + value_text(*e.mine) + " to " + value_text(v) + (reinsert ? " by reinsert" : ""); });
        mine_iterator same = e.mine;
        if constexpr (requires { mine_.reinsert(e.mine, v); }) {
            same = reinsert ? mine_.reinsert(e.mine, v) : mine_.update(e.mine, v);
        } else {
            same = mine_.update(e.mine, v);
        }
        log_.require(same == e.mine && *same == v, "update did not keep the handle or did not store the value");
        oracle_.erase(e.oracle);
        e.oracle = oracle_.insert(v);
    }
    // Moves the objects at distinct `indices` to `values` in one batch, with `strategy` where the
    // structure takes one.
    void update_batch(const std::vector<std::size_t>& indices, const std::vector<O>& values,
                      spatial::motion_strategy strategy) requires spatial::batched_motion<C> {
        spatial::motion_batch<C> moves;
        for (std::size_t k = 0; k < indices.size(); ++k) moves.emplace_back(live_[indices[k]].mine, values[k]);
        log_.trace([&] {
            std::string s = name_ + " strategy " + std::string(spatial::to_string(strategy)) + ":";
            for (const auto& [it, v] : moves) s += " " + value_text(*it) + " to " + value_text(v) + ";";
            return s;
        });
        if constexpr (spatial::motion_with_strategy<C>) {
            const auto applied = mine_.update(moves.begin(), moves.end(), strategy);
            log_.require(strategy == spatial::motion_strategy::automatic ? applied != strategy : applied == strategy,
                         "update(first, last, strategy) reported another strategy");
        } else {
            mine_.update(moves.begin(), moves.end());
        }
        for (std::size_t k = 0; k < indices.size(); ++k) {
            element& e = live_[indices[k]];
            log_.require(*e.mine == values[k], "update(first, last) did not store a value");
            oracle_.erase(e.oracle);
            e.oracle = oracle_.insert(values[k]);
        }
    }

    void clear() {
        log_.trace([&] { return name_; });
        mine_.clear();
        oracle_.clear();
        live_.clear();
        erased_.clear();
    }

    // The structure, the oracle and the handle table hold as many objects.
    void check_sizes() const {
        log_.require(mine_.size() == live_.size() && oracle_.size() == live_.size(), "sizes differ from the oracle's");
    }
    // Sizes agree and the structure's own invariant check passes; with `full`, also every
    // handle pair holds equal values and the contents are equal as multisets.
    void check(bool full) const {
        check_sizes();
        if constexpr (requires { mine_.check_invariants(); }) {
            const std::string problem = mine_.check_invariants();
            log_.require(problem.empty(), "check_invariants: " + problem);
        }
        if (!full) return;
        for (const element& e : live_) log_.require(*e.mine == *e.oracle, "a handle refers to another value than the oracle's");
        log_.require(spatial_test::contents(mine_) == spatial_test::contents(oracle_), "contents differ from the oracle's");
    }

private:
    // After a bulk insert: pair the structure's objects with the oracle's by equal values.
    // Each side is sorted by signature, computed once per object (a signature is a vector: in
    // the comparator it would be built O(n log n) times, most of a soak's time).
    void rematch() {
        const auto by_signature = [](auto& container) {
            std::vector<std::pair<std::vector<double>, decltype(container.begin())>> out;
            for (auto it = container.begin(); it != container.end(); ++it) out.emplace_back(spatial_test::signature(*it), it);
            std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
            return out;
        };
        const auto ms = by_signature(mine_);
        const auto os = by_signature(oracle_);
        log_.require(ms.size() == os.size(), "bulk insert: sizes differ from the oracle's");
        live_.clear();
        for (std::size_t k = 0; k < ms.size(); ++k) {
            log_.require(*ms[k].second == *os[k].second, "bulk insert: contents differ from the oracle's");
            live_.push_back({ms[k].second, os[k].second});
        }
    }
    void remember_erased(mine_iterator it) {
        if (erased_.size() == 8) erased_.erase(erased_.begin());
        erased_.push_back(it);
    }

    const operation_log& log_;
    std::string name_;
    C mine_;
    oracle_type oracle_;
    std::vector<element> live_;
    std::vector<mine_iterator> erased_;  // iterators of erased objects: hints the contract accepts
};

}  // namespace spatial_fuzz
