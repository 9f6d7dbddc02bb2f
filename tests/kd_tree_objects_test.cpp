// kd_tree over objects with extent (the skd-tree of Ooi, McDonell & Sacks-Davis 1987): the shared
// contract suite, structure-specific checks (extents stay conservative, every object stored
// once) and hard cases (identical objects, objects on split planes, axis rays with +-0
// components, origins on planes, huge and tiny coordinates, a closed mesh hit from inside).
// Differential tests against brute_force: kd_tree_objects_differential_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "container_contract.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"
#include "test_support.hpp"

using namespace spatial;
using objects::box;
using objects::sphere;
using objects::triangle;
using spatial_test::tagged_box;
using P3 = point<double, 3>;

// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): boxes,
// triangles, a user type, both scalars and dimensions; the release build runs all.
#if SPATIAL_TEST_FULL_MATRIX
using kd_object_containers =
    ::testing::Types<kd_tree<box<double, 3>>, kd_tree<box<float, 2>>, kd_tree<sphere<double, 3>>,
                     kd_tree<triangle<double, 3>>, kd_tree<triangle<float, 2>>, kd_tree<tagged_box, kd_tree_config<4>>>;
#else
using kd_object_containers = ::testing::Types<kd_tree<box<float, 2>>, kd_tree<triangle<double, 3>>,
                                              kd_tree<tagged_box, kd_tree_config<4>>>;
#endif
namespace spatial_contract {
INSTANTIATE_TYPED_TEST_SUITE_P(kd_objects, container_contract, kd_object_containers);
}

namespace {

template <class T>
using sorted_times = std::vector<T>;

// Sorted squared distances from q of the objects behind `its`.
template <class It, class Q>
auto distances(const Q& q, const std::vector<It>& its) {
    std::vector<typename Q::scalar_type> d;
    for (const auto& it : its) d.push_back(object_squared_distance(*it, q));
    std::sort(d.begin(), d.end());
    return d;
}

// Runs one ray on a kd_tree and on the oracle and requires the same answer (hit or not, and the
// bit-identical hit time: both call the object's own intersect).
template <class Tree, class Oracle, class Q>
void expect_same_ray(const Tree& tree, const Oracle& oracle, const Q& o, const Q& d, typename Q::scalar_type thick) {
    intersect_info<Q> a, b;
    const bool ha = tree.intersect(o, d, thick, a);
    const bool hb = oracle.intersect(o, d, thick, b);
    ASSERT_EQ(ha, hb) << "ray from " << o << " along " << d;
    ASSERT_EQ(a.hit_time, b.hit_time) << "ray from " << o << " along " << d;
}

// Same kNN distances, ball, box and ray answers as the oracle at a few queries.
template <class Tree, class Oracle, class Q>
void expect_same_queries(const Tree& tree, const Oracle& oracle, const Q& q, typename Q::scalar_type r) {
    for (std::size_t k : {std::size_t(1), std::size_t(7), tree.size() + 1})
        ASSERT_EQ(distances(q, tree.find_nearest(q, k)), distances(q, oracle.find_nearest(q, k))) << "k=" << k;
    ASSERT_EQ(distances(q, tree.find_in_ball(q, r)), distances(q, oracle.find_in_ball(q, r)));
    Q lo = q, hi = q;
    for (std::size_t i = 0; i < Q::dimension; ++i) lo[i] -= r, hi[i] += r;
    ASSERT_EQ(distances(q, tree.find_in_box(lo, hi)), distances(q, oracle.find_in_box(lo, hi)));
}


box<double, 3> cube(double x, double y, double z, double h) {
    return box<double, 3>(P3{{x - h, y - h, z - h}}, P3{{x + h, y + h, z + h}});
}

}  // namespace

// ---- structure: every object stored once, extents conservative under churn ----------------

TEST(kd_tree_objects, every_object_is_stored_once_and_iteration_sees_each_once) {
    // Large, overlapping boxes straddle many split planes; a split-based kd-tree would
    // duplicate them. Here size() == number of inserts and iteration yields each exactly once.
    kd_tree<box<double, 3>, kd_tree_config<4>> t;
    std::mt19937_64 rng(spatial_test::test_seed(5));
    SCOPED_TRACE(spatial_test::replay_hint(spatial_test::test_seed(5)));
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<box<double, 3>> in;
    for (int i = 0; i < 500; ++i) in.push_back(cube(u(rng), u(rng), u(rng), 0.3 * u(rng)));
    for (const auto& b : in) t.insert(b);
    ASSERT_EQ(t.size(), in.size());
    ASSERT_EQ(t.check_invariants(), "");
    std::multiset<std::array<double, 6>> seen, want;
    for (const auto& b : t) seen.insert({b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]});
    for (const auto& b : in) want.insert({b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]});
    EXPECT_EQ(seen, want);
    // A box query covering everything reports each object once.
    const auto all = t.find_in_box(P3{{-1, -1, -1}}, P3{{2, 2, 2}});
    EXPECT_EQ(all.size(), in.size());
    std::set<const box<double, 3>*> unique;
    for (auto it : all) unique.insert(&*it);
    EXPECT_EQ(unique.size(), in.size());
    EXPECT_GT(t.height(), 3u);
}

TEST(kd_tree_objects, extents_stay_conservative_under_churn_and_hinted_and_bulk_inserts) {
    spatial_test::seeded_rng rng(77);
    std::uniform_real_distribution<double> u(0, 1);
    kd_tree<box<double, 3>, kd_tree_config<4>> t;
    brute_force<box<double, 3>> oracle;
    std::vector<kd_tree<box<double, 3>, kd_tree_config<4>>::iterator> live;
    for (int round = 0; round < 3000; ++round) {
        const int op = static_cast<int>(rng() % 10);
        // Sizes vary over three decades so that growing a leaf's extent must propagate up.
        const auto b = cube(u(rng), u(rng), u(rng), std::pow(10.0, -3 * u(rng)) * 0.5);
        if (op < 4) {
            live.push_back(t.insert(b));
            oracle.insert(b);
        } else if (op < 6) {
            live.push_back(t.insert(live.empty() ? t.end() : live[rng() % live.size()], b));
            oracle.insert(b);
        } else if (op < 7) {
            std::vector<box<double, 3>> batch;
            for (int i = 0; i < 1 + static_cast<int>(rng() % 40); ++i) batch.push_back(cube(u(rng), u(rng), u(rng), 0.2 * u(rng)));
            t.insert(batch.begin(), batch.end());
            oracle.insert(batch.begin(), batch.end());
            live.clear();
            for (auto it = t.begin(); it != t.end(); ++it) live.push_back(it);
        } else if (!live.empty()) {
            const std::size_t i = rng() % live.size();
            const auto v = *live[i];
            t.erase(live[i]);
            live[i] = live.back();
            live.pop_back();
            const std::size_t c = oracle.erase(v);
            for (std::size_t r = 1; r < c; ++r) oracle.insert(v);
        }
        if (round % 100 == 0) {
            ASSERT_EQ(t.check_invariants(), "") << "round " << round;
            ASSERT_NO_FATAL_FAILURE(expect_same_queries(t, oracle, P3{{u(rng), u(rng), u(rng)}}, 0.1));
            ASSERT_NO_FATAL_FAILURE(
                expect_same_ray(t, oracle, P3{{u(rng), u(rng), -0.5}}, P3{{u(rng) - 0.5, u(rng) - 0.5, 1}}, 0.0));
        }
    }
    ASSERT_EQ(t.size(), oracle.size());
}

// ---- hard cases ----------------------------------------------------------------------------

TEST(kd_tree_objects, all_objects_identical) {
    kd_tree<triangle<double, 3>> t;
    brute_force<triangle<double, 3>> oracle;
    const triangle<double, 3> tri(P3{{0, 0, 0}}, P3{{1, 0, 0}}, P3{{0, 1, 1}});
    std::vector<triangle<double, 3>> batch(300, tri);
    t.insert(batch.begin(), batch.end());
    oracle.insert(batch.begin(), batch.end());
    for (int i = 0; i < 200; ++i) {
        t.insert(tri);
        oracle.insert(tri);
    }
    ASSERT_EQ(t.check_invariants(), "");
    EXPECT_EQ(t.count(tri), 500u);
    // Median splits and the scapegoat rule keep depth logarithmic even on identical keys.
    EXPECT_LE(static_cast<double>(t.height()), std::ceil(std::log(500.0 / 16) / std::log(4.0 / 3)) + 2);
    ASSERT_NO_FATAL_FAILURE(expect_same_queries(t, oracle, P3{{0.2, 0.2, 0.5}}, 0.5));
    ASSERT_NO_FATAL_FAILURE(expect_same_ray(t, oracle, P3{{0.2, 0.2, -1}}, P3{{0, 0, 1}}, 0.0));
    EXPECT_EQ(t.find_nearest(P3{{5, 5, 5}}, 20).size(), 20u);
    EXPECT_EQ(t.erase(tri), 500u);
    EXPECT_TRUE(t.empty());
    EXPECT_EQ(t.check_invariants(), "");
}

TEST(kd_tree_objects, objects_exactly_on_split_planes_and_rays_along_them) {
    // A lattice of unit boxes [i, i+1]^3: centres at half-integers, and every box face lies on
    // the planes where neighbours touch. Rays run along axes inside the faces, with +0 and -0
    // direction components, from origins on those planes.
    using B = box<double, 3>;
    kd_tree<B, kd_tree_config<2>> t;
    brute_force<B> oracle;
    std::vector<B> lattice;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k)
                if ((i + j + k) % 3 != 0)  // leave holes so rays have something to miss
                    lattice.emplace_back(P3{{double(i), double(j), double(k)}}, P3{{i + 1.0, j + 1.0, k + 1.0}});
    t.insert(lattice.begin(), lattice.end());
    oracle.insert(lattice.begin(), lattice.end());
    ASSERT_EQ(t.check_invariants(), "");
    int rays = 0;
    for (double a = -1; a <= 9; a += 0.5)
        for (double b = -1; b <= 9; b += 0.5)
            for (int axis = 0; axis < 3; ++axis)
                for (double sign : {1.0, -1.0})
                    for (double zero : {0.0, -0.0}) {
                        P3 o{}, d{};
                        o[axis] = sign > 0 ? -2 : 10;
                        o[(axis + 1) % 3] = a;
                        o[(axis + 2) % 3] = b;
                        d[axis] = sign;
                        d[(axis + 1) % 3] = zero;
                        d[(axis + 2) % 3] = zero;
                        ASSERT_NO_FATAL_FAILURE(expect_same_ray(t, oracle, o, d, 0.0));
                        ++rays;
                    }
    EXPECT_GT(rays, 5000);
    // Origins on planes inside the lattice, oblique directions.
    std::mt19937_64 rng(spatial_test::test_seed(11));
    for (int i = 0; i < 2000; ++i) {
        const P3 o{{double(rng() % 9), double(rng() % 9), double(rng() % 9)}};
        P3 d{{double(int(rng() % 5) - 2), double(int(rng() % 5) - 2), double(int(rng() % 5) - 2)}};
        if (d[0] == 0 && d[1] == 0 && d[2] == 0) continue;
        ASSERT_NO_FATAL_FAILURE(expect_same_ray(t, oracle, o, d, double(rng() % 3) * 0.25));
        ASSERT_NO_FATAL_FAILURE(expect_same_queries(t, oracle, o, 1.0));
    }
}

template <class T> using kd_tree_objects_scale = spatial_test::plain_typed_suite<T>;
TYPED_TEST_SUITE(kd_tree_objects_scale, spatial_test::scalar_types);

// Huge (offset 1e15 for double, 1e7 for float so that objects stay resolvable) and tiny (1e-15)
// objects: every query agrees with the oracle, rays bit-exactly.
TYPED_TEST(kd_tree_objects_scale, huge_and_tiny_coordinates) {
    using T = TypeParam;
    using V = point<T, 3>;
    const spatial_test::logged_seed seed(2026);
    const double huge = std::is_same_v<T, float> ? 1e7 : 1e15;
    for (const auto& placement : {std::pair{huge, huge * 1e-3}, std::pair{0.0, 1e-15}, std::pair{1e8, 1.0}}) {
        // Plain variables, not a structured binding: clang before 16 cannot capture one.
        const double offset = placement.first, scale = placement.second;
        SCOPED_TRACE("offset " + std::to_string(offset) + " scale " + std::to_string(scale));
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(0, 1);
        auto at = [&](double a, double b, double c) {
            return V{{T(offset + scale * a), T(offset + scale * b), T(offset + scale * c)}};
        };
        kd_tree<triangle<T, 3>, kd_tree_config<4>> tt;
        brute_force<triangle<T, 3>> ot;
        kd_tree<sphere<T, 3>> ts;
        brute_force<sphere<T, 3>> os;
        for (int i = 0; i < 400; ++i) {
            const double x = u(rng), y = u(rng), z = u(rng), h = 0.05 * u(rng);
            const triangle<T, 3> tri(at(x, y, z), at(x + h, y, z + h), at(x, y + h, z - h));
            tt.insert(tri);
            ot.insert(tri);
            const sphere<T, 3> s(at(x, y, z), T(scale * h));
            ts.insert(s);
            os.insert(s);
        }
        ASSERT_EQ(tt.check_invariants(), "");
        ASSERT_EQ(ts.check_invariants(), "");
        for (int i = 0; i < 300; ++i) {
            const V o = at(u(rng), u(rng), -0.5);
            V d{{T(u(rng) - 0.5), T(u(rng) - 0.5), T(1)}};
            if (i % 3 == 0) d[0] = (i % 2) ? T(0) : T(-0.0);
            ASSERT_NO_FATAL_FAILURE(expect_same_ray(tt, ot, o, d, T(0)));
            ASSERT_NO_FATAL_FAILURE(expect_same_ray(ts, os, o, d, T(0)));
            const V q = at(u(rng), u(rng), u(rng));
            // kNN: distances must agree for boxes of the query; sphere and triangle distance
            // routines are compared through the oracle's own values.
            ASSERT_NO_FATAL_FAILURE(expect_same_queries(ts, os, q, T(scale * 0.1)));
            ASSERT_NO_FATAL_FAILURE(expect_same_queries(tt, ot, q, T(scale * 0.1)));
        }
    }
}

TYPED_TEST(kd_tree_objects_scale, closed_icosphere_is_never_missed_from_inside) {
    using T = TypeParam;
    using V = point<T, 3>;
    spatial_test::seeded_rng rng(41);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const double offset : {0.0, 1e3}) {
        const auto mesh = spatial_test::icosphere<T>(3, 2.0, {offset, offset, offset});  // 1280 triangles
        kd_tree<triangle<T, 3>> t(mesh.begin(), mesh.end());
        brute_force<triangle<T, 3>> oracle(mesh.begin(), mesh.end());
        ASSERT_EQ(t.check_invariants(), "");
        std::vector<V> origins = {V{{T(offset), T(offset), T(offset)}}};
        for (int i = 0; i < 4; ++i)
            origins.push_back(V{{T(offset + unit(rng) * 1.2 - 0.6), T(offset + unit(rng) * 1.2 - 0.6),
                                 T(offset + unit(rng) * 1.2 - 0.6)}});
        int rays = 0;
        for (const V& o : origins)
            for (std::size_t f = 0; f < mesh.size(); f += 3)
                for (int k = 0; k < 3; ++k) {
                    // Through a shared vertex and through a point on a shared edge.
                    const V& a = mesh[f].vertex(k);
                    const V& b = mesh[f].vertex((k + 1) % 3);
                    const T s = T(unit(rng));
                    for (const V& target : {a, V{{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])}}}) {
                        const V d{{target[0] - o[0], target[1] - o[1], target[2] - o[2]}};
                        intersect_info<V> info;
                        ASSERT_TRUE(t.intersect(o, d, info)) << "ray from " << o << " toward " << target << " slipped through";
                        ASSERT_NO_FATAL_FAILURE(expect_same_ray(t, oracle, o, d, T(0)));
                        ++rays;
                    }
                }
        // Axis rays from the centre with +-0 components hit vertices of the icosahedron's axes.
        for (int axis = 0; axis < 3; ++axis)
            for (double sign : {1.0, -1.0})
                for (double zero : {0.0, -0.0}) {
                    V d{{T(zero), T(zero), T(zero)}};
                    d[static_cast<std::size_t>(axis)] = T(sign);
                    intersect_info<V> info;
                    ASSERT_TRUE(t.intersect(origins[0], d, info));
                    ASSERT_NO_FATAL_FAILURE(expect_same_ray(t, oracle, origins[0], d, T(0)));
                }
        EXPECT_GT(rays, 2000);
    }
}

TEST(kd_tree_objects, thick_rays_and_eps_knn_on_spheres_in_2d_float) {
    using S = sphere<float, 2>;
    using V = point<float, 2>;
    spatial_test::seeded_rng rng(9);
    std::uniform_real_distribution<float> u(0, 1);
    kd_tree<S> t;
    brute_force<S> oracle;
    for (int i = 0; i < 2000; ++i) {
        const S s(V{{u(rng), u(rng)}}, 0.01f * u(rng));
        t.insert(s);
        oracle.insert(s);
    }
    for (int i = 0; i < 300; ++i) {
        const V o{{u(rng), u(rng)}};
        const V d{{u(rng) - 0.5f, u(rng) - 0.5f}};
        ASSERT_NO_FATAL_FAILURE(expect_same_ray(t, oracle, o, d, 0.02f * u(rng)));
        const auto want = distances(o, oracle.find_nearest(o, 10));
        const auto got = distances(o, t.find_nearest(o, 10, 0.5f));
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t k = 0; k < want.size(); ++k) ASSERT_LE(std::sqrt(got[k]), 1.5f * std::sqrt(want[k]) * 1.00001f + 1e-7f);
    }
}
