#pragma once
// Differential testing of spatial::bvh against the brute-force oracle, shared by the bvh test
// files (each file instantiates it for a slice of the BV x object x scalar x dimension product,
// to keep every translation unit quick to compile).
//
// A run: a seeded random scene, then rounds of interleaved mutations (single, hinted and bulk
// inserts; erase by iterator, by value, by range; objects moved by update() with an
// immediate path refit or deferred to one refit()), each round followed by the structural
// check and a batch of queries compared with the oracle: ray hit times EXACTLY (both call the
// same O::intersect), kNN distance lists exactly, the (1+eps) guarantee of approximate kNN,
// ball and box ranges as sorted distance / bound lists.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "spatial/brute/brute_force.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"
#include "test_support.hpp"

namespace bvh_test {

using namespace spatial;

template <class O>
class scene_source {
public:
    using Q = point_type_of<O>;
    using T = typename O::scalar_type;
    static constexpr std::size_t D = O::dimension;

    scene_source(std::uint64_t seed, double offset = 0, double scale = 1) : rng_(seed), offset_(offset), scale_(scale) {}

    double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
    std::size_t below(std::size_t n) { return static_cast<std::size_t>(rng_() % n); }

    Q point_in(double lo, double hi) {
        Q q{};
        for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(q, i, offset_ + scale_ * (lo + (hi - lo) * unit()));
        return q;
    }
    // Objects: half-sizes heavy-tailed in [1e-3, 0.06] of the scale; a few duplicates.
    O object() {
        if (!made_.empty() && below(20) == 0) return made_[below(made_.size())];
        const double h = scale_ * 1e-3 * std::pow(60.0, unit() * unit());
        O o = spatial_test::object_factory<O>::at(point_in(0, 1), h, 0);
        made_.push_back(o);
        return o;
    }
    O moved(const O& o) {
        Q c{};
        for (std::size_t i = 0; i < D; ++i) spatial_test::set_coord(c, i, static_cast<double>(object_center(o, i)) + scale_ * 0.05 * (unit() - 0.5));
        const double h = (static_cast<double>(object_upper(o, 0)) - static_cast<double>(object_lower(o, 0))) / 2;
        return spatial_test::object_factory<O>::at(c, h > 0 ? h * 0.9 : 0, 0);
    }
    // Directions with zero and negative-zero components one time in three.
    Q direction() {
        Q d{};
        for (;;) {
            bool any = false;
            for (std::size_t i = 0; i < D; ++i) {
                double v = 2 * unit() - 1;
                const auto r = below(6);
                if (r == 0) v = 0.0;
                if (r == 1) v = -0.0;
                spatial_test::set_coord(d, i, v);
                any |= v != 0;
            }
            if (any) return d;
        }
    }
    double scale() const { return scale_; }

private:
    std::mt19937_64 rng_;
    double offset_, scale_;
    std::vector<O> made_;
};

using spatial_test::signatures_of;
using spatial_test::all_iterators;

// Queries compared with the oracle. Returns the number of ray hits seen (so callers can
// check the scene was not trivially empty).
template <class Tree>
std::size_t compare_queries(const Tree& tree, const brute_force<typename Tree::value_type>& oracle,
                            scene_source<typename Tree::value_type>& g, int count) {
    using O = typename Tree::value_type;
    using Q = typename Tree::point_type;
    using T = typename Tree::scalar_type;
    std::size_t hits = 0;
    const double s = g.scale();
    const auto stored = all_iterators(tree);
    for (int qi = 0; qi < count; ++qi) {
        // --- rays: random, and aimed at a stored object (origin at its centre for thin rays)
        Q o = g.point_in(-0.3, 1.3), d = g.direction();
        if (qi % 3 == 0 && !stored.empty()) {
            const O& target = *stored[g.below(stored.size())];
            for (std::size_t i = 0; i < O::dimension; ++i) spatial_test::set_coord(o, i, object_center(target, i));
            if (qi % 2 == 0)  // back off along -d so the ray starts outside
                for (std::size_t i = 0; i < O::dimension; ++i) spatial_test::set_coord(o, i, o[i] - 0.5 * d[i]);
        }
        const T thickness = static_cast<T>(qi % 4 == 0 ? 0.0 : (qi % 4 == 1 ? 0.004 * s : 0.03 * s));
        intersect_info<Q> a, b;
        if (qi % 5 == 0) a.hit_time = b.hit_time = T(0.7);
        const auto it_tree = tree.intersect_object(o, d, thickness, a);
        const auto it_oracle = oracle.intersect_object(o, d, thickness, b);
        EXPECT_EQ(it_tree != tree.end(), it_oracle != oracle.end()) << "ray " << qi;
        EXPECT_EQ(a.hit_time, b.hit_time) << "ray " << qi;
        if (it_tree != tree.end()) {
            ++hits;
            intersect_info<Q> single;  // the reported object really is hit at that time
            EXPECT_TRUE(it_tree->intersect(o, d, thickness, single));
            EXPECT_EQ(single.hit_time, a.hit_time);
        }
        // --- kNN exact and approximate
        const Q q = g.point_in(-0.2, 1.2);
        const std::size_t k = std::size_t(1) + g.below(12);
        const auto kt = tree.find_nearest(q, k), ko = oracle.find_nearest(q, k);
        EXPECT_EQ(spatial_test::distances_from(q, kt), spatial_test::distances_from(q, ko)) << "knn " << qi;
        for (std::size_t i = 1; i < kt.size(); ++i)
            EXPECT_LE(object_squared_distance(*kt[i - 1], q), object_squared_distance(*kt[i], q));
        const T eps = T(0.5);
        const auto ka = tree.find_nearest(q, k, eps);
        EXPECT_EQ(ka.size(), ko.size());
        for (std::size_t i = 0; i < std::min(ka.size(), ko.size()); ++i) {
            const double exact = object_squared_distance(*ko[i], q), approx = object_squared_distance(*ka[i], q);
            EXPECT_LE(approx, exact * 1.5 * 1.5 * (1 + 1e-5) + 1e-30) << "approximate knn " << qi;
        }
        // --- ball and box
        const T r = static_cast<T>(s * (0.02 + 0.2 * g.unit()));
        EXPECT_EQ(spatial_test::distances_from(q, tree.find_in_ball(q, r)), spatial_test::distances_from(q, oracle.find_in_ball(q, r)))
            << "ball " << qi;
        Q lo = g.point_in(-0.1, 1.0), hi = lo;
        for (std::size_t i = 0; i < O::dimension; ++i) spatial_test::set_coord(hi, i, lo[i] + s * 0.3 * g.unit());
        EXPECT_EQ(signatures_of(tree.find_in_box(lo, hi)), signatures_of(oracle.find_in_box(lo, hi))) << "box " << qi;
    }
    return hits;
}

// The full differential scenario for one tree type.
template <class Tree>
void differential(std::uint64_t seed, std::size_t n, int rounds, double offset = 0, double scale = 1) {
    using O = typename Tree::value_type;
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    scene_source<O> g(seed, offset, scale);
    Tree tree;
    brute_force<O> oracle;
    std::vector<O> initial;
    for (std::size_t i = 0; i < n; ++i) initial.push_back(g.object());
    tree.insert(initial.begin(), initial.end());
    oracle.insert(initial.begin(), initial.end());
    ASSERT_EQ(tree.check_invariants(), "");
    std::size_t hits = compare_queries(tree, oracle, g, 40);
    for (int round = 0; round < rounds; ++round) {
        SCOPED_TRACE("round " + std::to_string(round));
        // single and hinted inserts
        for (int i = 0; i < 12; ++i) {
            const O x = g.object();
            if (i % 2 == 0 || tree.empty()) tree.insert(x);
            else tree.insert(all_iterators(tree)[g.below(tree.size())], x);
            oracle.insert(x);
        }
        // a small bulk batch (incremental path) and, every third round, a large one (rebuild)
        std::vector<O> batch;
        for (std::size_t i = 0; i < (round % 3 == 2 ? tree.size() / 2 + 1 : 5); ++i) batch.push_back(g.object());
        tree.insert(batch.begin(), batch.end());
        oracle.insert(batch.begin(), batch.end());
        // erase by iterator
        for (int i = 0; i < 10 && !tree.empty(); ++i) {
            const auto it = all_iterators(tree)[g.below(tree.size())];
            const O v = *it;
            tree.erase(it);
            oracle.erase(oracle.find(v));
        }
        // erase by value (all equal)
        if (!tree.empty()) {
            const O v = *all_iterators(tree)[g.below(tree.size())];
            EXPECT_EQ(tree.erase(v), oracle.erase(v));
        }
        // erase a range (small, or a large one every fourth round)
        {
            auto its = all_iterators(tree);
            const std::size_t m = round % 4 == 3 ? its.size() / 3 : std::min<std::size_t>(4, its.size());
            std::vector<O> gone;
            for (std::size_t i = 0; i < m; ++i) gone.push_back(*its[i]);
            tree.erase(tree.begin(), m < its.size() ? its[m] : tree.end());
            for (const O& v : gone) oracle.erase(oracle.find(v));
        }
        // motion: update with an immediate path refit, or deferred to one refit()
        const bool deferred = round % 2 == 1;
        for (int i = 0; i < 15 && !tree.empty(); ++i) {
            const auto it = all_iterators(tree)[g.below(tree.size())];
            const O v = *it, w = g.moved(v);
            const auto same = tree.update(it, w, !deferred);
            EXPECT_TRUE(same == it) << "update keeps the iterator";
            oracle.erase(oracle.find(v));
            oracle.insert(w);
        }
        if (deferred) {
            EXPECT_THROW((void)tree.find_nearest(g.point_in(0, 1), 1), std::logic_error);
            tree.refit();
        }
        ASSERT_EQ(tree.size(), oracle.size());
        ASSERT_EQ(tree.check_invariants(), "");
        EXPECT_EQ(signatures_of(all_iterators(tree)), signatures_of(all_iterators(oracle)));
        hits += compare_queries(tree, oracle, g, 25);
    }
    EXPECT_GT(hits, 0u) << "the scenario never produced a ray hit; it tests nothing";
}

// The differential scenarios of parts 2 and 3 (bvh_volumes_test, bvh_2d_float_test), with their
// seeds: interleaved updates and motion; offset and small scales; small trees.
template <class Tree>
void interleaved_updates_and_motion() {
    for (std::uint64_t seed : {21u, 22u}) differential<Tree>(spatial_test::test_seed(seed * 104729), 250, 5);
}
template <class Tree>
void offset_and_small_scales() {
    differential<Tree>(spatial_test::test_seed(31), 150, 2, 1e6, 10);
    differential<Tree>(spatial_test::test_seed(32), 150, 2, 0, 1e-12);
}
template <class Tree>
void small_trees() {
    for (std::size_t n : {0u, 1u, 3u}) differential<Tree>(spatial_test::test_seed(200 + n), n, 3);
}

}  // namespace bvh_test
