// Boost.Geometry's R-tree (Debian's libboost-dev 1.74, header-only) behind
// harness::point_index<T, D>; the only translation unit that includes it.
//
// Two configurations, as Boost.Geometry documents them:
//   boost_rtree            bgi::rstar<16>, bulk-loaded by the packing constructor (the
//                          R*-tree of Beckmann, Kriegel, Schneider & Seeger, SIGMOD 1990;
//                          packing after Leutenegger, Lopez & Edgington's STR, ICDE 1997);
//                          the static workloads
//   boost_rtree_quadratic  bgi::quadratic<16>, built by inserting one point at a time
//                          (Guttman's quadratic split, SIGMOD 1984); insert and remove as
//                          they come: the dynamic workloads
//
// Conventions converted here (Boost.Geometry -> point_index):
//   * kNN: query(bgi::nearest(q, k)) returns the k nearest in no specified order; the
//     adapter sorts them by squared distance, computed as a naive loop in T. No approximate
//     search.
//   * radius: a query with the box [q - r, q + r] (closed, bgi::intersects) filtered by
//     |p - q|^2 <= r^2 in T: a closed ball.
//   * memory: every node the tree allocates passes through a counting allocator; the
//     adapter adds its own id -> point table.
//   * ids: the values are (point, id) pairs; remove() needs the exact value, so the adapter
//     keeps each live id's point.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "harness/adapters.hpp"
#include "counting_allocator.hpp"

namespace harness {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;

// The rtree's node allocations, counted (counting_allocator.hpp).
using boost_adapters::counting_allocator;

// Boost's leaf and node capacity for both configurations (its documentation's examples use
// 16; the harness's peers run at their documented defaults until issue 18's sweep).
constexpr std::size_t node_capacity = 16;

template <class T, std::size_t D, class Params, bool Packed>
class boost_rtree_index final : public point_index<T, D> {
    using point_type = typename point_index<T, D>::point_type;
    using bg_point = bg::model::point<T, D, bg::cs::cartesian>;
    using value = std::pair<bg_point, std::uint32_t>;
    using allocator = counting_allocator<value>;
    using tree_type = bgi::rtree<value, Params, bgi::indexable<value>, bgi::equal_to<value>, allocator>;

public:
    explicit boost_rtree_index(std::string name) : name_(std::move(name)) { reset({}); }
    boost_rtree_index(const boost_rtree_index&) = delete;
    boost_rtree_index& operator=(const boost_rtree_index&) = delete;

    std::string name() const override { return name_; }
    unsigned capabilities() const override {
        if constexpr (Packed) return capability::knn | capability::radius;
        else return capability::knn | capability::radius | capability::dynamic | capability::dynamic_variant;
    }

    void build(std::span<const point_type> pts) override {
        std::vector<value> values(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) values[i] = {to_bg(pts[i]), static_cast<std::uint32_t>(i)};
        points_.assign(pts.begin(), pts.end());
        live_.assign(pts.size(), 1);
        reset(values);
    }

    std::size_t memory_bytes() const override {
        return sizeof(*this) + tree_bytes_ + points_.capacity() * sizeof(point_type) + live_.capacity();
    }

    void knn(const point_type& q, std::size_t k, T eps, std::vector<neighbor<T>>& out) override {
        out.clear();
        if (!(eps >= T(0))) throw std::invalid_argument(name_ + ": eps must be >= 0, got " + std::to_string(eps));
        if (k == 0 || tree_->empty()) return;
        found_.clear();
        tree_->query(bgi::nearest(to_bg(q), static_cast<unsigned>(std::min<std::size_t>(k, tree_->size()))),
                     std::back_inserter(found_));
        for (const auto& [p, id] : found_) out.push_back({squared_distance(points_[id], q), id});
        std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.distance_squared < b.distance_squared; });
    }

    void radius(const point_type& q, T r, std::vector<neighbor<T>>& out) override {
        out.clear();
        if (std::isnan(r)) throw std::invalid_argument(name_ + ": radius is NaN");
        if (r < T(0) || tree_->empty()) return;
        bg_point lo, hi;
        set_coords(lo, q, -r);
        set_coords(hi, q, r);
        const T r2 = r * r;
        found_.clear();
        tree_->query(bgi::intersects(bg::model::box<bg_point>(lo, hi)), std::back_inserter(found_));
        for (const auto& [p, id] : found_) {
            const T d2 = squared_distance(points_[id], q);
            if (d2 <= r2) out.push_back({d2, id});
        }
    }

    // The dynamic configuration only (the packed tree stands for the static workloads).
    void insert(std::uint32_t id, const point_type& p) override {
        if constexpr (Packed) return point_index<T, D>::insert(id, p);
        if (id >= points_.size()) points_.resize(id + std::size_t{1}), live_.resize(id + std::size_t{1}, 0);
        if (live_[id]) throw std::invalid_argument(name_ + ": insert of id " + std::to_string(id) + ", which is live");
        points_[id] = p;
        live_[id] = 1;
        tree_->insert(value{to_bg(p), id});
    }

    void erase(std::uint32_t id) override {
        if constexpr (Packed) return point_index<T, D>::erase(id);
        if (id >= live_.size() || !live_[id] || tree_->remove(value{to_bg(points_[id]), id}) != 1)
            throw std::invalid_argument(name_ + ": erase of id " + std::to_string(id) + ", which is not live");
        live_[id] = 0;
    }

    std::size_t size() const override { return tree_->size(); }
    std::optional<point_type> point_of(std::uint32_t id) override {
        return id < live_.size() && live_[id] ? std::optional<point_type>(points_[id]) : std::nullopt;
    }

private:
    static bg_point to_bg(const point_type& p) {
        bg_point b;
        set_coords(b, p, T(0));
        return b;
    }
    // b = p + offset in every coordinate.
    static void set_coords(bg_point& b, const point_type& p, T offset) {
        [&]<std::size_t... I>(std::index_sequence<I...>) { (bg::set<I>(b, p[I] + offset), ...); }(std::make_index_sequence<D>{});
    }
    static T squared_distance(const point_type& a, const point_type& b) {
        T s = 0;
        for (std::size_t d = 0; d < D; ++d) s += (a[d] - b[d]) * (a[d] - b[d]);
        return s;
    }

    // A fresh tree over `values`: packed (the range constructor), or inserted one by one.
    void reset(const std::vector<value>& values) {
        tree_.reset();  // frees the old nodes, so the counter restarts from the new tree alone
        tree_bytes_ = 0;
        const allocator alloc(&tree_bytes_);
        if constexpr (Packed) {
            tree_ = std::make_unique<tree_type>(values.begin(), values.end(), Params(), bgi::indexable<value>(),
                                                bgi::equal_to<value>(), alloc);
        } else {
            tree_ = std::make_unique<tree_type>(Params(), bgi::indexable<value>(), bgi::equal_to<value>(), alloc);
            for (const auto& v : values) tree_->insert(v);
        }
    }

    std::string name_;
    std::size_t tree_bytes_ = 0;  // the counting allocator's counter: declared before tree_
    std::unique_ptr<tree_type> tree_;
    std::vector<point_type> points_;  // by id: distances, and the value remove() needs
    std::vector<char> live_;
    std::vector<value> found_;  // per-query scratch
};

}  // namespace

template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_boost_rtree_index() {
    return std::make_unique<boost_rtree_index<T, D, bgi::rstar<node_capacity>, true>>("boost_rtree");
}

template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_boost_rtree_quadratic_index() {
    return std::make_unique<boost_rtree_index<T, D, bgi::quadratic<node_capacity>, false>>("boost_rtree_quadratic");
}

SPATIAL_INSTANTIATE_POINT_PEER_FACTORY(make_boost_rtree_index);

SPATIAL_INSTANTIATE_POINT_PEER_FACTORY(make_boost_rtree_quadratic_index);

}  // namespace harness
