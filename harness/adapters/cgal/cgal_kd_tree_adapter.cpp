// CGAL's Kd_tree (Debian's libcgal-dev 5.5) behind harness::point_index<T, D>.
//
// This is the only translation unit that includes CGAL's Spatial_searching headers (they
// cost ~10 s to compile, and CGAL::CGAL adds -frounding-math, which stays private to the
// spatial_adapter_cgal library).
//
// Tree: CGAL::Kd_tree<traits, Sliding_midpoint, extended nodes, points cache on or off>.
// Its settings (registry line: CGAL's defaults, bucket size 10 and no cache; the tuning sweep,
// harness/tuning_sweep.hpp, runs the others): bucket_size, the splitter's leaf size, and
// points_cache, CGAL's copy of every point's coordinates in leaf order (EnablePointsCache:
// leaves scan contiguous coordinates instead of following pointers, for D * n more values).
// Sliding midpoint: Maneewongvatana & Mount, "It's okay to be skinny, if your friends are
// fat", CGC Workshop 1999. Build O(n log n) expected.
//
// Conventions converted here (CGAL -> point_index):
//   * eps: Orthogonal_k_neighbor_search prunes when d_rect^2 * (1 + eps)^2 >= worst^2, i.e.
//     its eps multiplies DISTANCE, like ours: passed as is.
//   * radius: Fuzzy_sphere(q, r, 0).contains() keeps d^2 <= r^2 (closed ball; r is NOT
//     squared). CGAL reports points, so the adapter computes their squared distances.
//   * k = 0: the bounded queue has capacity 0 and the search would read its top(); we
//     return an empty answer. k > size: the queue never fills; all live points come back.
//   * Ids: the point type carries its id, so knn/radius answers map back without lookups,
//     and erase() removes by id: CGAL's default remove() compares coordinates only and
//     could take the wrong one of several coincident points.
//   * Dynamic behaviour is CGAL's own: insert() drops the built tree (after collecting the
//     surviving points if some were removed) and the next query rebuilds it from scratch;
//     remove() unlinks the point from its leaf in place (and builds first if needed).
//     tree.size() keeps counting removed points until the next rebuild, so the adapter
//     counts live points itself.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/iterator/function_output_iterator.hpp>

#include <CGAL/Dimension.h>
#include <CGAL/Euclidean_distance.h>
#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits.h>
#include <CGAL/Splitters.h>

#include "harness/adapters.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {
namespace {

// The point CGAL stores: coordinates plus the caller's id.
template <class T, std::size_t D>
struct cgal_point {
    std::array<T, D> coords{};
    std::uint32_t id = 0;
};

// Models CGAL's Construct_cartesian_const_iterator_d: (p) -> begin, (p, 0) -> end.
template <class T, std::size_t D>
struct construct_coord_iterator {
    using result_type = const T*;
    const T* operator()(const cgal_point<T, D>& p) const { return p.coords.data(); }
    const T* operator()(const cgal_point<T, D>& p, int) const { return p.coords.data() + D; }
};

template <class T, std::size_t D, class PointsCache>
class cgal_kd_tree_index final : public point_index<T, D> {
    using point_type = typename point_index<T, D>::point_type;
    using stored_point = cgal_point<T, D>;
    using traits = CGAL::Search_traits<T, stored_point, const T*, construct_coord_iterator<T, D>,
                                       CGAL::Dimension_tag<static_cast<int>(D)>>;
    using splitter = CGAL::Sliding_midpoint<traits>;
    using tree_type = CGAL::Kd_tree<traits, splitter, CGAL::Tag_true, PointsCache>;
    using distance_type = CGAL::Euclidean_distance<traits>;
    using knn_search = CGAL::Orthogonal_k_neighbor_search<traits, distance_type, splitter, tree_type>;
    using sphere_type = CGAL::Fuzzy_sphere<traits>;

    // Output iterator body for range search: CGAL reports points; we append (d^2, id).
    // A plain struct, not a lambda: CGAL copy-assigns its output iterators.
    // Points beyond `limit` (a squared distance) are dropped (see radius()).
    struct append_with_distance {
        const point_type* q;
        std::vector<neighbor<T>>* out;
        T limit = std::numeric_limits<T>::infinity();
        void operator()(const stored_point& p) const {
            T d2 = 0;
            for (std::size_t i = 0; i < D; ++i) {
                const T c = (*q)[i] - p.coords[i];
                d2 += c * c;
            }
            if (d2 <= limit) out->push_back({d2, p.id});
        }
    };

    // Equality for tree.remove(): the id, unique among live points.
    struct same_id {
        std::uint32_t id;
        bool operator()(const stored_point& p) const { return p.id == id; }
    };

public:
    explicit cgal_kd_tree_index(unsigned bucket_size) : bucket_size_(bucket_size), tree_(new_tree()) {}
    cgal_kd_tree_index(const cgal_kd_tree_index&) = delete;
    cgal_kd_tree_index& operator=(const cgal_kd_tree_index&) = delete;

    std::string name() const override { return "cgal_kd_tree"; }
    unsigned capabilities() const override {
        return capability::knn | capability::approximate_knn | capability::radius | capability::dynamic |
               capability::bulk_insert | capability::rebuilds_on_query;
    }

    void build(std::span<const point_type> pts) override {
        tree_ = new_tree();  // a fresh tree frees the old nodes and points
        by_id_.clear();
        by_id_.shrink_to_fit();
        alive_.clear();
        alive_.shrink_to_fit();
        table_ready_ = false;
        stale_ = false;
        build_count_ = pts.size();
        built_from_ = pts;
        live_ = pts.size();
        tree_->reserve(pts.size());  // safe: the tree is not built yet
        for (std::size_t i = 0; i < pts.size(); ++i)
            tree_->insert(stored_point{pts[i].coords, static_cast<std::uint32_t>(i)});
        // Build now, so build() is what gets timed (CGAL would build inside the first query).
        if (!pts.empty()) tree_->build();
    }

    // Honest estimate, in bytes:
    //   sizeof(adapter) + sizeof(Kd_tree)
    //   + capacity(points) * sizeof(point + id)          CGAL's own copy of the points
    //   if built:
    //   + L * sizeof(Leaf_node) + (L - 1) * sizeof(Internal_node)   L = leaves reachable
    //                                                    from the root (a full binary tree)
    //   + sizeof(Kd_tree_rectangle)                      the root box
    //   + size() * sizeof(pointer)                       the `data` array CGAL reserves for
    //                                                    the build and keeps (clear() only)
    //   + the id -> point table and live flags, once a dynamic operation has created them.
    // Not counted: the deques' block maps (a few pointers per 512 bytes of nodes), and
    // nodes orphaned by remove() (at most two per removal that empties a leaf), which stay
    // allocated until the next rebuild.
    std::size_t memory_bytes() const override {
        std::size_t bytes = sizeof(*this) + sizeof(tree_type);
        // Kd_tree::capacity() is not const-qualified although it only reads pts.capacity().
        bytes += const_cast<tree_type&>(*tree_).capacity() * sizeof(stored_point);
        if (tree_->is_built() && !tree_->empty()) {
            const std::size_t leaves = static_cast<std::size_t>(tree_->root()->num_nodes());
            bytes += leaves * sizeof(typename tree_type::Leaf_node) +
                     (leaves - 1) * sizeof(typename tree_type::Internal_node);
            bytes += sizeof(CGAL::Kd_tree_rectangle<T, CGAL::Dimension_tag<static_cast<int>(D)>>);
            bytes += tree_->size() * sizeof(const stored_point*);
            if constexpr (PointsCache::value) bytes += tree_->size() * D * sizeof(T);  // the points cache
        }
        bytes += by_id_.capacity() * sizeof(point_type) + alive_.capacity() * sizeof(unsigned char);
        return bytes;
    }

    void knn(const point_type& q, std::size_t k, T eps, std::vector<neighbor<T>>& out) override {
        out.clear();
        if (!(eps >= T(0))) throw std::invalid_argument("cgal_kd_tree: eps must be >= 0, got " + std::to_string(eps));
        last_nodes_ = 0;
        const std::size_t count = std::min(k, live_);
        if (count == 0) return;
        refresh();
        knn_search search(*tree_, stored_point{q.coords, 0}, static_cast<unsigned>(count), eps, true,
                          distance_type(), true);
        out.reserve(count);
        // advanced_begin() yields (const point*, squared distance) without copying points.
        for (auto it = search.advanced_begin(); it != search.advanced_end(); ++it)
            out.push_back({it->second, it->first->id});
        last_nodes_ = static_cast<long long>(search.internals_visited()) + search.leafs_visited();
    }

    void radius(const point_type& q, T r, std::vector<neighbor<T>>& out) override {
        out.clear();
        last_nodes_ = -1;  // CGAL's range search does not count nodes
        if (std::isnan(r)) throw std::invalid_argument("cgal_kd_tree: radius is NaN");
        if (r < T(0) || live_ == 0) return;
        refresh();
        if constexpr (PointsCache::value) {
            // CGAL 5.5's Fuzzy_sphere tests the points it reads from the points cache with
            // d^2 < r^2 (contains_point_given_as_coordinates: an OPEN ball), where contains(),
            // used without the cache, keeps d^2 <= r^2. So the ball gets the smallest radius
            // whose square exceeds r^2, and the answer is cut back to the closed ball here.
            // (r^2 infinite: every finite point is inside either way.)
            const T r2 = r * r;
            T wider = r;
            if (std::isfinite(r2)) {
                if (r2 == T(0)) wider = std::sqrt(std::numeric_limits<T>::denorm_min());
                while (!(wider * wider > r2)) wider = std::nextafter(wider, std::numeric_limits<T>::infinity());
            }
            const sphere_type ball(stored_point{q.coords, 0}, wider, T(0));
            tree_->search(boost::make_function_output_iterator(append_with_distance{&q, &out, r2}), ball);
        } else {
            const sphere_type ball(stored_point{q.coords, 0}, r, T(0));
            tree_->search(boost::make_function_output_iterator(append_with_distance{&q, &out}), ball);
        }
    }

    void insert(std::uint32_t id, const point_type& p) override {
        ensure_table();
        check_insertable(id, 1);
        mark_live(id, p);
        if constexpr (PointsCache::value) stale_ = true;  // see refresh()
        else tree_->insert(stored_point{p.coords, id});
    }

    // CGAL's range insert: one invalidation of the built tree, one append.
    void insert_bulk(std::uint32_t first_id, std::span<const point_type> pts) override {
        if (pts.empty()) return;
        if (pts.size() - 1 > std::numeric_limits<std::uint32_t>::max() - first_id)
            throw std::invalid_argument("cgal_kd_tree: insert_bulk ids overflow uint32");
        ensure_table();
        check_insertable(first_id, pts.size());
        std::vector<stored_point> batch(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const auto id = first_id + static_cast<std::uint32_t>(i);
            mark_live(id, pts[i]);
            batch[i] = stored_point{pts[i].coords, id};
        }
        if constexpr (PointsCache::value) stale_ = true;  // see refresh()
        else tree_->insert(batch.begin(), batch.end());
    }

    void erase(std::uint32_t id) override {
        ensure_table();
        if (id >= alive_.size() || !alive_[id])
            throw std::invalid_argument("cgal_kd_tree: erase of id " + std::to_string(id) + ", which is not live");
        if constexpr (PointsCache::value) stale_ = true;  // see refresh()
        else tree_->remove(stored_point{by_id_[id].coords, id}, same_id{id});
        alive_[id] = 0;
        --live_;
    }

    std::size_t size() const override { return live_; }
    long long last_nodes_visited() const override { return last_nodes_; }
    // Before any dynamic operation the ids are the build array's positions (the caller keeps
    // it alive, see point_index); afterwards the id -> point table says.
    std::optional<point_type> point_of(std::uint32_t id) override {
        if (!table_ready_) return id < built_from_.size() ? std::optional<point_type>(built_from_[id]) : std::nullopt;
        return id < alive_.size() && alive_[id] ? std::optional<point_type>(by_id_[id]) : std::nullopt;
    }

    // Untimed hook before dynamic workloads: build the id -> point table now, so the first
    // timed erase/insert does not pay the O(n) scan.
    void prepare_dynamic() override { ensure_table(); }

private:
    std::unique_ptr<tree_type> new_tree() const { return std::make_unique<tree_type>(splitter(bucket_size_)); }

    // CGAL 5.5's Kd_tree cannot change in place with the points cache: remove() swaps the
    // removed point with its leaf's last one in the point array but not in the cache, and
    // invalidate_build() (insert() calls it) keeps the old cache, to which the next build()
    // appends; either way queries then read other points' coordinates. So with the cache an
    // insertion or removal only marks the tree stale, and the next query builds a new tree of
    // the live points: the O(n log n) rebuild CGAL's own lazy rebuild after insert() costs too
    // (the dynamic workloads exclude this peer: capability::rebuilds_on_query).
    void refresh() {
        if constexpr (PointsCache::value) {
            if (!stale_) return;
            tree_ = new_tree();
            std::vector<stored_point> live;
            live.reserve(live_);
            for (std::size_t id = 0; id < alive_.size(); ++id)
                if (alive_[id]) live.push_back(stored_point{by_id_[id].coords, static_cast<std::uint32_t>(id)});
            tree_->insert(live.begin(), live.end());
            if (!live.empty()) tree_->build();
            stale_ = false;
        }
    }

    // erase() must hand CGAL the point's coordinates (remove() descends by them), so dynamic
    // operations need id -> point. It is built by prepare_dynamic() (or, failing that, by the
    // first dynamic operation) from CGAL's point array, O(n) once, so static workloads do not
    // pay for a second copy of the points. Before that first operation nothing was removed,
    // so the array is exactly the build set.
    void ensure_table() {
        if (table_ready_) return;
        by_id_.assign(build_count_, point_type{});
        alive_.assign(build_count_, 0);
        for (auto it = tree_->begin(); it != tree_->end(); ++it) {
            by_id_[it->id].coords = it->coords;
            alive_[it->id] = 1;
        }
        table_ready_ = true;
    }

    void check_insertable(std::uint32_t first_id, std::size_t count) const {
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t id = first_id + i;
            if (id < alive_.size() && alive_[id])
                throw std::invalid_argument("cgal_kd_tree: insert of id " + std::to_string(id) +
                                            ", which is already live");
        }
    }

    void mark_live(std::uint32_t id, const point_type& p) {
        if (id >= alive_.size()) {
            by_id_.resize(std::size_t{id} + 1);
            alive_.resize(std::size_t{id} + 1, 0);
        }
        by_id_[id] = p;
        alive_[id] = 1;
        ++live_;
    }

    unsigned bucket_size_;
    std::unique_ptr<tree_type> tree_;
    std::vector<point_type> by_id_;     // id -> point, valid where alive_[id]
    std::vector<unsigned char> alive_;  // id -> live flag
    bool table_ready_ = true;           // an empty adapter has an (empty) table
    bool stale_ = false;                // points cache only: rebuild before the next query
    std::size_t build_count_ = 0;
    std::span<const point_type> built_from_;  // the last build's points (point_of)
    std::size_t live_ = 0;
    long long last_nodes_ = -1;
};

}  // namespace

template <class T, std::size_t D>
std::unique_ptr<point_index<T, D>> make_cgal_kd_tree_index(const key_values& settings) {
    const std::size_t bucket = count_setting(settings, "bucket_size", "cgal_kd_tree");
    if (bucket > std::numeric_limits<unsigned>::max())
        throw std::invalid_argument("cgal_kd_tree: bucket_size " + std::to_string(bucket) + " is too large");
    if (switch_setting(settings, "points_cache", "cgal_kd_tree"))
        return std::make_unique<cgal_kd_tree_index<T, D, CGAL::Tag_true>>(static_cast<unsigned>(bucket));
    return std::make_unique<cgal_kd_tree_index<T, D, CGAL::Tag_false>>(static_cast<unsigned>(bucket));
}

SPATIAL_INSTANTIATE_CONFIGURABLE_POINT_PEER_FACTORY(make_cgal_kd_tree_index);

}  // namespace harness
