#pragma once
// The container contract: ONE type-parameterised suite that every structure runs, for points
// and for objects with extent (the course's Project 2/3 interface). A structure's test file
// instantiates it inside this namespace (gtest's macros need the unqualified suite name):
//     namespace spatial_contract {
//     INSTANTIATE_TYPED_TEST_SUITE_P(my_structure, container_contract, my_container_types);
//     }
// Scenarios are written with points; for containers of objects, pt(x, y, z) is an object of
// half-size h "at" that point (object_factory in test_support.hpp), and expected ray hit times
// are the objects' own answers (points: closest approach; objects: first contact).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/core/capabilities.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/ray.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/point.hpp"
#include "test_support.hpp"

namespace spatial_contract {

using namespace spatial;

template <class C>
class container_contract : public ::testing::Test {
protected:
    static_assert(spatial_container<C>, "the container must model spatial::spatial_container");
    using Value = typename C::value_type;
    using Query = typename C::point_type;
    using Scalar = typename C::scalar_type;
    static constexpr std::size_t D = C::dimension;
    // Half-size of the objects standing in for points (0 for points).
    static constexpr double half_size = point_object<Value> ? 0.0 : 1e-3;

    static Query q(double x, double y, double z = 0) {
        Query p{};
        const double c[3] = {x, y, z};
        for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(p, i, c[i]);
        return p;
    }
    static Value at(const Query& p, int tag = 0) { return spatial_test::object_factory<Value>::at(p, half_size, tag); }
    static Value pt(double x, double y, double z = 0, int tag = 0) { return at(q(x, y, z), tag); }
    static Value nan_point() {
        return spatial_test::object_factory<Value>::with_coord(pt(0, 0, 0), 1, std::numeric_limits<double>::quiet_NaN());
    }
    static Query nan_query() {
        Query p = q(0, 0, 0);
        spatial_test::set_coord(p, 1, std::numeric_limits<double>::quiet_NaN());
        return p;
    }
    // The hit time the single object v reports for the ray (the expected container answer).
    static Scalar hit_time_of(const Value& v, const Query& o, const Query& d, Scalar thickness) {
        intersect_info<Query> info;
        EXPECT_TRUE(v.intersect(o, d, thickness, info));
        return info.hit_time;
    }
    // A grid of (side x side [x 2]) objects.
    static std::vector<Value> grid(int side) {
        std::vector<Value> v;
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
                for (int k = 0; k < (D == 3 ? 2 : 1); ++k) v.push_back(pt(i, j, k));
        return v;
    }

    // Pair searches through box queries (collide/pairs.hpp) build the query box as a point_type,
    // which needs writable coordinates; the tagged_point user type has none, so containers of
    // it skip the pair checks unless they descend their own tree (bvh).
    static constexpr bool pairs_testable =
        pair_search<C> && (requires(Query p) { p[0] = p[0]; } || requires { typename C::volume_type; });

    // ---- the empty states: never filled, moved from, cleared --------------------------------
    // kd_tree and bvh hold no node at all in the first two (nor after clear()): their default
    // constructor and moves allocate nothing, which makes the moves noexcept (docs/contract.md,
    // moved-from containers). Every member must still work there.

    // Every query, pair search, ray form, check and statistic `c` offers answers as for an
    // empty container; so do the empty motions (a batch of no moves, refit, rebuild).
    static void expect_answers_as_empty(C& c) {
        EXPECT_TRUE(c.empty());
        EXPECT_EQ(c.size(), 0u);
        EXPECT_TRUE(c.begin() == c.end());
        std::size_t n = 0;
        for (auto it = c.begin(); it != c.end(); ++it) ++n;
        EXPECT_EQ(n, 0u);
        const Value v = pt(1, 2, 3);
        const Query x = q(1, 2, 3);
        EXPECT_TRUE(c.find(v) == c.end());
        EXPECT_EQ(std::as_const(c).count(v), 0u);
        EXPECT_TRUE(c.find_nearest(x, 5).empty());
        EXPECT_TRUE(c.find_nearest(x, 5, Scalar(0.5)).empty());
        EXPECT_TRUE(c.find_in_ball(x, 100).empty());
        EXPECT_TRUE(c.find_in_box(q(-9, -9, -9), q(9, 9, 9)).empty());
        intersect_info<Query> thin, thick, object;
        EXPECT_FALSE(c.intersect(q(-1, 0, 0), q(1, 0, 0), thin));
        EXPECT_FALSE(c.intersect(q(-1, 0, 0), q(1, 0, 0), Scalar(1), thick));
        EXPECT_TRUE(c.intersect_object(q(-1, 0, 0), q(1, 0, 0), Scalar(1), object) == c.end());
        if constexpr (candidate_knn<C>) {
            std::vector<neighbor_candidate<Scalar>> out(2);
            c.find_nearest_candidates(x, 3, Scalar(0), out);
            EXPECT_TRUE(out.empty());
        }
        if constexpr (candidate_ball<C>) {
            std::vector<neighbor_candidate<Scalar>> out(2);
            c.find_in_ball_candidates(x, 100, out);
            EXPECT_TRUE(out.empty());
        }
        if constexpr (pairs_testable) {
            for (pair_filter f : {pair_filter::exact, pair_filter::candidates}) {
                EXPECT_TRUE(c.self_pairs(f).empty());
                EXPECT_TRUE(c.pairs_with(c, f).empty());
            }
        }
        if constexpr (ray_preparation<C>) c.prepare_rays();
        if constexpr (requires(std::span<const ray<Query>> r, std::span<typename C::iterator> h,
                               std::span<intersect_info<Query>> i) { c.intersect_batch(r, h, i); }) {
            const std::vector<ray<Query>> rays{{q(-1, 0, 0), q(1, 0, 0), Scalar(1)}, {q(0, -1, 0), q(0, 1, 0), Scalar(0)}};
            std::vector<typename C::iterator> hits(rays.size(), c.begin());
            std::vector<intersect_info<Query>> infos(rays.size());
            c.intersect_batch(std::span<const ray<Query>>(rays), std::span<typename C::iterator>(hits),
                              std::span<intersect_info<Query>>(infos));
            for (const auto& h : hits) EXPECT_TRUE(h == c.end());
        }
        if constexpr (requires { c.check_invariants(); }) { EXPECT_EQ(c.check_invariants(), ""); }
        if constexpr (requires { c.height(); }) { EXPECT_EQ(c.height(), 0u); }
        if constexpr (requires { c.points_on_split_planes(); }) { EXPECT_EQ(c.points_on_split_planes(), 0u); }
        if constexpr (requires { c.leaf_count(); }) { EXPECT_LE(c.leaf_count(), 1u); }
        if constexpr (requires { c.node_count(); }) { EXPECT_LE(c.node_count(), 1u); }
        if constexpr (reports_node_areas<C>) {
            const auto [volumes, boxes] = c.node_surface_areas();
            EXPECT_FALSE(std::isnan(volumes));
            EXPECT_FALSE(std::isnan(boxes));
        }
        if constexpr (requires { c.quality(); }) { EXPECT_EQ(c.quality(), 1.0); }
        if constexpr (requires { c.root_volume(); }) (void)c.root_volume();
        if constexpr (reports_query_stats<C>) { EXPECT_EQ(c.last_query_stats().objects_tested, 0u); }
        EXPECT_LT(c.memory_bytes(), std::size_t(1) << 20);  // what its few kept capacities hold
        // The modifiers that change nothing on an empty container.
        EXPECT_EQ(c.erase(v), 0u);
        c.erase(c.begin(), c.end());
        std::vector<Value> none;
        c.insert(none.begin(), none.end());
        if constexpr (batched_motion<C>) {
            motion_batch<C> moves;
            c.update(moves.begin(), moves.end());
        }
        if constexpr (motion_with_strategy<C>)
            for (motion_strategy s : {motion_strategy::refit, motion_strategy::rebuild, motion_strategy::reinsert,
                                      motion_strategy::automatic}) {
                motion_batch<C> moves;
                c.update(moves.begin(), moves.end(), s);
            }
        if constexpr (requires { c.refit(); }) c.refit();
        EXPECT_TRUE(c.empty());
        if constexpr (requires { c.check_invariants(); }) { EXPECT_EQ(c.check_invariants(), ""); }
    }

    // After `first` stored pt(0,0,0) first, the container takes more (single, hinted and bulk
    // inserts), answers every query right, and erases.
    template <class First>
    static void expect_usable_from_empty(C& c, First first) {
        first(c);
        ASSERT_EQ(c.size(), 1u);
        EXPECT_EQ(c.count(pt(0, 0, 0)), 1u);
        auto hint = c.insert(pt(2, 0, 0));
        c.insert(hint, pt(2.5, 0, 0));
        const std::vector<Value> more{pt(5, 0, 0), pt(5, 0, 0), pt(0, 7, 0)};
        c.insert(more.begin(), more.end());
        EXPECT_EQ(c.size(), 6u);
        if constexpr (requires { c.check_invariants(); }) { EXPECT_EQ(c.check_invariants(), ""); }
        auto f = c.find(pt(2, 0, 0));
        ASSERT_TRUE(f != c.end());
        EXPECT_TRUE(*f == pt(2, 0, 0));
        EXPECT_EQ(c.count(pt(5, 0, 0)), 2u);
        const auto nn = c.find_nearest(q(1.9, 0.1, 0), 2);
        ASSERT_EQ(nn.size(), 2u);
        EXPECT_TRUE(*nn[0] == pt(2, 0, 0));
        EXPECT_TRUE(*nn[1] == pt(2.5, 0, 0));
        EXPECT_EQ(c.find_in_ball(q(2, 0, 0), Scalar(0.6)).size(), 2u);
        EXPECT_EQ(c.find_in_box(q(-1, -1, -1), q(3, 1, 1)).size(), 3u);
        intersect_info<Query> info;
        const Query o = q(-1, 0, 0), d = q(1, 0, 0);
        auto hit = c.intersect_object(o, d, Scalar(0.1), info);
        ASSERT_TRUE(hit != c.end());
        EXPECT_TRUE(*hit == pt(0, 0, 0));
        EXPECT_EQ(info.hit_time, hit_time_of(pt(0, 0, 0), o, d, Scalar(0.1)));
        if constexpr (pairs_testable) { EXPECT_EQ(c.self_pairs(pair_filter::exact).size(), 1u); }  // the two at (5, 0)
        EXPECT_EQ(c.erase(pt(5, 0, 0)), 2u);
        c.erase(c.find(pt(0, 7, 0)));
        EXPECT_EQ(c.size(), 3u);
        EXPECT_TRUE(c.find(pt(0, 7, 0)) == c.end());
        if constexpr (requires { c.check_invariants(); }) { EXPECT_EQ(c.check_invariants(), ""); }
    }

    // Containers in each empty state; `filled` is moved from for the moved-from ones.
    template <class Check>
    static void for_each_empty_state(Check check) {
        {
            SCOPED_TRACE("default-constructed");
            C c;
            check(c);
        }
        {
            SCOPED_TRACE("moved from by move construction");
            C source = filled_with_grid();
            C target(std::move(source));
            EXPECT_FALSE(target.empty());
            check(source);  // NOLINT(bugprone-use-after-move): the contract says it is empty and usable
        }
        {
            SCOPED_TRACE("moved from by move assignment");
            C source = filled_with_grid();
            C target = filled_with_grid();
            target.insert(pt(9, 9, 9));
            target = std::move(source);
            EXPECT_EQ(target.count(pt(9, 9, 9)), 0u);
            check(source);  // NOLINT(bugprone-use-after-move)
        }
        {
            SCOPED_TRACE("moved from twice (a moved-from container moved on)");
            C source = filled_with_grid();
            C middle(std::move(source));
            C target(std::move(source));  // NOLINT(bugprone-use-after-move)
            EXPECT_TRUE(target.empty());
            check(target);
        }
        {
            SCOPED_TRACE("cleared");
            C c = filled_with_grid();
            c.clear();
            check(c);
        }
        {
            SCOPED_TRACE("emptied by erasure");
            C c = filled_with_grid();
            c.erase(c.begin(), c.end());
            check(c);
        }
    }
    static C filled_with_grid() {
        C c;
        const auto g = grid(4);
        c.insert(g.begin(), g.end());
        return c;
    }
};
TYPED_TEST_SUITE_P(container_contract);

TYPED_TEST_P(container_contract, empty_container_answers_every_query_with_nothing) {
    TypeParam c;
    using V = typename TypeParam::value_type;
    EXPECT_TRUE(c.empty());
    EXPECT_EQ(c.size(), 0u);
    EXPECT_TRUE(c.begin() == c.end());
    const V v = this->pt(1, 2, 3);
    const auto q = this->q(1, 2, 3);
    EXPECT_TRUE(c.find(v) == c.end());
    EXPECT_EQ(c.count(v), 0u);
    EXPECT_TRUE(c.find_nearest(q, 5).empty());
    EXPECT_TRUE(c.find_in_ball(q, 100).empty());
    EXPECT_TRUE(c.find_in_box(this->q(-9, -9, -9), this->q(9, 9, 9)).empty());
    intersect_info<typename TypeParam::point_type> info;
    EXPECT_FALSE(c.intersect(this->q(0, 0, 0), this->q(1, 0, 0), 1, info));
    EXPECT_EQ(c.erase(v), 0u);
}

TYPED_TEST_P(container_contract, insert_returns_iterator_to_the_new_element_and_iteration_sees_all) {
    TypeParam c;
    const auto pts = this->grid(7);
    for (const auto& p : pts) {
        auto it = c.insert(p);
        EXPECT_TRUE(*it == p);
    }
    EXPECT_EQ(c.size(), pts.size());
    EXPECT_FALSE(c.empty());
    std::size_t n = 0;
    for (auto it = c.begin(); it != c.end(); ++it) ++n;
    EXPECT_EQ(n, pts.size());
    TypeParam ref;
    ref.insert(pts.begin(), pts.end());
    EXPECT_EQ(spatial_test::contents(c), spatial_test::contents(ref));
}

TYPED_TEST_P(container_contract, hinted_insert_stores_the_value_with_any_hint) {
    TypeParam c;
    auto prev = c.insert(this->pt(0, 0, 0));
    for (int i = 1; i < 200; ++i) prev = c.insert(prev, this->pt(i * 0.01, std::sin(i * 0.1), 0.5));
    c.insert(c.end(), this->pt(5, 5, 5));         // end() as hint
    c.insert(c.begin(), this->pt(-50, 70, -3));  // a hint far from the value
    EXPECT_EQ(c.size(), 202u);
    EXPECT_EQ(c.count(this->pt(-50, 70, -3)), 1u);
    EXPECT_EQ(c.count(this->pt(5, 5, 5)), 1u);
    for (int i = 1; i < 200; ++i) EXPECT_EQ(c.count(this->pt(i * 0.01, std::sin(i * 0.1), 0.5)), 1u);
}

TYPED_TEST_P(container_contract, bulk_insert_into_empty_and_nonempty_containers) {
    TypeParam c;
    auto a = this->grid(10), b = this->grid(4);
    c.insert(a.begin(), a.end());
    EXPECT_EQ(c.size(), a.size());
    c.insert(b.begin(), b.end());  // small batch into a big tree
    c.insert(a.begin(), a.end());  // large batch into a tree
    EXPECT_EQ(c.size(), 2 * a.size() + b.size());
    EXPECT_EQ(c.count(this->pt(1, 1, 0)), 3u);
    EXPECT_EQ(c.count(this->pt(9, 9, 0)), 2u);
    std::vector<typename TypeParam::value_type> none;
    c.insert(none.begin(), none.end());
    EXPECT_EQ(c.size(), 2 * a.size() + b.size());
}

TYPED_TEST_P(container_contract, erase_by_iterator_returns_next_and_keeps_other_iterators_valid) {
    TypeParam c;
    const auto pts = this->grid(9);
    std::vector<typename TypeParam::iterator> its;
    for (const auto& p : pts) its.push_back(c.insert(p));
    // Erase every other element; the rest must still dereference to their values.
    for (std::size_t i = 0; i < its.size(); i += 2) c.erase(its[i]);
    EXPECT_EQ(c.size(), pts.size() / 2);
    for (std::size_t i = 1; i < its.size(); i += 2) EXPECT_TRUE(*its[i] == pts[i]);
    // Inserting many more (forcing splits and rebuilds) keeps them valid too.
    for (int i = 0; i < 500; ++i) c.insert(this->pt(100 + i, 3, 1));
    for (std::size_t i = 1; i < its.size(); i += 2) EXPECT_TRUE(*its[i] == pts[i]);
    // erase returns the iterator following the erased one in iteration order.
    auto first = c.begin();
    auto second = std::next(first);
    EXPECT_TRUE(c.erase(first) == second);
}

TYPED_TEST_P(container_contract, erase_by_value_removes_all_duplicates_and_returns_the_count) {
    TypeParam c;
    const auto d = this->pt(0.25, 0.5, 0.75);
    for (int i = 0; i < 40; ++i) c.insert(this->pt(i, i, i));
    for (int i = 0; i < 37; ++i) c.insert(d);
    EXPECT_EQ(c.count(d), 37u);
    EXPECT_EQ(c.erase(d), 37u);
    EXPECT_EQ(c.count(d), 0u);
    EXPECT_EQ(c.size(), 40u);
    EXPECT_EQ(c.erase(d), 0u);
    EXPECT_EQ(c.erase(this->pt(3, 3, 3)), 1u);
    EXPECT_EQ(c.size(), 39u);
}

TYPED_TEST_P(container_contract, bulk_erase_of_ranges_small_and_large) {
    TypeParam c;
    const auto pts = this->grid(12);
    c.insert(pts.begin(), pts.end());
    const auto before = c.size();
    auto first = c.begin();
    auto last = first;
    std::advance(last, 5);
    std::vector<typename TypeParam::value_type> removed(first, last);
    c.erase(first, last);  // small range
    EXPECT_EQ(c.size(), before - 5);
    for (const auto& p : removed) EXPECT_EQ(c.count(p), 0u);
    c.erase(c.begin(), c.begin());  // empty range
    EXPECT_EQ(c.size(), before - 5);
    c.erase(c.begin(), c.end());  // everything
    EXPECT_TRUE(c.empty());
    c.insert(this->pt(1, 2, 3));  // still usable
    EXPECT_EQ(c.size(), 1u);
}

TYPED_TEST_P(container_contract, find_and_count) {
    TypeParam c;
    const auto pts = this->grid(6);
    c.insert(pts.begin(), pts.end());
    for (const auto& p : pts) {
        auto it = c.find(p);
        ASSERT_TRUE(it != c.end());
        EXPECT_TRUE(*it == p);
        EXPECT_EQ(c.count(p), 1u);
    }
    EXPECT_TRUE(c.find(this->pt(0.5, 0.5, 0.5)) == c.end());
    EXPECT_EQ(c.count(this->pt(99, 0, 0)), 0u);
}

TYPED_TEST_P(container_contract, find_nearest_sorted_with_k_zero_and_k_beyond_size) {
    TypeParam c;
    const auto pts = this->grid(8);
    c.insert(pts.begin(), pts.end());
    const auto q = this->q(3.2, 4.1, 0.2);
    EXPECT_TRUE(c.find_nearest(q, 0).empty());
    auto nn = c.find_nearest(q, 5);
    ASSERT_EQ(nn.size(), 5u);
    EXPECT_TRUE(*nn[0] == this->pt(3, 4, 0));
    for (std::size_t i = 1; i < nn.size(); ++i)
        EXPECT_LE(object_squared_distance(*nn[i - 1], q), object_squared_distance(*nn[i], q));
    auto all = c.find_nearest(q, pts.size() + 10);
    ASSERT_EQ(all.size(), pts.size());
    for (std::size_t i = 1; i < all.size(); ++i)
        EXPECT_LE(object_squared_distance(*all[i - 1], q), object_squared_distance(*all[i], q));
}

TYPED_TEST_P(container_contract, approximate_nearest_respects_the_eps_guarantee) {
    TypeParam c;
    spatial_test::point_source<typename TypeParam::point_type> src(spatial_test::distribution::clusters, 7);
    for (int i = 0; i < 3000; ++i) c.insert(this->at(src.next()));
    for (int r = 0; r < 50; ++r) {
        const auto q = src.next();
        const auto exact = spatial_test::distances_from(q, c.find_nearest(q, 10));
        for (double eps : {0.1, 0.5, 2.0}) {
            const auto approx = c.find_nearest(q, 10, static_cast<typename TypeParam::scalar_type>(eps));
            ASSERT_EQ(approx.size(), 10u);
            for (std::size_t i = 1; i < approx.size(); ++i)
                EXPECT_LE(object_squared_distance(*approx[i - 1], q), object_squared_distance(*approx[i], q));
            const auto ad = spatial_test::distances_from(q, approx);
            for (std::size_t i = 0; i < 10; ++i)
                EXPECT_LE(std::sqrt(ad[i]), (1 + eps) * std::sqrt(exact[i]) * (1 + 1e-5) + 1e-12);
        }
    }
    EXPECT_THROW(c.find_nearest(src.next(), 3, -0.5f), std::invalid_argument);
}

TYPED_TEST_P(container_contract, ball_and_box_ranges_are_closed) {
    TypeParam c;
    const auto pts = this->grid(7);
    c.insert(pts.begin(), pts.end());
    const auto center = this->q(3, 3, 0);
    // Radius exactly 1: the 4 axis neighbours (and the one above in 3D) are ON the sphere.
    const auto ball = c.find_in_ball(center, 1);
    EXPECT_EQ(ball.size(), this->D == 3 ? 6u : 5u);
    const auto box = c.find_in_box(this->q(2, 2, 0), this->q(4, 3, 0));
    EXPECT_EQ(box.size(), 6u);  // x in {2,3,4}, y in {2,3}, z = 0
    for (const auto& it : box)
        EXPECT_TRUE(std::abs(static_cast<double>(object_center(*it, this->D - 1))) <= this->half_size || this->D == 2);
    EXPECT_TRUE(c.find_in_box(this->q(4, 4, 0), this->q(2, 2, 0)).empty());  // inverted box
    // Radius 0 finds the object at the centre (for a tilted triangle, "on" it only up to rounding).
    EXPECT_EQ(c.find_in_ball(center, static_cast<typename TypeParam::scalar_type>(this->half_size > 0 ? 1e-6 : 0)).size(), 1u);
    EXPECT_THROW(c.find_in_ball(center, -1), std::invalid_argument);
}

TYPED_TEST_P(container_contract, ray_cast_honours_thickness_hit_time_and_reports_the_object) {
    using Q = typename TypeParam::point_type;
    using T = typename TypeParam::scalar_type;
    TypeParam c;
    c.insert(this->pt(5, 0.05, 0));
    c.insert(this->pt(2, 0.3, 0));
    c.insert(this->pt(8, 0, 0));
    const Q o = this->q(0, 0, 0), dir = this->q(1, 0, 0);
    intersect_info<Q> info;
    EXPECT_TRUE(c.intersect(o, dir, T(0.1), info));  // (2, 0.3) is too far from the ray
    // Points are hit at the closest approach, objects at first contact: the object's own answer.
    EXPECT_EQ(info.hit_time, this->hit_time_of(this->pt(5, 0.05, 0), o, dir, T(0.1)));
    EXPECT_NEAR(static_cast<double>(info.hit_time), 5.0, 0.1);
    EXPECT_NEAR(static_cast<double>(info.hit_location[0]), static_cast<double>(info.hit_time), 1e-5);
    intersect_info<Q> thick;
    auto hit = c.intersect_object(o, dir, 0.5, thick);  // now (2, 0.3) is hit first
    ASSERT_TRUE(hit != c.end());
    EXPECT_TRUE(*hit == this->pt(2, 0.3, 0));
    intersect_info<Q> limited;
    limited.hit_time = 1.5;  // only hits before t = 1.5 count
    EXPECT_FALSE(c.intersect(o, dir, 0.5, limited));
    EXPECT_EQ(limited.hit_time, typename TypeParam::scalar_type(1.5));
    intersect_info<Q> backwards;
    EXPECT_FALSE(c.intersect(this->q(-1, 0, 0), this->q(-1, 0, 0), T(0.1), backwards));
    // Default thickness is 0: an exact pass through a point hits it.
    intersect_info<Q> exact;
    EXPECT_TRUE(c.intersect(this->q(8, -4, 0), this->q(0, 1, 0), exact));
    EXPECT_EQ(exact.hit_time, this->hit_time_of(this->pt(8, 0, 0), this->q(8, -4, 0), this->q(0, 1, 0), T(0)));
    EXPECT_NEAR(static_cast<double>(exact.hit_time), 4.0, 0.01);
}

TYPED_TEST_P(container_contract, bad_input_is_rejected_by_name_and_nothing_stored_changes) {
    using V = typename TypeParam::value_type;
    TypeParam c;
    const auto pts = this->grid(5);
    c.insert(pts.begin(), pts.end());
    const auto before = spatial_test::contents(c);
    try {
        c.insert(this->nan_point());
        FAIL() << "NaN insert accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("nan"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("coordinate 1"), std::string::npos) << e.what();
    }
    std::vector<V> batch = this->grid(3);
    batch.push_back(this->nan_point());
    EXPECT_THROW(c.insert(batch.begin(), batch.end()), std::invalid_argument);
    EXPECT_THROW(c.insert(c.begin(), this->nan_point()), std::invalid_argument);
    const V inf_point = spatial_test::object_factory<V>::with_coord(this->pt(0, 0, 0), 0, std::numeric_limits<double>::infinity());
    EXPECT_THROW(c.insert(inf_point), std::invalid_argument);
    EXPECT_EQ(spatial_test::contents(c), before);
    EXPECT_THROW(c.find_nearest(this->nan_query(), 3), std::invalid_argument);
    intersect_info<typename TypeParam::point_type> info;
    try {
        c.intersect(this->q(0, 0, 0), this->q(0, 0, 0), info);
        FAIL() << "zero direction accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("zero vector"), std::string::npos) << e.what();
    }
    EXPECT_THROW(c.intersect(this->nan_query(), this->q(1, 0, 0), info), std::invalid_argument);
    EXPECT_THROW(c.intersect(this->q(0, 0, 0), this->q(1, 0, 0), -1, info), std::invalid_argument);
    EXPECT_EQ(spatial_test::contents(c), before);
}

TYPED_TEST_P(container_contract, clear_empties_and_the_container_is_reusable) {
    TypeParam c;
    const auto pts = this->grid(10);
    c.insert(pts.begin(), pts.end());
    c.clear();
    EXPECT_TRUE(c.empty());
    EXPECT_TRUE(c.begin() == c.end());
    EXPECT_TRUE(c.find_nearest(this->q(1, 1, 1), 3).empty());
    c.insert(this->pt(1, 1, 1));
    EXPECT_EQ(c.find_nearest(this->q(0, 0, 0), 3).size(), 1u);
}

TYPED_TEST_P(container_contract, user_defined_equality_distinguishes_payloads) {
    // For the tagged user types, equal geometry with different tags are different values.
    TypeParam c;
    using V = typename TypeParam::value_type;
    if constexpr (requires(V v) { v.tag; }) {
        c.insert(this->pt(1, 1, 1, 1));
        c.insert(this->pt(1, 1, 1, 2));
        c.insert(this->pt(1, 1, 1, 2));
        EXPECT_EQ(c.count(this->pt(1, 1, 1, 2)), 2u);
        EXPECT_EQ(c.erase(this->pt(1, 1, 1, 2)), 2u);
        EXPECT_EQ(c.count(this->pt(1, 1, 1, 1)), 1u);
    } else {
        c.insert(this->pt(1, 1, 1));
        EXPECT_EQ(c.count(this->pt(1, 1, 1)), 1u);
    }
}

TYPED_TEST_P(container_contract, copies_are_independent_and_moved_from_containers_are_empty_and_usable) {
    TypeParam a;
    const auto pts = this->grid(8);
    a.insert(pts.begin(), pts.end());
    TypeParam copy = a;
    copy.erase(copy.begin());
    EXPECT_EQ(a.size(), pts.size());
    EXPECT_EQ(copy.size(), pts.size() - 1);
    TypeParam moved = std::move(a);
    EXPECT_EQ(moved.size(), pts.size());
    EXPECT_EQ(spatial_test::contents(moved).size(), pts.size());
    EXPECT_TRUE(a.empty());  // NOLINT(bugprone-use-after-move): the contract says so
    a.insert(this->pt(1, 2, 3));
    EXPECT_EQ(a.count(this->pt(1, 2, 3)), 1u);
    EXPECT_EQ(a.find_nearest(this->q(0, 0, 0), 4).size(), 1u);
    TypeParam assigned;
    assigned.insert(this->pt(9, 9, 9));
    assigned = std::move(moved);
    EXPECT_EQ(assigned.size(), pts.size());
    EXPECT_EQ(assigned.count(this->pt(9, 9, 9)), 0u);
    EXPECT_TRUE(moved.empty());  // NOLINT(bugprone-use-after-move)
}

TYPED_TEST_P(container_contract, default_constructed_and_moved_from_containers_answer_every_query_as_empty) {
    using C = TypeParam;
    TestFixture::for_each_empty_state([](C& c) { TestFixture::expect_answers_as_empty(c); });
}

TYPED_TEST_P(container_contract, default_constructed_and_moved_from_containers_accept_every_first_insertion) {
    using C = TypeParam;
    const auto origin = TestFixture::pt(0, 0, 0);
    TestFixture::for_each_empty_state([&](C& c) {
        SCOPED_TRACE("insert");
        C a = c;  // a copy of the empty state is that state too
        TestFixture::expect_usable_from_empty(a, [&](C& d) { EXPECT_TRUE(*d.insert(origin) == origin); });
    });
    TestFixture::for_each_empty_state([&](C& c) {
        SCOPED_TRACE("hinted insert with end()");
        TestFixture::expect_usable_from_empty(c, [&](C& d) { EXPECT_TRUE(*d.insert(d.end(), origin) == origin); });
    });
    TestFixture::for_each_empty_state([&](C& c) {
        SCOPED_TRACE("bulk insert");
        TestFixture::expect_usable_from_empty(c, [&](C& d) {
            const std::vector<typename C::value_type> one{origin};
            d.insert(one.begin(), one.end());
        });
    });
    if constexpr (requires(C c) { c.rebuild(); }) {
        TestFixture::for_each_empty_state([&](C& c) {
            SCOPED_TRACE("rebuild, then insert");
            c.rebuild();
            if constexpr (requires { c.check_invariants(); }) { EXPECT_EQ(c.check_invariants(), ""); }
            TestFixture::expect_answers_as_empty(c);
            TestFixture::expect_usable_from_empty(c, [&](C& d) { d.insert(origin); });
        });
    }
}

TYPED_TEST_P(container_contract, empty_states_copy_swap_move_and_pair_with_populated_containers) {
    using C = TypeParam;
    TestFixture::for_each_empty_state([](C& empty) {
        C populated = TestFixture::filled_with_grid();
        const auto n = populated.size();
        if constexpr (TestFixture::pairs_testable) {
            for (pair_filter f : {pair_filter::exact, pair_filter::candidates}) {
                EXPECT_TRUE(populated.pairs_with(empty, f).empty());
                EXPECT_TRUE(empty.pairs_with(populated, f).empty());
            }
        }
        C copy = empty;
        TestFixture::expect_answers_as_empty(copy);
        C assigned = TestFixture::filled_with_grid();
        assigned = copy;  // copy-assigning the empty state
        TestFixture::expect_answers_as_empty(assigned);
        C moved_into = TestFixture::filled_with_grid();
        moved_into = std::move(copy);  // move-assigning the empty state
        TestFixture::expect_answers_as_empty(moved_into);
        TestFixture::expect_answers_as_empty(copy);  // NOLINT(bugprone-use-after-move)
        std::swap(empty, populated);
        EXPECT_EQ(empty.size(), n);
        TestFixture::expect_answers_as_empty(populated);
        if constexpr (requires { empty.check_invariants(); }) { EXPECT_EQ(empty.check_invariants(), ""); }
        EXPECT_EQ(empty.count(TestFixture::pt(3, 3, 0)), 1u);
        populated.insert(TestFixture::pt(3, 3, 0));
        if constexpr (TestFixture::pairs_testable) {
            EXPECT_EQ(populated.pairs_with(empty, pair_filter::exact).size(), 1u);  // the two at (3, 3, 0)
            EXPECT_EQ(empty.pairs_with(populated, pair_filter::exact).size(), 1u);
        }
    });
}

REGISTER_TYPED_TEST_SUITE_P(container_contract,
    empty_container_answers_every_query_with_nothing,
    insert_returns_iterator_to_the_new_element_and_iteration_sees_all,
    hinted_insert_stores_the_value_with_any_hint,
    bulk_insert_into_empty_and_nonempty_containers,
    erase_by_iterator_returns_next_and_keeps_other_iterators_valid,
    erase_by_value_removes_all_duplicates_and_returns_the_count,
    bulk_erase_of_ranges_small_and_large,
    find_and_count,
    find_nearest_sorted_with_k_zero_and_k_beyond_size,
    approximate_nearest_respects_the_eps_guarantee,
    ball_and_box_ranges_are_closed,
    ray_cast_honours_thickness_hit_time_and_reports_the_object,
    bad_input_is_rejected_by_name_and_nothing_stored_changes,
    clear_empties_and_the_container_is_reusable,
    user_defined_equality_distinguishes_payloads,
    copies_are_independent_and_moved_from_containers_are_empty_and_usable,
    default_constructed_and_moved_from_containers_answer_every_query_as_empty,
    default_constructed_and_moved_from_containers_accept_every_first_insertion,
    empty_states_copy_swap_move_and_pair_with_populated_containers);

}  // namespace spatial_contract
