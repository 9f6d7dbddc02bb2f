#pragma once
// Our containers behind harness::point_index: kd_tree (any config) and brute_force.
// The adapters add only the id bookkeeping the harness needs for dynamic workloads; it is
// NOT counted in memory_bytes (a user of the container would hold their own iterators).

#include <algorithm>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/point_index.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/kdtree/kd_tree.hpp"

namespace harness {

template <class Container, class T, std::size_t D>
class container_index : public point_index<T, D> {
public:
    using point_type = spatial::point<T, D>;
    using iterator = typename Container::iterator;

    explicit container_index(std::string name) : name_(std::move(name)) {}
    std::string name() const override { return name_; }
    unsigned capabilities() const override {
        const unsigned batched = spatial::batched_knn<Container> ? static_cast<unsigned>(capability::batched_knn) : 0u;
        return capability::knn | capability::approximate_knn | capability::radius | capability::dynamic |
               capability::hinted_insert | capability::bulk_insert | capability::bulk_erase | batched;
    }
    // Only the container's own build is timed; the id bookkeeping for dynamic workloads is
    // set up lazily from the caller's array (kept alive by the caller, see point_index).
    void build(std::span<const point_type> pts) override {
        c_.clear();
        c_.insert(pts.begin(), pts.end());
        built_from_ = pts;
        point_of_.clear();
        by_id_.clear();
        known_.clear();
        unresolved_.clear();
        ids_pending_ = true;
        slot_points_.clear();
    }
    std::size_t memory_bytes() const override { return c_.memory_bytes(); }
    void knn(const point_type& q, std::size_t k, T eps, std::vector<neighbor<T>>& out) override {
        out.clear();
        if constexpr (spatial::candidate_knn<Container>) {
            c_.find_nearest_candidates(q, k, eps, cand_);
            for (const auto& c : cand_) out.push_back({c.distance_squared, c.slot});
        } else {
            for (auto it : c_.find_nearest(q, k, eps)) out.push_back({spatial::squared_distance(*it, q), it.slot()});
        }
    }
    std::size_t knn_batch(std::span<const point_type> queries, std::size_t k, spatial::query_order order, bool parallel,
                          std::vector<neighbor<T>>& out) override {
        if constexpr (spatial::batched_knn<Container>) {
            const auto found = parallel ? c_.find_nearest_batch(queries, k, T(0), order, spatial::par)
                                        : c_.find_nearest_batch(queries, k, T(0), order);
            out.resize(found.size() * found.per_query());
            auto at = out.begin();
            for (std::size_t q = 0; q < found.size(); ++q) {
                const auto items = found.neighbors(q);
                const auto d2 = found.distances_squared(q);
                for (std::size_t j = 0; j < items.size(); ++j) *at++ = {d2[j], items[j].slot()};
            }
            return found.per_query();
        } else {
            return point_index<T, D>::knn_batch(queries, k, order, parallel, out);
        }
    }
    void radius(const point_type& q, T r, std::vector<neighbor<T>>& out) override {
        out.clear();
        if constexpr (spatial::candidate_ball<Container>) {
            // The distances the search computed, into a buffer kept between queries (as the
            // peers' are): looking every point up again was a second pass over a large ball.
            c_.find_in_ball_candidates(q, r, cand_);
            for (const auto& c : cand_) out.push_back({c.distance_squared, c.slot});
        } else {
            for (auto it : c_.find_in_ball(q, r)) out.push_back({spatial::squared_distance(*it, q), it.slot()});
        }
    }
    void insert(std::uint32_t id, const point_type& p) override {
        if (ids_pending_) resolve_ids();
        slot_points_.clear();
        remember(id, c_.insert(p));
    }
    void insert_near(std::uint32_t prev_id, std::uint32_t id, const point_type& p) override {
        resolve_ids();
        slot_points_.clear();
        const bool have_hint = prev_id < known_.size() && known_[prev_id];
        remember(id, c_.insert(have_hint ? by_id_[prev_id] : c_.end(), p));
    }
    void insert_bulk(std::uint32_t first_id, std::span<const point_type> pts) override {
        if (ids_pending_) resolve_ids();
        slot_points_.clear();
        c_.insert(pts.begin(), pts.end());
        for (std::uint32_t i = 0; i < pts.size(); ++i) {
            grow(first_id + i);
            point_of_[first_id + i] = pts[i];
            unresolved_.push_back(first_id + i);  // bulk insert returns no iterators
        }
    }
    void erase(std::uint32_t id) override {
        resolve_ids();
        if (id >= known_.size() || !known_[id]) throw std::logic_error(name_ + ": erase of unknown id");
        slot_points_.clear();
        c_.erase(by_id_[id]);
        known_[id] = 0;
    }
    // Resolve ids of bulk-inserted points by matching coordinates with elements no id owns
    // (equal values are interchangeable, so any pairing of duplicates is correct).
    // O(n log n); the harness calls it before timing dynamic operations.
    void prepare_dynamic() override { resolve_ids(); }
    void resolve_ids() {
        if (ids_pending_) {  // ids 0..n-1 of the last build()
            ids_pending_ = false;
            const std::size_t n = built_from_.size();
            grow(static_cast<std::uint32_t>(std::max<std::size_t>(n, 1) - 1));
            std::copy(built_from_.begin(), built_from_.end(), point_of_.begin());
            for (std::uint32_t i = 0; i < n; ++i) unresolved_.push_back(i);
        }
        if (unresolved_.empty()) return;
        std::vector<char> owned(c_.end().slot(), 0);
        for (std::size_t id = 0; id < known_.size(); ++id)
            if (known_[id]) owned[by_id_[id].slot()] = 1;
        // Both sides sorted by coordinates, each point copied beside its id or element: sorting
        // indices through a comparator that looks the points up missed the cache on every
        // comparison (a third of the knn suite's bulk comparisons at 1e6, untimed but waited for).
        std::vector<std::pair<point_type, iterator>> free_elems;
        for (auto it = c_.begin(); it != c_.end(); ++it)
            if (!owned[it.slot()]) free_elems.push_back({*it, it});
        std::vector<std::pair<point_type, std::uint32_t>> wanted;
        wanted.reserve(unresolved_.size());
        for (const std::uint32_t id : unresolved_) wanted.push_back({point_of_[id], id});
        const auto by_point = [](const auto& a, const auto& b) { return a.first.coords < b.first.coords; };
        std::sort(wanted.begin(), wanted.end(), by_point);
        std::sort(free_elems.begin(), free_elems.end(), by_point);
        if (free_elems.size() != wanted.size()) throw std::logic_error(name_ + ": id bookkeeping lost track");
        for (std::size_t i = 0; i < wanted.size(); ++i) {
            if (!(free_elems[i].first == wanted[i].first)) throw std::logic_error(name_ + ": id mismatch");
            by_id_[wanted[i].second] = free_elems[i].second;
            known_[wanted[i].second] = 1;
        }
        unresolved_.clear();
    }
    std::size_t size() const override { return c_.size(); }
    // Reported ids are slot handles: the element in that slot, from a slot -> point table built
    // by one pass over the container after each change (a harness table, not counted).
    std::optional<point_type> point_of(std::uint32_t slot) override {
        if (slot_points_.empty() && !c_.empty()) {
            slot_points_.assign(c_.end().slot(), std::nullopt);
            for (auto it = c_.begin(); it != c_.end(); ++it) slot_points_[it.slot()] = *it;
        }
        return slot < slot_points_.size() ? slot_points_[slot] : std::nullopt;
    }
    long long last_nodes_visited() const override {
        if constexpr (spatial::reports_query_stats<Container>) return static_cast<long long>(c_.last_query_stats().nodes_visited);
        return -1;
    }

    Container& container() { return c_; }

private:
    void grow(std::uint32_t id) {
        if (by_id_.size() <= id) {
            by_id_.resize(id + 1);
            known_.resize(id + 1, 0);
            point_of_.resize(id + 1);
        }
    }
    // point_of_ is only needed for ids awaiting resolution (bulk-inserted), so a single
    // insertion does not write it.
    void remember(std::uint32_t id, iterator it) {
        grow(id);
        by_id_[id] = it;
        known_[id] = 1;
    }

    std::string name_;
    Container c_;
    std::vector<point_type> point_of_;  // the point each id was given
    std::vector<iterator> by_id_;
    std::vector<char> known_;
    std::vector<std::uint32_t> unresolved_;
    std::span<const point_type> built_from_;
    bool ids_pending_ = false;
    std::vector<spatial::neighbor_candidate<T>> cand_;  // knn()'s and radius()'s answer buffer, reused
    std::vector<std::optional<point_type>> slot_points_;  // point_of's table; empty: stale
};

template <class T, std::size_t D>
using kd_tree_index = container_index<spatial::kd_tree<spatial::point<T, D>>, T, D>;
template <class T, std::size_t D>
using kd_tree_stats_index =
    container_index<spatial::kd_tree<spatial::point<T, D>,
                                     spatial::kd_tree_config<spatial::kd_tree_config<>::leaf_capacity,
                                                             spatial::kd_tree_config<>::splitter, true>>,
                    T, D>;

// The kd_tree at another leaf capacity, for the tuning sweep (harness/tuning_sweep.hpp): the
// capacity is a template argument, so only the capacities listed here exist (each one more
// instantiation of the tree); another is std::invalid_argument.
template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_kd_tree_index_with_leaf_capacity(std::size_t leaf_capacity) {
    auto make = [&]<std::size_t L>() -> std::unique_ptr<point_index<T, D>> {
        return std::make_unique<container_index<
            spatial::kd_tree<spatial::point<T, D>, spatial::kd_tree_config<L, spatial::kd_tree_config<>::splitter>>, T, D>>(
            "kd_tree");
    };
    switch (leaf_capacity) {
        case 8: return make.template operator()<8>();
        case 16: return make.template operator()<16>();
        case 32: return make.template operator()<32>();
        case 64: return make.template operator()<64>();
        default:
            throw std::invalid_argument("kd_tree: leaf_capacity " + std::to_string(leaf_capacity) +
                                        " is not one of the swept capacities 8, 16, 32, 64");
    }
}

template <class T, std::size_t D>
struct brute_force_index : container_index<spatial::brute_force<spatial::point<T, D>>, T, D> {
    brute_force_index() : container_index<spatial::brute_force<spatial::point<T, D>>, T, D>("brute_force") {}
};

}  // namespace harness
