#pragma once
// Hard cases shared by octree_test.cpp and grid_test.cpp, as a type-parameterised suite:
// each case fills a structure and the brute-force oracle with the same objects and compares
// every query (kNN distance lists, approximate-kNN bounds, ball/box sets, ray hit times and
// locations, with axis-parallel rays carrying +0 and -0 components and origins on cell planes).
// Instantiate with:  INSTANTIATE_TYPED_TEST_SUITE_P(prefix, octree_grid_hard_cases, types);

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <list>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "differential.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/core/object_geometry.hpp"
#include "test_support.hpp"

namespace og_test {

using namespace spatial;

template <class C>
struct checker {
    using V = typename C::value_type;
    using Q = typename C::point_type;
    using T = typename C::scalar_type;
    static constexpr std::size_t D = C::dimension;

    // Seeded by test_seed(fallback) and logged for the checker's lifetime.
    spatial_test::seeded_rng rng;
    explicit checker(std::uint64_t fallback) : rng(fallback) {}

    double unit() { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
    static Q q_at(const std::array<double, 3>& c) {
        Q p{};
        for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(p, i, c[i]);
        return p;
    }
    static V obj_at(const Q& q, double h) { return spatial_test::object_factory<V>::at(q, h, 0); }
    Q random_point(double offset, double scale, double spread) {
        std::array<double, 3> c{};
        for (std::size_t i = 0; i < D; ++i) c[i] = offset + scale * (unit() * spread - (spread - 1) / 2);
        return q_at(c);
    }

    void compare_ray(const C& c, const brute_force<V>& b, const Q& o, const Q& d, T thick) {
        intersect_info<Q> a, e;
        const auto it = c.intersect_object(o, d, thick, a);
        const auto jt = b.intersect_object(o, d, thick, e);
        ASSERT_EQ(it != c.end(), jt != b.end()) << "ray hit disagreement, origin " << std::setprecision(17) << o[0]
                                                << " dir " << d[0] << "," << d[1];
        ASSERT_EQ(a.hit_time, e.hit_time) << std::setprecision(17) << a.hit_time << " vs " << e.hit_time;
        if (it != c.end()) {
            for (std::size_t i = 0; i < D; ++i) ASSERT_EQ(a.hit_location[i], e.hit_location[i]);
            intersect_info<Q> again;
            ASSERT_TRUE(it->intersect(o, d, thick, again));
            ASSERT_EQ(again.hit_time, a.hit_time);
        }
    }

    // Every query kind, `queries` times, over [offset, offset + scale]^D (queries reach 20%
    // beyond it). Thick rays use thickness scale / 100.
    void compare_all(const C& c, const brute_force<V>& b, double offset, double scale, int queries) {
        ASSERT_EQ(c.size(), b.size());
        ASSERT_EQ(spatial_test::contents(c), spatial_test::contents(b));
        std::vector<Q> anchors;  // points of stored objects: rays aimed exactly through them
        for (const V& v : b) {
            Q p{};
            for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(p, i, static_cast<double>(object_center(v, i)));
            anchors.push_back(p);
        }
        for (int n = 0; n < queries; ++n) {
            const Q x = random_point(offset, scale, 1.4);
            const std::size_t k = 1 + rng() % 12;
            const auto want = spatial_test::distances_from(x, b.find_nearest(x, k));
            ASSERT_EQ(spatial_test::distances_from(x, c.find_nearest(x, k)), want) << "kNN k=" << k;
            const auto approx = spatial_test::distances_from(x, c.find_nearest(x, k, T(0.5)));
            ASSERT_EQ(approx.size(), want.size());
            for (std::size_t i = 0; i < want.size(); ++i) ASSERT_LE(std::sqrt(approx[i]), 1.5 * std::sqrt(want[i]) * (1 + 1e-5));
            const T r = static_cast<T>(scale * unit() * 0.3);
            ASSERT_EQ(spatial_test::distances_from(x, c.find_in_ball(x, r)),
                      spatial_test::distances_from(x, b.find_in_ball(x, r)));
            Q lo = random_point(offset, scale, 1.2), hi = lo;
            for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(hi, i, static_cast<double>(lo[i]) + scale * unit() * 0.4);
            ASSERT_EQ(spatial_test::distances_from(x, c.find_in_box(lo, hi)),
                      spatial_test::distances_from(x, b.find_in_box(lo, hi)));
            for (int variant = 0; variant < 3; ++variant) {
                Q o = random_point(offset, scale, 1.4), d{};
                const std::size_t axis = rng() % D;
                if (variant == 0) {
                    for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(d, i, unit() - 0.5);
                } else {
                    // Axis-parallel: the other components are +0 or -0.
                    for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(d, i, rng() % 2 ? 0.0 : -0.0);
                    spatial_test::set_coord(d, axis, rng() % 2 ? 1.0 : -1.0);
                    if (variant == 2 && !anchors.empty()) {  // through a stored object's centre
                        o = anchors[rng() % anchors.size()];
                        spatial_test::set_coord(o, axis, static_cast<double>(o[axis]) - static_cast<double>(d[axis]) * scale * 2);
                    }
                }
                bool nonzero = false;
                for (std::size_t i = 0; i < D; ++i) nonzero |= d[i] != 0;
                if (!nonzero) continue;
                compare_ray(c, b, o, d, T(0));
                compare_ray(c, b, o, d, static_cast<T>(scale * 0.01));
                if (::testing::Test::HasFatalFailure()) return;
            }
        }
    }
};

template <class C>
class octree_grid_hard_cases : public ::testing::Test {};
TYPED_TEST_SUITE_P(octree_grid_hard_cases);

TYPED_TEST_P(octree_grid_hard_cases, interleaved_updates_match_brute_force_for_every_distribution) {
    spatial_test::run_all_distributions<TypeParam>(20261123, 400);
}

TYPED_TEST_P(octree_grid_hard_cases, many_identical_objects_neither_subdivide_forever_nor_lose_any) {
    using K = checker<TypeParam>;
    K k(7);
    TypeParam c;
    brute_force<typename K::V> b;
    const auto v = K::obj_at(K::q_at({0.25, 0.5, 0.75}), 0.01);
    for (int i = 0; i < 3000; ++i) {
        c.insert(v);
        b.insert(v);
    }
    std::vector<typename K::V> more(2000, v);
    c.insert(more.begin(), more.end());
    b.insert(more.begin(), more.end());
    ASSERT_EQ(c.count(v), 5000u);
    if constexpr (requires { c.check_invariants(); }) {
        ASSERT_EQ(c.check_invariants(), "");
    }
    if constexpr (requires { c.height(); }) {
        EXPECT_LE(c.height(), 2u) << "identical objects must not be subdivided";
    }
    k.compare_all(c, b, 0, 1, 20);
    ASSERT_EQ(c.erase(v), 5000u);
    EXPECT_TRUE(c.empty());
    EXPECT_TRUE(c.find_nearest(K::q_at({0, 0, 0}), 3).empty());
}

TYPED_TEST_P(octree_grid_hard_cases, huge_and_tiny_coordinates_match_brute_force) {
    using K = checker<TypeParam>;
    // (offset, scale): coordinates near 1e15 with spread 1e3 (float: spread 1e9), and spread 1e-15.
    const double big_spread = std::is_same_v<typename K::T, float> ? 1e9 : 1e3;
    for (const auto& [offset, scale] : {std::pair{1e15, big_spread}, std::pair{0.0, 1e-15}, std::pair{-1e8, 1e-3}}) {
        SCOPED_TRACE("offset " + std::to_string(offset) + " scale " + std::to_string(scale));
        K k(11);
        TypeParam c;
        brute_force<typename K::V> b;
        std::vector<typename K::V> batch;
        for (int i = 0; i < 300; ++i) batch.push_back(K::obj_at(k.random_point(offset, scale, 1), scale * 0.01 * k.unit()));
        c.insert(batch.begin(), batch.begin() + 150);
        b.insert(batch.begin(), batch.begin() + 150);
        for (std::size_t i = 150; i < batch.size(); ++i) {
            c.insert(batch[i]);
            b.insert(batch[i]);
        }
        k.compare_all(c, b, offset, scale, 40);
        if (::testing::Test::HasFatalFailure()) return;
        for (int i = 0; i < 100; ++i) {
            ASSERT_EQ(c.erase(batch[static_cast<std::size_t>(i) * 3]), b.erase(batch[static_cast<std::size_t>(i) * 3]));
        }
        k.compare_all(c, b, offset, scale, 20);
        if (::testing::Test::HasFatalFailure()) return;
    }
}

TYPED_TEST_P(octree_grid_hard_cases, lattice_objects_on_cell_planes_and_axis_rays_with_signed_zeros) {
    using K = checker<TypeParam>;
    using Q = typename K::Q;
    K k(13);
    TypeParam c;
    brute_force<typename K::V> b;
    // Integer lattice: objects exactly on every power-of-two split plane and grid plane.
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < (K::D == 3 ? 4 : 1); ++z) {
                const auto v = K::obj_at(K::q_at({double(x), double(y), double(z)}), (x + y) % 3 == 0 ? 0.0 : 0.5);
                c.insert(v);
                b.insert(v);
            }
    // Rays along every axis, from lattice coordinates (origins on planes), both signs of zero.
    for (std::size_t axis = 0; axis < K::D; ++axis)
        for (double sign : {1.0, -1.0})
            for (double zero : {0.0, -0.0})
                for (int a = -1; a < 9; ++a)
                    for (int bb = -1; bb < 5; ++bb) {
                        Q o{}, d{};
                        for (std::size_t i = 0; i < K::D; ++i) spatial_test::set_coord(d, i, zero);
                        spatial_test::set_coord(d, axis, sign);
                        std::size_t j = 0;
                        for (std::size_t i = 0; i < K::D; ++i) {
                            if (i == axis) spatial_test::set_coord(o, i, sign > 0 ? -3.0 : 11.0);
                            else spatial_test::set_coord(o, i, j++ == 0 ? a : bb * 0.5);
                        }
                        k.compare_ray(c, b, o, d, typename K::T(0));
                        k.compare_ray(c, b, o, d, typename K::T(0.5));
                        if (::testing::Test::HasFatalFailure()) return;
                    }
    k.compare_all(c, b, 0, 8, 60);
}

TYPED_TEST_P(octree_grid_hard_cases, objects_far_outside_the_initial_bounds) {
    using K = checker<TypeParam>;
    K k(17);
    TypeParam c;
    brute_force<typename K::V> b;
    std::vector<typename K::V> first;
    for (int i = 0; i < 200; ++i) first.push_back(K::obj_at(k.random_point(0, 1, 1), 0.01 * k.unit()));
    c.insert(first.begin(), first.end());
    b.insert(first.begin(), first.end());
    for (double far : {3.0, -7.0, 1e3, -1e6, 1e9}) {
        for (int i = 0; i < 5; ++i) {
            const auto v = K::obj_at(k.random_point(far, 1, 1), 0.5 * k.unit());
            c.insert(v);
            b.insert(v);
        }
        if constexpr (requires { c.check_invariants(); }) {
            ASSERT_EQ(c.check_invariants(), "");
        }
    }
    k.compare_all(c, b, 0, 1, 40);
    k.compare_all(c, b, -1e6, 2e6, 20);
}

TYPED_TEST_P(octree_grid_hard_cases, empty_container_and_bad_input_leave_contents_unchanged) {
    using K = checker<TypeParam>;
    using Q = typename K::Q;
    using T = typename K::T;
    TypeParam c;
    const Q o = K::q_at({0, 0, 0}), d = K::q_at({1, 0.5, 0.25});
    intersect_info<Q> info;
    EXPECT_FALSE(c.intersect(o, d, info));
    EXPECT_TRUE(c.find_nearest(o, 4).empty());
    EXPECT_TRUE(c.find_in_ball(o, 10).empty());
    EXPECT_TRUE(c.find_in_box(o, d).empty());
    EXPECT_EQ(c.count(K::obj_at(o, 0.1)), 0u);
    EXPECT_EQ(c.erase(K::obj_at(o, 0.1)), 0u);
    EXPECT_TRUE(c.find(K::obj_at(o, 0.1)) == c.end());

    std::vector<typename K::V> good;
    for (int i = 0; i < 50; ++i) good.push_back(K::obj_at(K::q_at({i * 0.1, i * 0.05, 0.3}), 0.02));
    c.insert(good.begin(), good.end());
    const auto before = spatial_test::contents(c);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<typename K::V> bad = good;
    bad[25] = spatial_test::object_factory<typename K::V>::with_coord(bad[25], 0, nan);
    EXPECT_THROW(c.insert(bad.begin(), bad.end()), std::invalid_argument);
    EXPECT_THROW(c.insert(bad[25]), std::invalid_argument);
    EXPECT_THROW(c.insert(c.begin(), bad[25]), std::invalid_argument);
    Q nq = o;
    spatial_test::set_coord(nq, 0, nan);
    EXPECT_THROW(c.find_nearest(nq, 2), std::invalid_argument);
    EXPECT_THROW(c.find_nearest(o, 2, T(-1)), std::invalid_argument);
    EXPECT_THROW(c.find_in_ball(o, T(-1)), std::invalid_argument);
    EXPECT_THROW(c.find_in_ball(nq, T(1)), std::invalid_argument);
    EXPECT_THROW(c.find_in_box(nq, d), std::invalid_argument);
    EXPECT_THROW(c.intersect(o, K::q_at({0, 0, 0}), info), std::invalid_argument);
    EXPECT_THROW(c.intersect(o, K::q_at({-0.0, -0.0, -0.0}), info), std::invalid_argument);
    EXPECT_THROW(c.intersect(nq, d, info), std::invalid_argument);
    EXPECT_THROW(c.intersect(o, d, T(-1), info), std::invalid_argument);
    EXPECT_THROW(c.set_ray_thickness(T(-1)), std::invalid_argument);
    EXPECT_THROW(c.erase(bad[25]), std::invalid_argument);
    EXPECT_THROW((void)c.count(bad[25]), std::invalid_argument);
    EXPECT_EQ(spatial_test::contents(c), before);
    EXPECT_EQ(c.size(), good.size());
    if constexpr (requires { c.check_invariants(); }) {
        EXPECT_EQ(c.check_invariants(), "");
    }
}

// The bulk insertion's paths (issue 18): a batch into an empty structure (octree: the array
// build; grids: grid chosen once, entries grouped by cell), merged into a filled one (octree:
// the array partition down the tree, leaves split; grids: grouped by cell, hashed cells
// created in the map), a batch at least as large as the structure (octree: rebuild), one
// reaching far outside the current bounds (root growth, re-grid), with duplicates inside the
// batch and of stored objects (refused splits, one cell listing a slot many times), and from
// a list (the copying path). Every answer against brute force, the invariants after each.
TYPED_TEST_P(octree_grid_hard_cases, bulk_batches_into_empty_and_filled_structures_match_brute_force) {
    using K = checker<TypeParam>;
    using V = typename K::V;
    K k(20261127);
    TypeParam c;
    brute_force<V> b;
    auto batch_of = [&](std::size_t m, double offset, double scale, std::size_t copies) {
        std::vector<V> v;
        for (std::size_t i = 0; i < m; ++i) {
            const V x = K::obj_at(k.random_point(offset, scale, 1.0), scale * 0.01);
            for (std::size_t j = 0; j < (i % 7 == 0 ? copies : 1); ++j) v.push_back(x);
        }
        return v;
    };
    auto add = [&](const std::vector<V>& v, double offset, double scale) {
        c.insert(v.begin(), v.end());
        b.insert(v.begin(), v.end());
        if constexpr (requires { c.check_invariants(); }) {
            ASSERT_EQ(c.check_invariants(), "");
        }
        k.compare_all(c, b, offset, scale, 40);
    };
    add(batch_of(1500, 0, 1, 3), 0, 1);                        // into empty, with duplicates
    if (::testing::Test::HasFatalFailure()) return;
    add(batch_of(150, 0, 1, 40), 0, 1);                        // n/10 into n, piles of 40 copies
    if (::testing::Test::HasFatalFailure()) return;
    std::vector<V> again(b.begin(), b.end());                  // duplicates of everything stored
    again.resize(again.size() / 3);
    add(again, 0, 1);
    if (::testing::Test::HasFatalFailure()) return;
    add(batch_of(400, 0.25, 0.01, 2), 0, 1);                   // dense in one corner: deep splits
    if (::testing::Test::HasFatalFailure()) return;
    add(batch_of(300, 5, 3, 1), 0, 8);                         // far outside: growth / re-grid
    if (::testing::Test::HasFatalFailure()) return;
    add(batch_of(4000, 0, 8, 2), 0, 8);                        // larger than the structure
    if (::testing::Test::HasFatalFailure()) return;
    const std::vector<V> v = batch_of(200, 0, 8, 2);
    const std::list<V> listed(v.begin(), v.end());              // a forward range: copied first
    c.insert(listed.begin(), listed.end());
    b.insert(listed.begin(), listed.end());
    if constexpr (requires { c.check_invariants(); }) {
        ASSERT_EQ(c.check_invariants(), "");
    }
    k.compare_all(c, b, 0, 8, 40);
    // The same objects inserted one by one answer the same.
    TypeParam one_by_one;
    for (const V& x : b) one_by_one.insert(x);
    k.compare_all(one_by_one, b, 0, 8, 20);
}

REGISTER_TYPED_TEST_SUITE_P(octree_grid_hard_cases, interleaved_updates_match_brute_force_for_every_distribution,
                            many_identical_objects_neither_subdivide_forever_nor_lose_any,
                            huge_and_tiny_coordinates_match_brute_force,
                            lattice_objects_on_cell_planes_and_axis_rays_with_signed_zeros,
                            objects_far_outside_the_initial_bounds,
                            empty_container_and_bad_input_leave_contents_unchanged,
                            bulk_batches_into_empty_and_filled_structures_match_brute_force);

}  // namespace og_test
