// Point peer adapters (every one harness/peer_registry.hpp lists for the knn suite) against a
// brute-force oracle.
//
// Every adapter compiled into the build (harness::make_peer_indices) x T in {float, double}
// x D in {2, 3}. Answers are compared by DISTANCE (ties make ids ambiguous), and every
// reported id is checked to be live with a distance that matches its stored point, which
// catches id-mapping bugs that distance lists alone would miss. A new peer needs no edit here:
// its name and capabilities come from its registry line. Only the harness's own headers are
// included: the peers' headers stay in their adapter libraries.
//
// Seeds are fixed and printed through SCOPED_TRACE, so a failure names its seed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "harness/adapters.hpp"
#include "harness/peer_registry.hpp"
#include "harness/tuning_sweep.hpp"

namespace {

using harness::capability;
using harness::neighbor;
using harness::point_index;

constexpr std::uint64_t base_seed = 20240611;
constexpr std::size_t n_points = 2000;
constexpr std::size_t n_queries = 50;

template <class T, std::size_t D>
struct config {
    using scalar = T;
    static constexpr std::size_t dim = D;
};

using configs = ::testing::Types<config<float, 2>, config<float, 3>, config<double, 2>, config<double, 3>>;

struct config_names {
    template <class C>
    static std::string GetName(int) {
        return std::string(std::is_same_v<typename C::scalar, float> ? "float" : "double") +
               std::to_string(C::dim) + "d";
    }
};

template <class C>
class adapters_test : public ::testing::Test {};
TYPED_TEST_SUITE(adapters_test, configs, config_names);

// ---------------------------------------------------------------------------------------
// Oracle

template <class T, std::size_t D>
using pt = spatial::point<T, D>;

template <class T, std::size_t D>
T dist2(const pt<T, D>& q, const pt<T, D>& p) {
    T s = 0;
    for (std::size_t i = 0; i < D; ++i) {
        const T c = q[i] - p[i];
        s += c * c;
    }
    return s;
}

// Relative tolerance on squared distances: peers sum the same terms, but a compiler may
// contract them into FMAs differently in different translation units.
template <class T>
constexpr T tol = T(16) * std::numeric_limits<T>::epsilon();

template <class T>
bool near(T a, T b) {
    return std::abs(a - b) <= tol<T> * std::max({std::abs(a), std::abs(b), T(1e-30)});
}

// The live set: id -> point.
template <class T, std::size_t D>
using live_set = std::unordered_map<std::uint32_t, pt<T, D>>;

template <class T, std::size_t D>
live_set<T, D> as_live(const std::vector<pt<T, D>>& pts) {
    live_set<T, D> live;
    for (std::size_t i = 0; i < pts.size(); ++i) live.emplace(static_cast<std::uint32_t>(i), pts[i]);
    return live;
}

template <class T, std::size_t D>
std::vector<T> all_distances(const live_set<T, D>& live, const pt<T, D>& q) {
    std::vector<T> d;
    d.reserve(live.size());
    for (const auto& [id, p] : live) d.push_back(dist2(q, p));
    std::sort(d.begin(), d.end());
    return d;
}

// Every reported id is live, unique, and carries the distance of its stored point.
template <class T, std::size_t D>
void check_ids(const live_set<T, D>& live, const pt<T, D>& q, const std::vector<neighbor<T>>& out) {
    std::set<std::uint32_t> seen;
    for (const auto& nb : out) {
        const auto it = live.find(nb.id);
        ASSERT_NE(it, live.end()) << "reported id " << nb.id << " is not live";
        ASSERT_TRUE(seen.insert(nb.id).second) << "id " << nb.id << " reported twice";
        ASSERT_TRUE(near(nb.distance_squared, dist2(q, it->second)))
            << "id " << nb.id << ": reported d^2 " << nb.distance_squared << ", its point gives " << dist2(q, it->second);
    }
}

template <class T, std::size_t D>
void check_knn(point_index<T, D>& index, const live_set<T, D>& live, const pt<T, D>& q, std::size_t k, T eps) {
    SCOPED_TRACE(::testing::Message() << "knn q=" << q << " k=" << k << " eps=" << eps << " live=" << live.size());
    std::vector<neighbor<T>> out{{T(-1), 12345}};  // must be cleared
    index.knn(q, k, eps, out);
    const auto exact = all_distances(live, q);
    ASSERT_EQ(out.size(), std::min(k, live.size()));
    ASSERT_NO_FATAL_FAILURE(check_ids(live, q, out));
    const T factor = (T(1) + eps) * (T(1) + eps);
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (i > 0) {
            EXPECT_LE(out[i - 1].distance_squared, out[i].distance_squared) << "not sorted at " << i;
        }
        if (eps == T(0)) {
            EXPECT_TRUE(near(out[i].distance_squared, exact[i]))
                << "i=" << i << ": got " << out[i].distance_squared << ", exact " << exact[i];
        } else {
            // (1+eps)-approximate: i-th distance within (1+eps) of the true i-th distance;
            // and never better than exact (distinct live points, sorted).
            EXPECT_LE(out[i].distance_squared, factor * exact[i] * (T(1) + tol<T>) + T(1e-30))
                << "i=" << i << ": got " << out[i].distance_squared << ", exact " << exact[i];
            EXPECT_GE(out[i].distance_squared, exact[i] * (T(1) - tol<T>)) << "i=" << i;
        }
    }
}

template <class T, std::size_t D>
void check_radius(point_index<T, D>& index, const live_set<T, D>& live, const pt<T, D>& q, T r) {
    SCOPED_TRACE(::testing::Message() << "radius q=" << q << " r=" << r << " live=" << live.size());
    std::vector<neighbor<T>> out{{T(-1), 12345}};
    index.radius(q, r, out);
    ASSERT_NO_FATAL_FAILURE(check_ids(live, q, out));
    const T r2 = r * r;
    const T band = tol<T> * std::max(r2, T(1e-30));
    std::set<std::uint32_t> reported;
    for (const auto& nb : out) {
        reported.insert(nb.id);
        EXPECT_LE(nb.distance_squared, r2 + band) << "id " << nb.id << " is outside the ball";
    }
    // Closed ball: everything with d^2 <= r^2 (beyond the rounding band) must be there, and
    // the sorted distance lists agree away from the boundary band.
    std::vector<T> expected, got;
    for (const auto& [id, p] : live) {
        const T d = dist2(q, p);
        if (d <= r2 - band || d == T(0)) {
            EXPECT_TRUE(reported.count(id)) << "missing id " << id << " at d^2 " << d;
        }
        if (d <= r2 && std::abs(d - r2) > band) expected.push_back(d);
    }
    for (const auto& nb : out)
        if (std::abs(nb.distance_squared - r2) > band) got.push_back(nb.distance_squared);
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_TRUE(near(got[i], expected[i])) << "i=" << i;
}

// ---------------------------------------------------------------------------------------
// Workloads

template <class T, std::size_t D>
std::vector<pt<T, D>> uniform_points(std::mt19937_64& rng, std::size_t n, T lo = 0, T hi = 1) {
    std::uniform_real_distribution<T> u(lo, hi);
    std::vector<pt<T, D>> pts(n);
    for (auto& p : pts)
        for (std::size_t i = 0; i < D; ++i) p[i] = u(rng);
    return pts;
}

// Queries: inside and slightly outside the unit cube, plus some exactly on data points.
template <class T, std::size_t D>
std::vector<pt<T, D>> make_queries(std::mt19937_64& rng, const live_set<T, D>& live, std::size_t n) {
    auto qs = uniform_points<T, D>(rng, n, T(-0.1), T(1.1));
    std::size_t i = 0;
    for (const auto& [id, p] : live) {
        if (i >= n / 5) break;
        qs[i++] = p;
    }
    return qs;
}

// Every query kind against the oracle: exact kNN (k = 0, 1, 10, > size), approximate kNN
// (eps 0.5 and 2), radius (0, between consecutive neighbour distances, random).
template <class T, std::size_t D>
void check_all(point_index<T, D>& index, const live_set<T, D>& live, std::mt19937_64& rng, std::size_t queries) {
    ASSERT_EQ(index.size(), live.size());
    const auto qs = make_queries(rng, live, queries);
    std::uniform_real_distribution<T> ur(T(0), T(0.2));
    for (const auto& q : qs) {
        for (std::size_t k : {std::size_t{0}, std::size_t{1}, std::size_t{10}, live.size() + 7})
            ASSERT_NO_FATAL_FAILURE(check_knn(index, live, q, k, T(0)));
        if (index.can(capability::approximate_knn)) {
            for (T eps : {T(0.5), T(2)})
                for (std::size_t k : {std::size_t{1}, std::size_t{10}})
                    ASSERT_NO_FATAL_FAILURE(check_knn(index, live, q, k, eps));
        }
        const auto exact = all_distances(live, q);
        std::vector<T> radii{T(0), ur(rng)};
        for (std::size_t j : {std::size_t{0}, std::size_t{9}, std::size_t{99}})
            if (j + 1 < exact.size()) radii.push_back(std::sqrt((exact[j] + exact[j + 1]) / T(2)));
        for (T r : radii) ASSERT_NO_FATAL_FAILURE(check_radius(index, live, q, r));
    }
}

template <class T, std::size_t D>
std::string trace_name(const point_index<T, D>& index, std::uint64_t seed) {
    const std::string configuration = index.configuration().empty() ? "" : "[" + index.configuration() + "]";
    return index.name() + configuration + " seed=" + std::to_string(seed);
}

// ---------------------------------------------------------------------------------------
// Tests

// n uniform points drawn from rng (uniform_points), and `index` built over them.
template <class T, std::size_t D>
std::vector<pt<T, D>> build_on_uniform_points(point_index<T, D>& index, std::mt19937_64& rng, std::size_t n) {
    auto pts = uniform_points<T, D>(rng, n);
    index.build(pts);
    return pts;
}

// `index` holds nothing: size 0, no k nearest neighbours of q, none within 10 of it (both
// answers in `out`, which the caller may hand over non-empty).
template <class T, std::size_t D>
void expect_holds_nothing(point_index<T, D>& index, const pt<T, D>& q, std::size_t k, std::vector<neighbor<T>>& out) {
    EXPECT_EQ(index.size(), 0u);
    index.knn(q, k, T(0), out);
    EXPECT_TRUE(out.empty());
    index.radius(q, T(10), out);
    EXPECT_TRUE(out.empty());
}

// Runs body(index, rng) for each peer index of dimension D over T (only the dynamic ones when
// `which` says so), traced with its seed base_seed + offset + D, rng seeded with it. Stops at
// the first fatal failure, as an ASSERT in a loop over the peers would.
enum class peers { all, dynamic };
template <class T, std::size_t D, class Body>
void for_each_seeded_peer(std::uint64_t offset, peers which, Body&& body) {
    // Every configuration of the tuning sweep too: a swept configuration is timed only if
    // validated, and validated here like the default.
    for (const auto& index : harness::make_peer_indices<T, D>(true)) {
        if (which == peers::dynamic && !index->can(capability::dynamic)) continue;
        const std::uint64_t seed = base_seed + offset + D;
        SCOPED_TRACE(trace_name(*index, seed));
        std::mt19937_64 rng(seed);
        body(index, rng);
        if (::testing::Test::HasFatalFailure()) return;
    }
}

// The point peers the registry lists (harness/peer_registry.hpp: the knn suite's peers).
std::set<std::string> registered_point_peers() {
    std::set<std::string> out;
    for (const auto& p : harness::registered_peers())
        if (p.takes_part_in(harness::in::knn)) out.insert(p.name);
    return out;
}

// Every adapter has its registry line, and with every peer's CMake option on (the default
// build; CMake defines SPATIAL_EVERY_PEER_ADAPTER_BUILT) every registered peer has its adapter:
// a new peer needs no line here.
TYPED_TEST(adapters_test, every_configured_peer_is_registered) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    std::set<std::string> names;
    for (const auto& index : harness::make_peer_indices<T, D>()) names.insert(index->name());
    const std::set<std::string> registered = registered_point_peers();
    for (const auto& name : names) EXPECT_TRUE(registered.count(name)) << name << " has no knn line in peer_registry.hpp";
#if SPATIAL_EVERY_PEER_ADAPTER_BUILT
    EXPECT_EQ(names, registered);
#endif
    if (names.empty()) GTEST_SKIP() << "no peer adapter configured";
}

// The capabilities each adapter reports are the ones its registry line documents: the suites
// choose workloads by them (rebuilds_on_query keeps CGAL's deferred rebuild out of the timed
// dynamic workloads, dynamic_variant keeps the dynamic configurations out of the static ones),
// and this file's answer tests by them too.
TYPED_TEST(adapters_test, capabilities_are_as_registered) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (const auto& index : harness::make_peer_indices<T, D>(true)) {
        SCOPED_TRACE(index->name() + " " + index->configuration());
        const harness::structure_info* entry = harness::find_peer(index->name());
        ASSERT_NE(entry, nullptr);
        ASSERT_FALSE(entry->capabilities.empty()) << "its registry line lists no capabilities";
        EXPECT_EQ(harness::capability_names(index->capabilities()), entry->capabilities);
        if (!index->can(capability::dynamic)) {
            EXPECT_THROW(index->insert(0, pt<T, D>{}), std::logic_error);
            EXPECT_THROW(index->erase(0), std::logic_error);
        }
    }
}

TYPED_TEST(adapters_test, static_queries_match_brute_force) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for_each_seeded_peer<T, D>(0, peers::all, [&](const auto& index, std::mt19937_64& rng) {
        const auto pts = build_on_uniform_points(*index, rng, n_points);
        const auto live = as_live(pts);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, n_queries));
        EXPECT_GE(index->memory_bytes(), pts.size() * sizeof(pt<T, D>));
    });
}

TYPED_TEST(adapters_test, clustered_points_with_duplicates_match_brute_force) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for_each_seeded_peer<T, D>(100, peers::all, [&](const auto& index, std::mt19937_64& rng) {
        // Tight Gaussian clusters, then every 7th point duplicated onto an earlier one.
        auto centres = uniform_points<T, D>(rng, 8);
        std::normal_distribution<T> g(T(0), T(0.01));
        std::vector<pt<T, D>> pts(n_points);
        for (std::size_t i = 0; i < pts.size(); ++i)
            for (std::size_t j = 0; j < D; ++j) pts[i][j] = centres[i % centres.size()][j] + g(rng);
        for (std::size_t i = 7; i < pts.size(); i += 7) pts[i] = pts[i / 7];
        index->build(pts);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, as_live(pts), rng, n_queries));
    });
}

// Integer lattice: exact coordinates, many ties, points exactly on the sphere boundary.
TYPED_TEST(adapters_test, lattice_ties_and_closed_balls) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    constexpr int side = D == 2 ? 30 : 10;
    std::vector<pt<T, D>> pts;
    std::size_t total = 1;
    for (std::size_t i = 0; i < D; ++i) total *= side;
    for (std::size_t c = 0; c < total; ++c) {
        pt<T, D> p;
        std::size_t rest = c;
        for (std::size_t i = 0; i < D; ++i) {
            p[i] = static_cast<T>(rest % side);
            rest /= side;
        }
        pts.push_back(p);
    }
    const auto live = as_live(pts);
    for (const auto& index : harness::make_peer_indices<T, D>(true)) {
        SCOPED_TRACE(index->name() + " " + index->configuration());
        index->build(pts);
        pt<T, D> centre;
        for (std::size_t i = 0; i < D; ++i) centre[i] = T(side / 2);
        // Radius 1 around a lattice point: itself + 2D neighbours, all ON the boundary.
        std::vector<neighbor<T>> out;
        index->radius(centre, T(1), out);
        EXPECT_EQ(out.size(), 1 + 2 * D);
        index->radius(centre, T(0), out);
        EXPECT_EQ(out.size(), 1u);
        for (T r : {T(1), T(2), T(3), T(0.5)}) ASSERT_NO_FATAL_FAILURE(check_radius(*index, live, centre, r));
        // Ties: k = 1 + 2D gives 0 then 2D times 1; k = 3 cuts the tie.
        for (std::size_t k : {std::size_t{1}, std::size_t{3}, 1 + 2 * D, std::size_t{30}})
            ASSERT_NO_FATAL_FAILURE(check_knn(*index, live, centre, k, T(0)));
        // A query in the middle of a cell: 2^D points tie at the nearest distance.
        pt<T, D> mid = centre;
        for (std::size_t i = 0; i < D; ++i) mid[i] += T(0.5);
        for (std::size_t k : {std::size_t{1}, std::size_t{1} << D, std::size_t{20}})
            ASSERT_NO_FATAL_FAILURE(check_knn(*index, live, mid, k, T(0)));
        for (T eps : {T(0.5), T(2)}) ASSERT_NO_FATAL_FAILURE(check_knn(*index, live, mid, 10, eps));
        ASSERT_NO_FATAL_FAILURE(check_radius(*index, live, mid, std::sqrt(T(D)) / T(2)));
    }
}

TYPED_TEST(adapters_test, empty_single_and_rebuild) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for_each_seeded_peer<T, D>(200, peers::all, [&](const auto& index, std::mt19937_64& rng) {
        std::vector<neighbor<T>> out;
        const pt<T, D> q{};
        // Queries before any build, then on an empty build.
        index->knn(q, 5, T(0), out);
        EXPECT_TRUE(out.empty());
        index->build(std::span<const pt<T, D>>{});
        expect_holds_nothing(*index, q, 5, out);
        // One point.
        const auto one = build_on_uniform_points(*index, rng, 1);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, as_live(one), rng, 5));
        // Rebuild replaces the contents (smaller, then larger).
        const auto a = uniform_points<T, D>(rng, 500);
        const auto b = uniform_points<T, D>(rng, 50, T(2), T(3));
        index->build(a);
        index->build(b);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, as_live(b), rng, 10));
        index->build(a);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, as_live(a), rng, 10));
        // Bad parameters.
        EXPECT_THROW(index->knn(q, 1, T(-1), out), std::invalid_argument);
        EXPECT_THROW(index->radius(q, std::numeric_limits<T>::quiet_NaN(), out), std::invalid_argument);
        index->radius(q, T(-1), out);
        EXPECT_TRUE(out.empty());
    });
}

// Insert/erase sequences with sparse and reused ids, bulk inserts, coincident points and
// emptying the index, each phase checked against brute force over the live set.
TYPED_TEST(adapters_test, dynamic_sequences_match_brute_force) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for_each_seeded_peer<T, D>(300, peers::dynamic, [&](const auto& index, std::mt19937_64& rng) {
        constexpr std::size_t q_per_phase = 12;

        auto pick_live = [&](const live_set<T, D>& live, std::size_t count) {
            std::vector<std::uint32_t> ids;
            for (const auto& [id, p] : live) ids.push_back(id);
            std::sort(ids.begin(), ids.end());
            std::shuffle(ids.begin(), ids.end(), rng);
            ids.resize(std::min(count, ids.size()));
            return ids;
        };

        const auto initial = build_on_uniform_points(*index, rng, 1000);
        index->prepare_dynamic();  // what the harness calls, untimed, before dynamic work
        auto live = as_live(initial);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));

        // 1. Erase 300 random ids.
        std::vector<std::uint32_t> erased = pick_live(live, 300);
        for (auto id : erased) {
            index->erase(id);
            live.erase(id);
        }
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));

        // 2. Insert 400 points with sparse ids, querying in between (CGAL rebuilds lazily).
        std::uniform_int_distribution<std::uint32_t> sparse(1000, 50000);
        const auto fresh = uniform_points<T, D>(rng, 400);
        for (std::size_t i = 0; i < fresh.size(); ++i) {
            std::uint32_t id;
            do id = sparse(rng);
            while (live.count(id));
            index->insert(id, fresh[i]);
            live.emplace(id, fresh[i]);
            if (i % 100 == 99) {
                ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, 3));
            }
        }
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));

        // 3. Reuse 100 erased ids with new coordinates.
        const auto moved = uniform_points<T, D>(rng, 100);
        for (std::size_t i = 0; i < moved.size(); ++i) {
            index->insert(erased[i], moved[i]);
            live.emplace(erased[i], moved[i]);
        }
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));

        // 4. Bulk insert with consecutive ids.
        const auto bulk = uniform_points<T, D>(rng, 200);
        index->insert_bulk(60000, bulk);
        for (std::size_t i = 0; i < bulk.size(); ++i) live.emplace(60000 + static_cast<std::uint32_t>(i), bulk[i]);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));

        // 5. Coincident points: five copies of a live point; erasing one of them by id must
        //    remove exactly that id (an adapter that erases "a point at these coordinates"
        //    would take the wrong one). Each erase runs on a built tree (a query first).
        const std::uint32_t original = pick_live(live, 1).front();
        const auto spot = live.at(original);
        for (std::uint32_t c = 0; c < 5; ++c) {
            index->insert(70000 + c, spot);
            live.emplace(70000 + c, spot);
        }
        std::vector<neighbor<T>> out;
        auto ids_at_spot = [&] {
            index->radius(spot, T(0), out);
            std::set<std::uint32_t> ids;
            for (const auto& nb : out) ids.insert(nb.id);
            return ids;
        };
        EXPECT_EQ(ids_at_spot(), (std::set<std::uint32_t>{original, 70000, 70001, 70002, 70003, 70004}));
        for (std::uint32_t victim : {std::uint32_t{70002}, std::uint32_t{70004}, original}) {
            index->erase(victim);
            live.erase(victim);
            std::set<std::uint32_t> expected;
            for (const auto& [id, p] : live)
                if (p == spot) expected.insert(id);
            EXPECT_EQ(ids_at_spot(), expected) << "after erasing " << victim;
        }
        ASSERT_NO_FATAL_FAILURE(check_ids(live, spot, out));
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));

        // 6. Contract violations are reported, not silently absorbed.
        EXPECT_THROW(index->erase(original), std::invalid_argument);
        EXPECT_THROW(index->insert(70000, spot), std::invalid_argument);
        EXPECT_EQ(index->size(), live.size());

        // 7. Erase all but three, then all, then refill.
        auto all_ids = pick_live(live, live.size());
        for (std::size_t i = 3; i < all_ids.size(); ++i) {
            index->erase(all_ids[i]);
            live.erase(all_ids[i]);
        }
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));
        for (std::size_t i = 0; i < 3; ++i) {
            index->erase(all_ids[i]);
            live.erase(all_ids[i]);
        }
        expect_holds_nothing(*index, spot, 3, out);
        const auto refill = uniform_points<T, D>(rng, 50);
        for (std::size_t i = 0; i < refill.size(); ++i) {
            index->insert(static_cast<std::uint32_t>(i), refill[i]);
            live.emplace(static_cast<std::uint32_t>(i), refill[i]);
        }
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));
        EXPECT_GT(index->memory_bytes(), refill.size() * sizeof(pt<T, D>));

        // 8. build() resets everything, including ids.
        const auto rebuilt = uniform_points<T, D>(rng, 300);
        index->build(rebuilt);
        live = as_live(rebuilt);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));
        index->insert(5000, rebuilt[0]);
        live.emplace(5000, rebuilt[0]);
        index->erase(7);
        live.erase(7);
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, q_per_phase));
    });
}

// Dynamic adapters built by insertions only (no build() call at all).
TYPED_TEST(adapters_test, dynamic_from_scratch) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for_each_seeded_peer<T, D>(400, peers::dynamic, [&](const auto& index, std::mt19937_64& rng) {
        const auto pts = uniform_points<T, D>(rng, 700);
        live_set<T, D> live;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const auto id = static_cast<std::uint32_t>(3 * i + 11);
            index->insert(id, pts[i]);
            live.emplace(id, pts[i]);
        }
        ASSERT_NO_FATAL_FAILURE(check_all(*index, live, rng, 20));
    });
}

TYPED_TEST(adapters_test, memory_and_node_counters) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for_each_seeded_peer<T, D>(500, peers::all, [&](const auto& index, std::mt19937_64& rng) {
        const auto pts = build_on_uniform_points(*index, rng, n_points);
        const std::size_t bytes = index->memory_bytes();
        // At least the points, and not absurdly more (nodes + permutations are O(n)). The
        // largest overhead is the R-tree built by insertion: fixed-capacity nodes (17 values
        // of 32 B in 3D double) about 60% full, plus its adapter's id -> point table.
        EXPECT_GE(bytes, pts.size() * sizeof(pt<T, D>));
        EXPECT_LE(bytes, pts.size() * (sizeof(pt<T, D>) + 128) + (1u << 16));
        std::vector<neighbor<T>> out;
        index->knn(pts[0], 10, T(0), out);
        const long long visited = index->last_nodes_visited();
        if (index->name() == "cgal_kd_tree") {
            EXPECT_GT(visited, 0);
        } else {
            EXPECT_EQ(visited, -1);
        }
    });
}

}  // namespace

// A setting a peer cannot run is an error naming the peer and the setting, not a silent
// default; a sweep configuration naming a setting its registry line lacks is a logic error.
TEST(tuning_sweep, bad_settings_are_errors_that_name_them) {
    const harness::key_values no_setting{};
    EXPECT_THROW(harness::count_setting(no_setting, "bucket_size", "cgal_kd_tree"), std::invalid_argument);
    for (const char* bad : {"0", "-3", "ten", "32x", ""}) {
        const harness::key_values settings{{"leaf_max_size", bad}};
        try {
            harness::count_setting(settings, "leaf_max_size", "nanoflann");
            ADD_FAILURE() << "leaf_max_size=" << bad << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("nanoflann: setting leaf_max_size="), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(harness::switch_setting({{"points_cache", "yes"}}, "points_cache", "cgal_kd_tree"), std::invalid_argument);
    EXPECT_THROW(harness::configurations("cgal_kd_tree", {{"bucket_size", "10"}}, true), std::logic_error);
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    EXPECT_THROW((harness::make_cgal_kd_tree_index<double, 3>({{"bucket_size", "0"}, {"points_cache", "off"}})),
                 std::invalid_argument);
#endif
}

// Each swept configuration is one index, labelled with what it changes; the default is first
// and unlabelled, and the sweep names every setting it changes in the registry's terms.
TEST(tuning_sweep, configurations_overlay_the_registry_settings) {
    const auto c = harness::configurations("cgal_kd_tree", harness::find_peer("cgal_kd_tree")->settings, true);
    ASSERT_EQ(c.size(), 1 + harness::tuning_sweep("cgal_kd_tree").size());
    EXPECT_EQ(c[0].params, "");
    EXPECT_EQ(harness::params_of(c[0].settings), "bucket_size=10;points_cache=off");
    bool found = false;
    for (const auto& x : c)
        if (x.params == "bucket_size=32;points_cache=on") {
            found = true;
            EXPECT_EQ(harness::params_of(x.settings), "bucket_size=32;points_cache=on");
        }
    EXPECT_TRUE(found);
    EXPECT_EQ(harness::configurations("cgal_kd_tree", harness::find_peer("cgal_kd_tree")->settings, false).size(), 1u);
}
