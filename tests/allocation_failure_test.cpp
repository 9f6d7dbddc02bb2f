// Exception safety under allocation failure (docs/contract.md, "Exception safety"): every
// mutation of every structure is run once to count its allocations, then again failing at
// the k-th allocation for EVERY k = 1..count (failing_allocation.hpp). After each failure the
// structure must keep the guarantee the contract documents for that operation:
//   strong — the same elements in the same slots, the same end(), sound invariants, and every
//            query answering as brute_force over those elements;
//   basic  — sound invariants, queries answering as brute_force over whatever it now holds,
//            and still usable (inserts and erases after the failure stay correct).
// Leaks are LeakSanitizer's to catch (this binary runs in the sanitizer build).
// The number of injected failures per structure is printed at the end of each suite: these
// are the figures docs/contract.md quotes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <ostream>
#include <map>
#include <new>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "failing_allocation.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/ellipsoid.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/sweep_and_prune.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/octree/octree.hpp"
#include "test_support.hpp"

namespace {

using namespace spatial;
using spatial_test::B3;
using spatial_test::P3;
namespace fa = spatial_test::failing_allocation;

enum class guarantee { strong, basic };

// ---- names, for failure messages and the printed figures -------------------------------------
template <class C>
std::string structure_label() {
    std::string name;
    if constexpr (requires { typename C::volume_type; }) name = "bvh<" + C::volume_name() + ">";
    else if constexpr (requires { C::structure_name; }) name = C::structure_name;
    else if constexpr (std::is_same_v<C, collision_grid<typename C::value_type>>) name = "collision_grid";
    else name = "sweep_and_prune";
    return name + (std::is_same_v<typename C::value_type, P3> ? " of points" : " of boxes");
}

// ---- the state compared by the strong guarantee ------------------------------------------------
// Every element with its slot (the handle an iterator holds), and end().
struct slot_contents {
    std::size_t end_slot = 0;
    std::vector<std::pair<slot_index, std::vector<double>>> elements;
    friend bool operator==(const slot_contents&, const slot_contents&) = default;
    // For GoogleTest's messages: the size, end() and the occupied slots.
    friend void PrintTo(const slot_contents& s, std::ostream* os) {
        *os << s.elements.size() << " elements, end() = slot " << s.end_slot << ", slots {";
        for (const auto& e : s.elements) *os << ' ' << e.first;
        *os << " }";
    }
};
template <class C>
slot_contents slots_of(const C& c) {
    slot_contents s;
    s.end_slot = c.end().slot();
    for (auto it = c.begin(); it != c.end(); ++it) s.elements.emplace_back(it.slot(), spatial_test::signature(*it));
    return s;
}

// The iterator of slot s in c (c may be a copy of the container the slot was taken from).
template <class C>
typename C::iterator at_slot(const C& c, slot_index s) {
    for (auto it = c.begin(); it != c.end(); ++it)
        if (it.slot() == s) return it;
    ADD_FAILURE() << "no element in slot " << s;
    return c.end();
}

// ---- objects of the workloads --------------------------------------------------------------
template <class O>
O object_at(const P3& p) {
    return spatial_test::object_factory<O>::at(p, 0.02, 0);
}
template <class O>
std::vector<O> random_objects(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<O> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back(object_at<O>(P3{{u(rng), u(rng), u(rng)}}));
    return v;
}

// ---- checks after an operation ------------------------------------------------------------
template <class C>
void expect_sound(const C& c, const std::string& where) {
    if constexpr (requires { c.check_invariants(); }) {
        EXPECT_EQ(c.check_invariants(), "") << where;
    }
    std::size_t n = 0;
    for (auto it = c.begin(); it != c.end(); ++it) ++n;
    EXPECT_EQ(n, c.size()) << where;
}

// Every query of c answers as brute_force over c's own elements.
template <class C>
void expect_answers_like_brute_force(const C& c, const std::string& where) {
    using O = typename C::value_type;
    brute_force<O> oracle;
    oracle.insert(c.begin(), c.end());
    const std::vector<P3> probes{P3{{0.5, 0.5, 0.5}}, P3{{0.1, 0.9, 0.2}}, P3{{1.2, -0.1, 0.4}}};
    for (const P3& q : probes) {
        const P3 lo{{q[0] - 0.3, q[1] - 0.3, q[2] - 0.3}}, hi{{q[0] + 0.3, q[1] + 0.3, q[2] + 0.3}};
        EXPECT_EQ(spatial_test::signatures_of(c.find_in_box(lo, hi)), spatial_test::signatures_of(oracle.find_in_box(lo, hi)))
            << where;
        if constexpr (spatial_container<C>) {
            EXPECT_EQ(spatial_test::distances_from(q, c.find_nearest(q, 5)), spatial_test::distances_from(q, oracle.find_nearest(q, 5)))
                << where;
            EXPECT_EQ(spatial_test::signatures_of(c.find_in_ball(q, 0.25)), spatial_test::signatures_of(oracle.find_in_ball(q, 0.25)))
                << where;
            intersect_info<P3> a, b;
            const P3 direction{{0.3, -0.2, 1.0}};
            const P3 origin{{q[0], q[1], -1.0}};
            EXPECT_EQ(c.intersect(origin, direction, 0.05, a), oracle.intersect(origin, direction, 0.05, b)) << where;
            EXPECT_EQ(a.hit_time, b.hit_time) << where;
        }
    }
    if constexpr (spatial_container<C>) {
        if (!c.empty()) {
            EXPECT_EQ(c.count(*c.begin()), oracle.count(*c.begin())) << where;
        }
    }
    if constexpr (pair_search<C>) {
        EXPECT_EQ(spatial_test::signature_pairs(c.self_pairs(pair_filter::exact)),
                  spatial_test::signature_pairs(oracle.self_pairs(pair_filter::exact)))
            << where;
    }
}

// After a failure the structure keeps working: inserts and an erase stay correct.
template <class C>
void expect_usable(C c, const std::string& where) {
    using O = typename C::value_type;
    for (const O& x : random_objects<O>(3, 99)) c.insert(x);
    if (!c.empty()) c.erase(c.begin());
    expect_sound(c, where + ", then 3 inserts and an erase");
    expect_answers_like_brute_force(c, where + ", then 3 inserts and an erase");
}

// ---- the driver --------------------------------------------------------------------------
struct tally {
    std::size_t operations = 0;
    std::size_t failure_points = 0;
};
// Injected failures per structure and operation, printed by the suite's TearDownTestSuite.
std::map<std::string, std::map<std::string, tally>>& figures() {
    static std::map<std::string, std::map<std::string, tally>> f;
    return f;
}

// The allocations a mutation's test fails, one run each: every one up to max_failure_points;
// beyond that (a batched update of convex-hull volumes allocates tens of thousands of times,
// and each run copies and checks the whole structure: hours), the first half of the budget and
// then evenly spaced ones up to the last, so the start, the whole range and the end are all
// failed. The figures count the points run.
constexpr std::size_t max_failure_points = 2000;
inline std::size_t next_failure_point(std::size_t k, std::size_t allocations) {
    if (allocations <= max_failure_points || k < max_failure_points / 2) return k + 1;
    const std::size_t stride = (allocations - max_failure_points / 2) / (max_failure_points / 2) + 1;
    return k == allocations ? k + 1 : std::min(k + stride, allocations);
}

// Applies `op` to a copy of `before` without failure (counting its allocations), then to a
// fresh copy once per allocation, failing at that allocation, and checks the guarantee `g`.
// `prepare(copy)` makes op's arguments (a batch of the copy's iterators) before counting
// starts, so that only the operation's own allocations fail.
template <class C, class Prepare, class Op>
void inject_every_failure(const C& before, Prepare prepare, Op op, guarantee g, const std::string& operation) {
    tally& t = figures()[structure_label<C>()][operation];
    ++t.operations;
    C reference = before;
    auto reference_arguments = prepare(reference);
    fa::reset_count();
    op(reference, reference_arguments);
    const std::size_t allocations = fa::count();
    expect_sound(reference, operation + " without failure");
    const slot_contents untouched = slots_of(before);
    for (std::size_t k = 1; k <= allocations; k = next_failure_point(k, allocations)) {
        const std::string where = structure_label<C>() + ", " + operation + ", allocation " + std::to_string(k) +
                                  " of " + std::to_string(allocations) + " failed";
        C c = before;
        auto arguments = prepare(c);
        bool threw = false;
        {
            fa::armed fail(k);
            try {
                op(c, arguments);
            } catch (const std::bad_alloc&) {
                threw = true;
            }
        }
        ++t.failure_points;
        if (!threw) {
            // The failure was absorbed (a nothrow allocation with a fallback, e.g. stable_sort's
            // buffer): the operation must then have done its whole work.
            EXPECT_EQ(spatial_test::contents(c), spatial_test::contents(reference)) << where << " (absorbed)";
        } else if (g == guarantee::strong) {
            EXPECT_EQ(slots_of(c), untouched) << where << ": the strong guarantee keeps every element in its slot";
        }
        expect_sound(c, where);
        expect_answers_like_brute_force(c, where);
        expect_usable(c, where);
        if (::testing::Test::HasFailure()) return;  // one broken state is enough to report
    }
}
// The same for an operation without prepared arguments.
template <class C, class Op>
void inject_every_failure(const C& before, Op op, guarantee g, const std::string& operation) {
    inject_every_failure(before, [](C&) { return 0; }, [&](C& d, int) { op(d); }, g, operation);
}

// ---- the guarantee each structure documents, per operation ---------------------------------
enum class operation {
    insert,
    hinted_insert,
    bulk_insert,
    erase_iterator,
    erase_value,
    erase_range,
    update_single,
    update_batched
};
// Strong everywhere, except a bvh's batched move by reinsertion (and the automatic strategy,
// which may choose it): each object's reinsertion is all or nothing, the batch is not.
template <class C>
constexpr guarantee documented(operation op, motion_strategy s = motion_strategy::refit) {
    if (op == operation::update_batched && (s == motion_strategy::reinsert || s == motion_strategy::automatic))
        return guarantee::basic;
    return guarantee::strong;
}

// ---- the suite ---------------------------------------------------------------------------
template <class C>
class allocation_failure : public ::testing::Test {
public:
    static void TearDownTestSuite() {
        std::size_t total = 0, operations = 0;
        for (const auto& [op, t] : figures()[structure_label<C>()]) {
            std::printf("[ figures  ] %s: %s: %zu operations, %zu failure points\n", structure_label<C>().c_str(),
                        op.c_str(), t.operations, t.failure_points);
            total += t.failure_points, operations += t.operations;
        }
        std::printf("[ figures  ] %s: total %zu operations, %zu failure points\n", structure_label<C>().c_str(), operations,
                    total);
    }

protected:
    // A structure holding `objects`, inserted one by one (so trees grow by splits, grids by
    // rehashing, as in use).
    static C filled(const std::vector<typename C::value_type>& objects) {
        C c;
        for (const auto& x : objects) c.insert(x);
        return c;
    }
};

template <class O>
using structures_of =
    ::testing::Types<brute_force<O>, kd_tree<O>, octree<O>, uniform_grid<O>, hashed_grid<O>, bvh<O>,
                     bvh<O, sphere<double, 3>>, bvh<O, obb<double, 3>>, bvh<O, kdop<double, 3, 26>>,
                     bvh<O, ellipsoid<double, 3>>, bvh<O, convex_hull<double, 3>>, collision_grid<O>, sweep_and_prune<O>>;
template <class A, class B>
struct concatenated;
template <class... A, class... B>
struct concatenated<::testing::Types<A...>, ::testing::Types<B...>> {
    using type = ::testing::Types<A..., B...>;
};
// The sanitizer build (SPATIAL_TEST_FULL_MATRIX=0) leaves out the bvh volumes whose fits
// allocate hundreds of times per insertion (kdop, ellipsoid, convex_hull: minutes each under
// ASan); the release build runs every structure over points and boxes.
#if SPATIAL_TEST_FULL_MATRIX
using every_structure = concatenated<structures_of<P3>, structures_of<B3>>::type;
#else
template <class O>
using light_structures_of = ::testing::Types<brute_force<O>, kd_tree<O>, octree<O>, uniform_grid<O>, hashed_grid<O>, bvh<O>,
                                             bvh<O, sphere<double, 3>>, bvh<O, obb<double, 3>>, collision_grid<O>,
                                             sweep_and_prune<O>>;
using every_structure = concatenated<light_structures_of<P3>, light_structures_of<B3>>::type;
#endif
TYPED_TEST_SUITE(allocation_failure, every_structure);

constexpr std::size_t grown = 40;  // past a kd-tree leaf (32), an octree cell's split, grid rehashes

// Every structure's moves cannot throw, so that a std::vector of structures moves them when it
// grows (std::move_if_noexcept) instead of copying. They can be noexcept because they only
// swap or move members (vectors, scalars, a shared pointer) and the moved-from source is left
// the empty structure of the default constructor, which allocates nothing: kd_tree's and
// bvh's empty tree has no root node until the first insertion (their "unallocated" state,
// docs/contract.md, moved-from containers). Before that, their empty tree allocated its root,
// so their moves were noexcept(false) and this test listed them as the exception.
TYPED_TEST(allocation_failure, moves_cannot_throw_where_the_members_allow_it) {
    using C = TypeParam;
    static_assert(std::is_nothrow_move_constructible_v<C> && std::is_nothrow_move_assignable_v<C>);
    // kd_tree's and bvh's moves start from their default constructor (the source receives the
    // empty tree it makes), which therefore cannot throw either.
    if constexpr (std::is_same_v<C, kd_tree<typename C::value_type>> || requires { typename C::volume_type; })
        static_assert(std::is_nothrow_default_constructible_v<C>);
}

// What makes the moves above noexcept, observed: default construction, move construction and
// move assignment allocate nothing (nor does the moved-from source), and the moved-from source
// then works as a new structure (its first insertion allocates what it needs).
TYPED_TEST(allocation_failure, default_construction_and_moves_allocate_nothing) {
    using C = TypeParam;
    using O = typename C::value_type;
    const auto objects = random_objects<O>(grown, 12);
    C source = this->filled(objects), target = this->filled(random_objects<O>(5, 13));
    fa::reset_count();
    {
        C fresh;
        C moved(std::move(source));
        target = std::move(moved);
        moved = std::move(fresh);  // NOLINT(bugprone-use-after-move): moved-from is empty and usable
        source = std::move(moved);
    }
    EXPECT_EQ(fa::count(), 0u) << structure_label<C>();
    EXPECT_EQ(target.size(), objects.size());
    EXPECT_TRUE(source.empty());  // NOLINT(bugprone-use-after-move)
    expect_sound(source, structure_label<C>() + ", moved from");
    expect_answers_like_brute_force(source, structure_label<C>() + ", moved from");
    expect_usable(source, structure_label<C>() + ", moved from");
    expect_sound(target, structure_label<C>() + ", moved to");
    expect_answers_like_brute_force(target, structure_label<C>() + ", moved to");
}

TYPED_TEST(allocation_failure, insert_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    const auto objects = random_objects<O>(grown, 1);
    C c;
    for (const O& x : objects) {
        inject_every_failure(c, [&](C& d) { d.insert(x); }, documented<C>(operation::insert), "insert");
        if (this->HasFailure()) return;
        c.insert(x);
    }
}

TYPED_TEST(allocation_failure, hinted_insert_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    if constexpr (!spatial_container<C>) GTEST_SKIP() << "no hinted insert";
    else {
        const auto objects = random_objects<O>(grown, 2);
        C c;
        slot_index last = 0;
        for (const O& x : objects) {
            const bool has_hint = !c.empty();
            inject_every_failure(
                c, [&](C& d) { d.insert(has_hint ? at_slot(d, last) : d.end(), x); }, documented<C>(operation::hinted_insert),
                "hinted insert");
            if (this->HasFailure()) return;
            last = c.insert(x).slot();
        }
    }
}

TYPED_TEST(allocation_failure, bulk_insert_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    const auto batch = random_objects<O>(grown, 3);
    // Into an empty structure (the bulk build), and into a filled one: a small batch, one as
    // large as the contents (the kd-tree rebuilds), one larger.
    const C empty;
    inject_every_failure(empty, [&](C& d) { d.insert(batch.begin(), batch.end()); },
                               documented<C>(operation::bulk_insert), "bulk insert");
    const C some = this->filled(random_objects<O>(24, 4));
    for (std::size_t m : {3u, 24u, 40u})
        inject_every_failure(some, [&](C& d) { d.insert(batch.begin(), batch.begin() + m); },
                                   documented<C>(operation::bulk_insert), "bulk insert");
}

TYPED_TEST(allocation_failure, erase_by_iterator_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    C c = this->filled(random_objects<O>(grown, 5));
    // Erase down to a few elements: trees merge leaves and rebuild on the way.
    while (c.size() > 4) {
        const slot_index s = std::next(c.begin(), static_cast<std::ptrdiff_t>(c.size() / 2)).slot();
        inject_every_failure(c, [&](C& d) { d.erase(at_slot(d, s)); }, documented<C>(operation::erase_iterator),
                                   "erase(iterator)");
        if (this->HasFailure()) return;
        c.erase(at_slot(c, s));
    }
}

TYPED_TEST(allocation_failure, erase_by_value_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    if constexpr (!spatial_container<C>) GTEST_SKIP() << "no erase by value";
    else {
        // Each value three times: erase(value) removes all copies.
        const auto values = random_objects<O>(grown / 3, 6);
        std::vector<O> stored;
        for (int copy = 0; copy < 3; ++copy) stored.insert(stored.end(), values.begin(), values.end());
        C c = this->filled(stored);
        for (const O& x : values) {
            inject_every_failure(c, [&](C& d) { d.erase(x); }, documented<C>(operation::erase_value), "erase(value)");
            if (this->HasFailure()) return;
            c.erase(x);
        }
    }
}

TYPED_TEST(allocation_failure, erase_range_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    if constexpr (!spatial_container<C>) GTEST_SKIP() << "no range erase";
    else {
        const C c = this->filled(random_objects<O>(grown, 7));
        // Below a quarter of the contents (erased one by one) and above (the survivors rebuilt).
        for (std::size_t m : {5u, 10u, 25u}) {
            const slot_index first = std::next(c.begin(), 3).slot();
            const slot_index last = std::next(c.begin(), static_cast<std::ptrdiff_t>(3 + m)).slot();
            inject_every_failure(c, [&](C& d) { d.erase(at_slot(d, first), at_slot(d, last)); },
                                       documented<C>(operation::erase_range), "erase(first, last)");
        }
    }
}

// Objects of very different sizes: boxes hundreds of times larger than the rest (a grid keeps
// them in its list of large objects, grid_core.hpp large_object_cells), inserted one by one and
// in bulk among small ones, then erased. Points have no extent, so this runs on boxes.
TYPED_TEST(allocation_failure, large_objects_keep_the_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    if constexpr (!std::is_same_v<O, B3>) GTEST_SKIP() << "points have no extent";
    else {
        std::vector<O> large;
        for (int i = 0; i < 4; ++i) large.push_back(B3(P3{{-5.0 - i, -5, 0.1 * i}}, P3{{6.0 + i, 6, 0.1 * i + 0.05}}));
        C c = this->filled(random_objects<O>(grown, 14));
        for (const O& x : large) {
            inject_every_failure(c, [&](C& d) { d.insert(x); }, documented<C>(operation::insert), "insert (large)");
            if (this->HasFailure()) return;
            c.insert(x);
        }
        const C some = this->filled(random_objects<O>(24, 15));
        inject_every_failure(some, [&](C& d) { d.insert(large.begin(), large.end()); }, documented<C>(operation::bulk_insert),
                             "bulk insert (large)");
        for (const O& x : large) {
            const slot_index s = std::find(c.begin(), c.end(), x).slot();
            inject_every_failure(c, [&](C& d) { d.erase(at_slot(d, s)); }, documented<C>(operation::erase_iterator),
                                 "erase(iterator) (large)");
            if (this->HasFailure()) return;
            c.erase(at_slot(c, s));
        }
    }
}

// Moves of stored objects: near (within their cell or leaf) and far (across the space).
template <class O>
std::vector<O> moved_objects(std::size_t n, std::uint64_t seed) {
    auto v = random_objects<O>(n, seed);
    for (std::size_t i = 0; i < n; i += 2) v[i] = object_at<O>(P3{{1.5 + 0.01 * double(i), -0.5, 0.5}});
    return v;
}

TYPED_TEST(allocation_failure, single_update_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    if constexpr (!single_motion<C>) GTEST_SKIP() << "no update";
    else {
        C c = this->filled(random_objects<O>(grown, 8));
        const auto targets = moved_objects<O>(12, 9);
        for (std::size_t i = 0; i < targets.size(); ++i) {
            const slot_index s = std::next(c.begin(), static_cast<std::ptrdiff_t>(3 * i)).slot();
            inject_every_failure(c, [&](C& d) { d.update(at_slot(d, s), targets[i]); },
                                       documented<C>(operation::update_single), "update(iterator, value)");
            if (this->HasFailure()) return;
            c.update(at_slot(c, s), targets[i]);
        }
    }
}

TYPED_TEST(allocation_failure, batched_update_keeps_its_documented_guarantee) {
    using C = TypeParam;
    using O = typename C::value_type;
    if constexpr (!batched_motion<C>) GTEST_SKIP() << "no batched update";
    else {
        const C c = this->filled(random_objects<O>(grown, 10));
        const auto targets = moved_objects<O>(grown, 11);
        // A batch moving every fourth object (automatic: reinsert) and one moving all (rebuild).
        for (std::size_t stride : {4u, 1u}) {
            std::vector<std::pair<slot_index, O>> moves;
            std::size_t i = 0;
            for (auto it = c.begin(); it != c.end(); ++it, ++i)
                if (i % stride == 0) moves.emplace_back(it.slot(), targets[i]);
            auto batch_of = [&](const C& d) {
                std::vector<std::pair<typename C::iterator, O>> b;
                for (const auto& [s, v] : moves) b.emplace_back(at_slot(d, s), v);
                return b;
            };
            using batch = std::vector<std::pair<typename C::iterator, O>>;
            if constexpr (motion_with_strategy<C>) {
                for (motion_strategy strategy : {motion_strategy::refit, motion_strategy::rebuild, motion_strategy::reinsert,
                                                 motion_strategy::automatic}) {
                    inject_every_failure(
                        c, batch_of, [&](C& d, batch& b) { d.update(b.begin(), b.end(), strategy); },
                        documented<C>(operation::update_batched, strategy),
                        "update(first, last, " + std::string(to_string(strategy)) + ")");
                }
            } else {
                inject_every_failure(
                    c, batch_of, [&](C& d, batch& b) { d.update(b.begin(), b.end()); },
                    documented<C>(operation::update_batched), "update(first, last)");
            }
        }
    }
}

}  // namespace
