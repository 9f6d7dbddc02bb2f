// nanoflann (Debian's libnanoflann-dev 1.4.3) behind harness::point_index<T, D>.
//
// Two adapters share this translation unit, the only one that includes <nanoflann.hpp>:
//   nanoflann          KDTreeSingleIndexAdaptor         (static; build O(n log n))
//   nanoflann_dynamic  KDTreeSingleIndexDynamicAdaptor  (logarithmic method of Bentley &
//                      Saxe, "Decomposable searching problems I: static-to-dynamic
//                      transformation", J. Algorithms 1980: a forest of static trees of
//                      sizes 2^i; insert O(log^2 n) amortised, lazy deletion)
//
// Conventions converted here (nanoflann 1.4.x -> point_index):
//   * eps: nanoflann prunes a subtree when mindist^2 * (1 + eps_nf) > worst^2, i.e. its eps
//     multiplies SQUARED distance; ours multiplies distance, so eps_nf = (1 + eps)^2 - 1.
//   * radius: its RadiusResultSet and leaf test keep d^2 < radius (open ball, and radius is
//     squared); we pass nextafter(r^2, +inf) so every d^2 <= r^2 is kept (closed ball).
//   * k = 0: KNNResultSet::worstDist() reads dists[capacity - 1], so capacity 0 is out of
//     bounds; we return an empty answer. k > size: capacity min(k, size), size results.
//   * Distances reported are nanoflann's own squared distances (sum of squared coordinate
//     differences in T, the same order as a naive loop).
//   * Ties: nanoflann's result set keeps the first of equal distances it meets; answers are
//     compared by distance, never by id, so any tie order is correct.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// nanoflann 1.4.3's dynamic adaptor copies a prototype sub-index whose root_bbox was never
// initialised (KDTreeSingleIndexDynamicAdaptor::init); GCC's -Wmaybe-uninitialized reports
// it at our call site although it is harmless (the box is written before any use).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <nanoflann.hpp>
#pragma GCC diagnostic pop

#include "harness/adapters.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {
namespace {


// Dataset adaptor: nanoflann reads coordinates through it. It points at a vector the
// adapter owns, so the adapter (heap-allocated by the factory, never moved) outlives it.
template <class T, std::size_t D>
struct point_cloud {
    const std::vector<spatial::point<T, D>>* pts = nullptr;

    std::size_t kdtree_get_point_count() const { return pts->size(); }
    T kdtree_get_pt(std::size_t idx, std::size_t dim) const { return (*pts)[idx][dim]; }
    // No precomputed box: nanoflann computes it in one pass over the points.
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};

template <class T, std::size_t D>
using l2_metric = nanoflann::L2_Simple_Adaptor<T, point_cloud<T, D>, T, std::uint32_t>;

template <class T>
void check_eps(T eps) {
    if (!(eps >= T(0))) throw std::invalid_argument("nanoflann adapter: eps must be >= 0, got " + std::to_string(eps));
}

// Our eps multiplies distance; nanoflann's multiplies squared distance.
template <class T>
float nanoflann_eps(T eps) {
    const double e = static_cast<double>(eps);
    return static_cast<float>((1.0 + e) * (1.0 + e) - 1.0);
}

// nanoflann keeps d^2 < radius: the next float above r^2 makes the ball closed.
template <class T>
T closed_radius_squared(T r) {
    if (std::isnan(r)) throw std::invalid_argument("nanoflann adapter: radius is NaN");
    return std::nextafter(r * r, std::numeric_limits<T>::infinity());
}

// ---------------------------------------------------------------------------------------
// Static index.
template <class T, std::size_t D>
class nanoflann_static_index final : public point_index<T, D> {
    using point_type = typename point_index<T, D>::point_type;
    using cloud_type = point_cloud<T, D>;
    using tree_type = nanoflann::KDTreeSingleIndexAdaptor<l2_metric<T, D>, cloud_type,
                                                          static_cast<std::int32_t>(D), std::uint32_t>;

public:
    // leaf_max_size: the registry's setting (nanoflann's default, 10) or a tuning sweep's.
    explicit nanoflann_static_index(std::size_t leaf_max_size) : leaf_max_size_(leaf_max_size) { cloud_.pts = &points_; }
    nanoflann_static_index(const nanoflann_static_index&) = delete;
    nanoflann_static_index& operator=(const nanoflann_static_index&) = delete;

    std::string name() const override { return "nanoflann"; }
    unsigned capabilities() const override {
        return capability::knn | capability::approximate_knn | capability::radius;
    }

    void build(std::span<const point_type> pts) override {
        tree_.reset();  // it references points_: drop it before they change
        points_.assign(pts.begin(), pts.end());
        // nanoflann 1.4's constructor builds the index.
        tree_ = std::make_unique<tree_type>(static_cast<int>(D), cloud_,
                                            nanoflann::KDTreeSingleIndexAdaptorParams(leaf_max_size_));
    }

    // The point copy the dataset adaptor exposes + nanoflann's usedMemory (node pool, used
    // and wasted, plus the n-entry index permutation vAcc).
    std::size_t memory_bytes() const override {
        std::size_t bytes = sizeof(*this) + points_.capacity() * sizeof(point_type);
        if (tree_) bytes += sizeof(tree_type) + tree_->usedMemory(*tree_);
        return bytes;
    }

    void knn(const point_type& q, std::size_t k, T eps, std::vector<neighbor<T>>& out) override {
        out.clear();
        check_eps(eps);
        const std::size_t capacity = std::min(k, points_.size());
        if (capacity == 0 || !tree_) return;
        ids_.resize(capacity);
        dists_.resize(capacity);
        nanoflann::KNNResultSet<T, std::uint32_t, std::size_t> result(capacity);
        result.init(ids_.data(), dists_.data());
        tree_->findNeighbors(result, q.coords.data(), nanoflann::SearchParams(32, nanoflann_eps(eps)));
        out.resize(result.size());
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = {dists_[i], ids_[i]};
    }

    void radius(const point_type& q, T r, std::vector<neighbor<T>>& out) override {
        out.clear();
        const T r2 = closed_radius_squared(r);
        if (r < T(0) || points_.empty() || !tree_) return;
        nanoflann::RadiusResultSet<T, std::uint32_t> result(r2, matches_);
        tree_->findNeighbors(result, q.coords.data(), nanoflann::SearchParams());
        out.reserve(matches_.size());
        for (const auto& [id, d2] : matches_) out.push_back({d2, id});
    }

    std::size_t size() const override { return points_.size(); }
    std::optional<point_type> point_of(std::uint32_t id) override {
        return id < points_.size() ? std::optional<point_type>(points_[id]) : std::nullopt;
    }

private:
    std::vector<point_type> points_;
    std::size_t leaf_max_size_;
    cloud_type cloud_;
    std::unique_ptr<tree_type> tree_;
    // Per-query scratch, kept to avoid an allocation per query.
    std::vector<std::uint32_t> ids_;
    std::vector<T> dists_;
    std::vector<std::pair<std::uint32_t, T>> matches_;
};

// ---------------------------------------------------------------------------------------
// Dynamic index.
//
// nanoflann 1.4.3's KDTreeSingleIndexDynamicAdaptor names points by their dataset index and
// silently assumes those indices are 0, 1, 2, ... in insertion order and never reused:
//   * addPoints(start, end) writes treeIndex[pointCount] (pointCount = points added so far),
//     not treeIndex[idx]; with idx != pointCount the searched bookkeeping is wrong, and an
//     idx >= pointCount makes the leaf test read treeIndex out of bounds;
//   * removePoint(idx) ignores idx >= pointCount;
//   * re-adding a removed idx sets treeIndex[idx] again, which also revives the stale copy
//     still sitting in an older tree: the point is then reported twice.
// So every insertion gets a fresh slot == pointCount, the adapter stores the point at that
// slot (the dataset adaptor exposes slot_points_) and maps caller id <-> slot.
template <class T, std::size_t D>
class nanoflann_dynamic_index final : public point_index<T, D> {
    using point_type = typename point_index<T, D>::point_type;
    using cloud_type = point_cloud<T, D>;
    using base_forest = nanoflann::KDTreeSingleIndexDynamicAdaptor<l2_metric<T, D>, cloud_type,
                                                                   static_cast<std::int32_t>(D), std::uint32_t>;

    // Thin subclass, only to read the protected bookkeeping for memory_bytes().
    struct forest final : base_forest {
        using base_forest::base_forest;
        std::size_t bytes() const {
            std::size_t b = sizeof(*this) + this->treeIndex.capacity() * sizeof(int);
            // removedPoints (std::unordered_set<int>): bucket array + one node per entry
            // (libstdc++: next pointer + int, padded to 16 bytes).
            b += this->removedPoints.bucket_count() * sizeof(void*) + this->removedPoints.size() * 16;
            for (const auto& tree : this->index) {
                b += sizeof(tree) + tree.vAcc.capacity() * sizeof(std::uint32_t) + tree.pool.usedMemory +
                     tree.pool.wastedMemory;
            }
            return b;
        }
    };

    static constexpr std::uint32_t no_slot = std::numeric_limits<std::uint32_t>::max();
    // The forest holds trees of sizes 2^0 .. 2^31: enough for every uint32 slot.
    static constexpr std::size_t max_points = std::numeric_limits<std::uint32_t>::max();

public:
    explicit nanoflann_dynamic_index(std::size_t leaf_max_size) : leaf_max_size_(leaf_max_size) {
        cloud_.pts = &slot_points_;
        reset_forest();
    }
    nanoflann_dynamic_index(const nanoflann_dynamic_index&) = delete;
    nanoflann_dynamic_index& operator=(const nanoflann_dynamic_index&) = delete;

    std::string name() const override { return "nanoflann_dynamic"; }
    unsigned capabilities() const override {
        return capability::knn | capability::approximate_knn | capability::radius | capability::dynamic |
               capability::bulk_insert | capability::dynamic_variant;
    }

    void build(std::span<const point_type> pts) override {
        forest_.reset();  // it references slot_points_
        slot_points_.assign(pts.begin(), pts.end());
        slot_ids_.resize(pts.size());
        std::iota(slot_ids_.begin(), slot_ids_.end(), std::uint32_t{0});
        id_slots_ = slot_ids_;
        live_ = pts.size();
        // The constructor adds every dataset point: addPoints(0, n - 1).
        reset_forest();
    }

    // Points at every slot ever used (deletion is lazy) + slot<->id maps + nanoflann's
    // per-tree pools, permutation arrays and bookkeeping.
    std::size_t memory_bytes() const override {
        return sizeof(*this) + slot_points_.capacity() * sizeof(point_type) +
               slot_ids_.capacity() * sizeof(std::uint32_t) + id_slots_.capacity() * sizeof(std::uint32_t) +
               forest_->bytes();
    }

    void knn(const point_type& q, std::size_t k, T eps, std::vector<neighbor<T>>& out) override {
        out.clear();
        check_eps(eps);
        const std::size_t capacity = std::min(k, live_);
        if (capacity == 0) return;
        slots_.resize(capacity);
        dists_.resize(capacity);
        nanoflann::KNNResultSet<T, std::uint32_t, std::size_t> result(capacity);
        result.init(slots_.data(), dists_.data());
        // One result set shared by all trees of the forest, so later trees are pruned by the
        // k-th distance found so far; each tree's leaf test skips removed slots.
        forest_->findNeighbors(result, q.coords.data(), nanoflann::SearchParams(32, nanoflann_eps(eps)));
        out.resize(result.size());
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = {dists_[i], slot_ids_[slots_[i]]};
    }

    void radius(const point_type& q, T r, std::vector<neighbor<T>>& out) override {
        out.clear();
        const T r2 = closed_radius_squared(r);
        if (r < T(0) || live_ == 0) return;
        nanoflann::RadiusResultSet<T, std::uint32_t> result(r2, matches_);
        forest_->findNeighbors(result, q.coords.data(), nanoflann::SearchParams());
        out.reserve(matches_.size());
        for (const auto& [slot, d2] : matches_) out.push_back({d2, slot_ids_[slot]});
    }

    void insert(std::uint32_t id, const point_type& p) override {
        check_insertable(id, 1);
        const auto slot = add_slot(id, p);
        forest_->addPoints(slot, slot);
    }

    // One addPoints call for the whole range: nanoflann then rebuilds each affected tree of
    // the forest once instead of once per point.
    void insert_bulk(std::uint32_t first_id, std::span<const point_type> pts) override {
        if (pts.empty()) return;
        if (pts.size() - 1 > std::numeric_limits<std::uint32_t>::max() - first_id)
            throw std::invalid_argument("nanoflann_dynamic: insert_bulk ids overflow uint32");
        check_insertable(first_id, pts.size());
        std::uint32_t first_slot = no_slot;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const auto slot = add_slot(first_id + static_cast<std::uint32_t>(i), pts[i]);
            if (i == 0) first_slot = slot;
        }
        forest_->addPoints(first_slot, static_cast<std::uint32_t>(first_slot + pts.size() - 1));
    }

    void erase(std::uint32_t id) override {
        if (id >= id_slots_.size() || id_slots_[id] == no_slot)
            throw std::invalid_argument("nanoflann_dynamic: erase of id " + std::to_string(id) + ", which is not live");
        forest_->removePoint(id_slots_[id]);  // lazy: the slot stays in its tree, marked removed
        id_slots_[id] = no_slot;
        --live_;
    }

    std::size_t size() const override { return live_; }
    std::optional<point_type> point_of(std::uint32_t id) override {
        if (id >= id_slots_.size() || id_slots_[id] == no_slot) return std::nullopt;
        return slot_points_[id_slots_[id]];
    }

private:
    void reset_forest() {
        forest_ = std::make_unique<forest>(static_cast<int>(D), cloud_,
                                           nanoflann::KDTreeSingleIndexAdaptorParams(leaf_max_size_), max_points);
    }

    void check_insertable(std::uint32_t first_id, std::size_t count) const {
        if (slot_points_.size() + count >= max_points)
            throw std::length_error("nanoflann_dynamic: more than 2^32 - 1 insertions since the last build");
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t id = first_id + i;
            if (id < id_slots_.size() && id_slots_[id] != no_slot)
                throw std::invalid_argument("nanoflann_dynamic: insert of id " + std::to_string(id) +
                                            ", which is already live");
        }
    }

    std::uint32_t add_slot(std::uint32_t id, const point_type& p) {
        const auto slot = static_cast<std::uint32_t>(slot_points_.size());
        slot_points_.push_back(p);
        slot_ids_.push_back(id);
        if (id >= id_slots_.size()) id_slots_.resize(std::size_t{id} + 1, no_slot);
        id_slots_[id] = slot;
        ++live_;
        return slot;
    }

    std::vector<point_type> slot_points_;     // slot -> point (the dataset nanoflann sees)
    std::vector<std::uint32_t> slot_ids_;     // slot -> caller id
    std::vector<std::uint32_t> id_slots_;     // caller id -> slot, no_slot when not live
    std::size_t live_ = 0;
    std::size_t leaf_max_size_;
    cloud_type cloud_;
    std::unique_ptr<forest> forest_;
    // Per-query scratch.
    std::vector<std::uint32_t> slots_;
    std::vector<T> dists_;
    std::vector<std::pair<std::uint32_t, T>> matches_;
};

}  // namespace

template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_nanoflann_index(const key_values& settings) {
    return std::make_unique<nanoflann_static_index<T, D>>(count_setting(settings, "leaf_max_size", "nanoflann"));
}

template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_nanoflann_dynamic_index(const key_values& settings) {
    return std::make_unique<nanoflann_dynamic_index<T, D>>(count_setting(settings, "leaf_max_size", "nanoflann_dynamic"));
}

SPATIAL_INSTANTIATE_CONFIGURABLE_POINT_PEER_FACTORY(make_nanoflann_index);

SPATIAL_INSTANTIATE_CONFIGURABLE_POINT_PEER_FACTORY(make_nanoflann_dynamic_index);

}  // namespace harness
