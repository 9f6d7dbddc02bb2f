#pragma once
// Differential property tests: long random sequences of every operation applied to a
// structure and to the brute-force oracle; every answer must agree (compared by distance,
// since ties make identities ambiguous; ray hits by exact hit time, since both call the
// object's own intersect). Works for points and for objects with extent. Seeds are logged;
// SPATIAL_TEST_SEED replays one. Use:
//     spatial_test::differential_case<my_container>::run(distribution, seed, steps);
// or run_all_distributions<my_container>(default_seed, steps).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <string>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/object_geometry.hpp"
#include "test_support.hpp"

namespace spatial_test {

template <class C>
struct differential_case {
    using P = typename C::value_type;  // the stored value (a point or an object)
    using Q = typename C::point_type;  // query points, ray origins and directions
    using T = typename C::scalar_type;
    static constexpr std::size_t D = C::dimension;

    // Objects are placed at generated points with a size that is a function of the point, so
    // the "duplicates" distribution yields identical objects. Sizes span 0 (degenerate) to 0.03.
    static P make_value(const Q& q) {
        if constexpr (spatial::point_object<P>) {
            return q;
        } else {
            double s = 0;
            for (std::size_t d = 0; d < D; ++d) s += std::abs(static_cast<double>(q[d])) * (13.7 + 3.1 * static_cast<double>(d));
            const double frac = s - std::floor(s);
            const double h = frac < 0.1 ? 0.0 : 0.03 * frac;
            return object_factory<P>::at(q, h, 0);
        }
    }

    static void run(distribution dist, std::uint64_t seed, int steps) {
        SCOPED_TRACE(std::string("distribution=") + name_of(dist) + " " + replay_hint(seed));
        point_source<Q> src(dist, seed);
        auto next_value = [&] { return make_value(src.next()); };
        C tree;
        spatial::brute_force<P> oracle;
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
                const P p = next_value();
                handles.push_back(tree.insert(p));
                oracle.insert(p);
            } else if (op < 35) {  // hinted insert near a random live element
                const P p = next_value();
                auto hint = handles.empty() ? tree.end() : handles[src.bits() % handles.size()];
                handles.push_back(tree.insert(hint, p));
                oracle.insert(p);
            } else if (op < 38) {  // bulk insert
                std::vector<P> batch;
                const std::size_t m = 1 + src.bits() % (src.bits() % 4 == 0 ? 400 : 20);
                for (std::size_t i = 0; i < m; ++i) batch.push_back(next_value());
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
                const P v = (src.bits() % 2 == 0 && !handles.empty()) ? *handles[src.bits() % handles.size()] : next_value();
                ASSERT_EQ(tree.count(v), oracle.count(v));
                ASSERT_EQ(tree.find(v) != tree.end(), oracle.find(v) != oracle.end());
            } else if (op < 80) {  // kNN, exact and approximate
                const Q q = src.next();
                const std::size_t k = src.bits() % 3 == 0 ? 1 : 1 + src.bits() % 25;
                const auto got = distances_from(q, tree.find_nearest(q, k));
                const auto want = distances_from(q, oracle.find_nearest(q, k));
                ASSERT_EQ(got, want) << "kNN mismatch, k=" << k;
                const T eps = T(0.5);
                const auto approx = distances_from(q, tree.find_nearest(q, k, eps));
                ASSERT_EQ(approx.size(), want.size());
                for (std::size_t i = 0; i < want.size(); ++i)
                    ASSERT_LE(std::sqrt(approx[i]), 1.5 * std::sqrt(want[i]) * (1 + 1e-5) + 1e-9);
            } else if (op < 88) {  // ball and box ranges
                const Q q = src.next();
                const T r = static_cast<T>(src.unit() * 0.3);
                ASSERT_EQ(distances_from(q, tree.find_in_ball(q, r)),
                          distances_from(q, oracle.find_in_ball(q, r)));
                if constexpr (spatial::candidate_ball<C>) {
                    // The visitor form: the same elements, each with its distance as computed.
                    const auto [as_candidates, as_iterators] = ball_both_ways(tree, q, r);
                    ASSERT_EQ(as_candidates, as_iterators) << "find_in_ball_candidates differs from find_in_ball";
                }
                Q lo = src.next(), hi = lo;
                for (std::size_t d = 0; d < D; ++d) set_coord(hi, d, lo[d] + src.unit() * 0.4);
                ASSERT_EQ(distances_from(q, tree.find_in_box(lo, hi)),
                          distances_from(q, oracle.find_in_box(lo, hi)));
            } else if (op < 98) {  // ray cast
                const Q o = src.next();
                Q dir{};
                for (std::size_t d = 0; d < D; ++d) set_coord(dir, d, src.unit() - 0.5);
                if (src.bits() % 4 == 0) set_coord(dir, src.bits() % D, src.bits() % 2 ? 0.0 : -0.0);
                bool nonzero = false;
                for (std::size_t d = 0; d < D; ++d) nonzero |= dir[d] != 0;
                if (!nonzero) continue;
                const T thick = static_cast<T>(src.unit() * 0.05);
                spatial::intersect_info<Q> a, b;
                if (src.bits() % 3 == 0) a.hit_time = b.hit_time = static_cast<T>(src.unit() * 2);
                auto ta = tree.intersect_object(o, dir, thick, a);
                auto tb = oracle.intersect_object(o, dir, thick, b);
                ASSERT_EQ(ta != tree.end(), tb != oracle.end()) << "ray hit disagreement";
                ASSERT_EQ(a.hit_time, b.hit_time) << std::setprecision(17) << a.hit_time << " vs oracle " << b.hit_time << " thick " << thick;
                if (ta != tree.end()) {  // the reported object really is hit at hit_time
                    spatial::intersect_info<Q> again;
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
        ASSERT_EQ(contents(tree), contents(oracle));
        if constexpr (requires { tree.check_invariants(); }) {
            ASSERT_EQ(tree.check_invariants(), "");
        }
    }
};

// Every distribution, three seeds each (derived from `seed`).
template <class C>
void run_all_distributions(std::uint64_t default_seed, int steps) {
    const std::uint64_t seed = test_seed(default_seed);
    for (distribution d : {distribution::uniform, distribution::lattice, distribution::duplicates,
                           distribution::clusters, distribution::line}) {
        for (int rep = 0; rep < 3; ++rep) {
            differential_case<C>::run(d, seed + static_cast<std::uint64_t>(rep) * 7919 + static_cast<int>(d), steps);
            if (::testing::Test::HasFatalFailure()) return;
        }
    }
}

}  // namespace spatial_test
