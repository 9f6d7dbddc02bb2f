#pragma once
// harness::point_index<T, D> — the runtime interface every benchmarked point structure
// (ours and the peers') is put behind, so one timing loop and one validator serve all.
//
// One virtual call per query costs a few nanoseconds, the same for every structure, and is
// small next to the microseconds a query takes; the structures themselves are not virtual.
//
// Identity: points are identified by their position `id` in the array passed to build()
// (and, for dynamic workloads, by the id passed to insert()). Answers are compared by
// DISTANCE, never by id, because distance ties make ids ambiguous; but each reported id must
// name a live point, at most once per answer, at the distance reported for it (point_of).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/configured.hpp"
#include "spatial/core/knn_batch.hpp"
#include "spatial/core/point.hpp"

namespace harness {

enum class capability : unsigned {
    knn = 1u << 0,          // exact k nearest neighbours
    approximate_knn = 1u << 1,  // (1+eps)-approximate kNN, eps multiplies DISTANCE
    radius = 1u << 2,       // all points within a ball (closed)
    dynamic = 1u << 3,      // insert(id, p) and erase(id) after build
    hinted_insert = 1u << 4,    // insert_near(prev_id, id, p)
    bulk_insert = 1u << 5,  // insert_bulk(first_id, pts)
    bulk_erase = 1u << 6,   // erase_bulk(ids)
    // Insertions after build are deferred to a full rebuild inside the next query (CGAL's
    // Kd_tree): a timed insert/erase loop would leave the rebuild out, so the dynamic
    // workloads do not time it.
    rebuilds_on_query = 1u << 7,
    // A peer's dynamic variant (nanoflann's KDTreeSingleIndexDynamicAdaptor): timed in the
    // dynamic workloads only; its static sibling stands for the library in the static ones.
    dynamic_variant = 1u << 8,
    // knn_batch(queries, k, order, parallel, out): the structure's own batched kNN, which may
    // reorder the queries (Morton order) and use every core (kd_tree::find_nearest_batch).
    batched_knn = 1u << 9,
};

constexpr unsigned operator|(capability a, capability b) {
    return static_cast<unsigned>(a) | static_cast<unsigned>(b);
}
constexpr unsigned operator|(unsigned a, capability b) { return a | static_cast<unsigned>(b); }

// The names of the capabilities in `bits`, in the enum's order: the words a peer's registry
// line (peer_registry.hpp) and results/registry.json use.
inline std::vector<std::string> capability_names(unsigned bits) {
    static constexpr std::pair<capability, const char*> names[] = {
        {capability::knn, "knn"},
        {capability::approximate_knn, "approximate_knn"},
        {capability::radius, "radius"},
        {capability::dynamic, "dynamic"},
        {capability::hinted_insert, "hinted_insert"},
        {capability::bulk_insert, "bulk_insert"},
        {capability::bulk_erase, "bulk_erase"},
        {capability::rebuilds_on_query, "rebuilds_on_query"},
        {capability::dynamic_variant, "dynamic_variant"},
        {capability::batched_knn, "batched_knn"},
    };
    std::vector<std::string> out;
    for (const auto& [c, name] : names)
        if (bits & static_cast<unsigned>(c)) out.emplace_back(name);
    return out;
}

// One reported neighbour. `id` identifies the point WITHIN the structure that reported it
// (for peers the build/insert id, for our containers the element's slot handle); the
// harness never compares ids across structures, only distances.
template <class T>
struct neighbor {
    T distance_squared;
    std::uint32_t id;
};

template <class T, std::size_t D>
class point_index : public configured {  // configuration(): harness/configured.hpp
public:
    using point_type = spatial::point<T, D>;
    virtual ~point_index() = default;

    // Name written to the CSV `structure` column (kd_tree, nanoflann, cgal_kd_tree, ...).
    virtual std::string name() const = 0;
    // Bit set of `capability` values.
    virtual unsigned capabilities() const = 0;
    bool can(capability c) const { return (capabilities() & static_cast<unsigned>(c)) != 0; }

    // Replace the contents with pts; point i gets id i. The structure may keep a reference
    // to pts (nanoflann does): the caller keeps pts alive and unchanged until the next build.
    virtual void build(std::span<const point_type> pts) = 0;
    // Bytes the structure holds, INCLUDING any point storage it references but does not own
    // (so an index over an external array is charged for that array).
    virtual std::size_t memory_bytes() const = 0;

    // k nearest neighbours of q, sorted by increasing distance, written to out (cleared first).
    // eps >= 0: each reported i-th distance is within (1 + eps) of the true i-th distance.
    virtual void knn(const point_type& q, std::size_t k, T eps, std::vector<neighbor<T>>& out) = 0;
    // All points p with |p - q| <= r, any order, written to out (cleared first).
    virtual void radius(const point_type& q, T r, std::vector<neighbor<T>>& out) = 0;
    // Exact kNN of every query at once (only if capability::batched_knn), searched in `order`
    // and, when `parallel`, on every core: query i's answer, nearest first, is written to
    // out[i * per_query, (i + 1) * per_query), and per_query (min(k, size())) is returned.
    virtual std::size_t knn_batch(std::span<const point_type> queries, std::size_t k, spatial::query_order order,
                                  bool parallel, std::vector<neighbor<T>>& out) {
        (void)queries, (void)k, (void)order, (void)parallel, (void)out;
        throw std::logic_error(name() + " does not support knn_batch");
    }

    // Dynamic workloads (only if capability::dynamic). ids are chosen by the caller and are
    // unique among live points.
    virtual void insert(std::uint32_t id, const point_type& p) { unsupported("insert"); (void)id; (void)p; }
    virtual void erase(std::uint32_t id) { unsupported("erase"); (void)id; }
    // Insert p next to the previously inserted point prev_id (the structure may use it as a hint).
    virtual void insert_near(std::uint32_t prev_id, std::uint32_t id, const point_type& p) {
        (void)prev_id;
        insert(id, p);
    }
    // Insert pts with ids first_id, first_id+1, ...
    virtual void insert_bulk(std::uint32_t first_id, std::span<const point_type> pts) {
        for (std::size_t i = 0; i < pts.size(); ++i) insert(first_id + static_cast<std::uint32_t>(i), pts[i]);
    }
    virtual void erase_bulk(std::span<const std::uint32_t> ids) {
        for (auto id : ids) erase(id);
    }
    virtual std::size_t size() const = 0;
    // Called UNTIMED after build() and before timed dynamic operations, for bookkeeping a
    // structure needs before erase(id) works (our adapters resolve ids of bulk-built points).
    virtual void prepare_dynamic() {}

    // The point a reported neighbour id stands for, or nullopt if no live point has that id.
    // Untimed (validation recomputes every reported distance from it); it may build a lookup
    // table the first time after a change, which memory_bytes() does not count.
    virtual std::optional<point_type> point_of(std::uint32_t id) = 0;

    // Nodes visited by the last query, or -1 when the structure cannot report it.
    virtual long long last_nodes_visited() const { return -1; }

protected:
    [[noreturn]] void unsupported(const char* what) const {
        throw std::logic_error(name() + " does not support " + what);
    }
};

}  // namespace harness
