// Differential property tests: long random sequences of every operation applied to a
// structure and to the brute-force oracle; every answer must agree (compared by distance,
// since ties make identities ambiguous). Seeds are logged; SPATIAL_TEST_SEED replays one.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "test_support.hpp"

using namespace spatial;
using spatial_test::distribution;

namespace {

template <class C>
struct differential_case {
    using P = typename C::value_type;
    using T = typename C::scalar_type;
    static constexpr std::size_t D = C::dimension;

    static void run(distribution dist, std::uint64_t seed, int steps) {
        SCOPED_TRACE(std::string("distribution=") + spatial_test::name_of(dist) + " " + spatial_test::replay_hint(seed));
        spatial_test::point_source<P> src(dist, seed);
        C tree;
        brute_force<P> oracle;
        std::vector<typename C::iterator> handles;  // live iterators into `tree`
        auto drop_dead = [&](const P& gone_value, std::size_t how_many) {
            // erase(value) removed every copy: forget handles to them.
            std::size_t removed = 0;
            handles.erase(std::remove_if(handles.begin(), handles.end(),
                                         [&](auto it) {
                                             if (removed < how_many && *it == gone_value) {
                                                 ++removed;
                                                 return true;
                                             }
                                             return false;
                                         }),
                          handles.end());
        };
        for (int step = 0; step < steps; ++step) {
            const std::uint64_t op = src.bits() % 100;
            SCOPED_TRACE("step " + std::to_string(step) + " op " + std::to_string(op));
            if (op < 25) {  // insert
                const P p = src.next();
                handles.push_back(tree.insert(p));
                oracle.insert(p);
            } else if (op < 35) {  // hinted insert near a random live element
                const P p = src.next();
                auto hint = handles.empty() ? tree.end() : handles[src.bits() % handles.size()];
                handles.push_back(tree.insert(hint, p));
                oracle.insert(p);
            } else if (op < 38) {  // bulk insert
                std::vector<P> batch;
                const std::size_t m = 1 + src.bits() % (src.bits() % 4 == 0 ? 400 : 20);
                for (std::size_t i = 0; i < m; ++i) batch.push_back(src.next());
                tree.insert(batch.begin(), batch.end());
                oracle.insert(batch.begin(), batch.end());
                handles.clear();  // bulk insert returns no iterators; rebuild the handle list
                for (auto it = tree.begin(); it != tree.end(); ++it) handles.push_back(it);
            } else if (op < 50 && !handles.empty()) {  // erase by iterator
                const std::size_t i = src.bits() % handles.size();
                const P v = *handles[i];
                tree.erase(handles[i]);
                handles[i] = handles.back();
                handles.pop_back();
                // The oracle erases all copies, then gets back all but one.
                const std::size_t copies = oracle.erase(v);
                ASSERT_GE(copies, 1u);
                for (std::size_t r = 1; r < copies; ++r) oracle.insert(v);
                ASSERT_EQ(tree.count(v), copies - 1);
            } else if (op < 55 && !handles.empty()) {  // erase by value (all copies)
                const P v = *handles[src.bits() % handles.size()];
                const std::size_t expected = oracle.count(v);
                ASSERT_EQ(tree.erase(v), expected);
                ASSERT_EQ(oracle.erase(v), expected);
                drop_dead(v, expected);
            } else if (op < 57 && tree.size() > 0) {  // bulk erase of a range
                auto first = tree.begin();
                std::advance(first, static_cast<long>(src.bits() % tree.size()));
                auto last = first;
                const std::size_t span = src.bits() % 3 == 0 ? tree.size() : 1 + src.bits() % 30;
                for (std::size_t i = 0; i < span && last != tree.end(); ++i) ++last;
                std::vector<P> gone(first, last);
                tree.erase(first, last);
                for (const P& v : gone) {
                    const std::size_t c = oracle.count(v);
                    oracle.erase(v);
                    for (std::size_t r = 1; r < c; ++r) oracle.insert(v);
                }
                handles.clear();
                for (auto it = tree.begin(); it != tree.end(); ++it) handles.push_back(it);
            } else if (op < 65) {  // find / count
                const P v = (src.bits() % 2 == 0 && !handles.empty()) ? *handles[src.bits() % handles.size()] : src.next();
                ASSERT_EQ(tree.count(v), oracle.count(v));
                ASSERT_EQ(tree.find(v) != tree.end(), oracle.find(v) != oracle.end());
            } else if (op < 80) {  // kNN, exact and approximate
                const P q = src.next();
                const std::size_t k = src.bits() % 3 == 0 ? 1 : 1 + src.bits() % 25;
                const auto got = spatial_test::distances_from(q, tree.find_nearest(q, k));
                const auto want = spatial_test::distances_from(q, oracle.find_nearest(q, k));
                ASSERT_EQ(got, want) << "kNN mismatch, k=" << k;
                const T eps = T(0.5);
                const auto approx = spatial_test::distances_from(q, tree.find_nearest(q, k, eps));
                ASSERT_EQ(approx.size(), want.size());
                for (std::size_t i = 0; i < want.size(); ++i)
                    ASSERT_LE(std::sqrt(approx[i]), 1.5 * std::sqrt(want[i]) * (1 + 1e-5) + 1e-9);
            } else if (op < 88) {  // ball and box ranges
                const P q = src.next();
                const T r = static_cast<T>(src.unit() * 0.3);
                ASSERT_EQ(spatial_test::distances_from(q, tree.find_in_ball(q, r)),
                          spatial_test::distances_from(q, oracle.find_in_ball(q, r)));
                P lo = src.next(), hi = lo;
                for (std::size_t d = 0; d < D; ++d) spatial_test::set_coord(hi, d, lo[d] + src.unit() * 0.4);
                ASSERT_EQ(spatial_test::distances_from(q, tree.find_in_box(lo, hi)),
                          spatial_test::distances_from(q, oracle.find_in_box(lo, hi)));
            } else if (op < 98) {  // ray cast
                const P o = src.next();
                P dir{};
                for (std::size_t d = 0; d < D; ++d) spatial_test::set_coord(dir, d, src.unit() - 0.5);
                if (src.bits() % 4 == 0) spatial_test::set_coord(dir, src.bits() % D, src.bits() % 2 ? 0.0 : -0.0);
                bool nonzero = false;
                for (std::size_t d = 0; d < D; ++d) nonzero |= dir[d] != 0;
                if (!nonzero) continue;
                const T thick = static_cast<T>(src.unit() * 0.05);
                intersect_info<P> a, b;
                if (src.bits() % 3 == 0) a.hit_time = b.hit_time = static_cast<T>(src.unit() * 2);
                auto ta = tree.intersect_object(o, dir, thick, a);
                auto tb = oracle.intersect_object(o, dir, thick, b);
                ASSERT_EQ(ta != tree.end(), tb != oracle.end()) << "ray hit disagreement";
                ASSERT_EQ(a.hit_time, b.hit_time) << std::setprecision(17) << a.hit_time << " vs oracle " << b.hit_time << " thick " << thick;
                if (ta != tree.end()) {  // the reported object really is hit at hit_time
                    intersect_info<P> again;
                    ASSERT_TRUE(ta->intersect(o, dir, thick, again));
                    ASSERT_EQ(again.hit_time, a.hit_time);
                }
            } else if (tree.size() > 0) {  // structural check
                if constexpr (requires { tree.check_invariants(); }) {
                    ASSERT_EQ(tree.check_invariants(), "");
                }
            }
            ASSERT_EQ(tree.size(), oracle.size());
        }
        ASSERT_EQ(spatial_test::contents(tree), spatial_test::contents(oracle));
        if constexpr (requires { tree.check_invariants(); }) {
            ASSERT_EQ(tree.check_invariants(), "");
        }
    }
};

template <class C>
class differential : public ::testing::Test {};

using kd_tiny = kd_tree_config<2, median_of_widest_spread>;
using kd_small = kd_tree_config<4, median_of_widest_spread>;
using kd_mid = kd_tree_config<5, midpoint_of_max_spread>;
using structure_types =
    ::testing::Types<kd_tree<point<double, 3>>, kd_tree<point<float, 3>>, kd_tree<point<double, 2>>,
                     kd_tree<point<float, 2>>, kd_tree<point<double, 3>, kd_tiny>, kd_tree<point<float, 2>, kd_small>,
                     kd_tree<point<double, 3>, kd_mid>, kd_tree<spatial_test::tagged_point, kd_small>>;
TYPED_TEST_SUITE(differential, structure_types);

TYPED_TEST(differential, random_operation_sequences_agree_with_brute_force) {
    std::uint64_t seed = spatial_test::test_seed(20261122);
    for (distribution d : {distribution::uniform, distribution::lattice, distribution::duplicates,
                           distribution::clusters, distribution::line}) {
        for (int rep = 0; rep < 3; ++rep) {
            differential_case<TypeParam>::run(d, seed + static_cast<std::uint64_t>(rep) * 7919 + static_cast<int>(d), 4000);
            if (::testing::Test::HasFatalFailure()) return;
        }
    }
}

}  // namespace
