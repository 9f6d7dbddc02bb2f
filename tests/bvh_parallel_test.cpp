// spatial::bvh's multi-threaded members (core/parallel.hpp):
//  * rebuild(par) / bvh(first, last, par) build the SAME tree as the sequential builder,
//    node for node: same node count and height, and every query visits the same number of
//    nodes and tests the same objects (median and SAH builders; aabb, sphere, obb and k-DOP
//    volumes; points and triangles; skewed and identical inputs);
//  * prepare_rays(par) lays out the same wide ray layout as prepare_rays();
//  * intersect_batch gives, with seq and with par, exactly the answers of one
//    intersect_object per ray, and rejects bad input before casting anything.
// With TBB (the default build) these run on several threads; without it `par` is sequential
// and the tests still check the answers.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <random>
#include <stdexcept>
#include <vector>

#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/objects/triangle.hpp"
#include "answer_comparison.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

using P3 = point<double, 3>;
using tri = objects::triangle<double, 3>;

std::vector<tri> random_triangles(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1), s(0.001, 0.02);
    std::vector<tri> out;
    for (std::size_t i = 0; i < n; ++i) {
        const P3 c{{u(rng), u(rng), u(rng)}};
        P3 v[3];
        const double h = s(rng);
        for (auto& p : v)
            for (std::size_t k = 0; k < 3; ++k) p[k] = c[k] + h * (2 * u(rng) - 1);
        out.emplace_back(v[0], v[1], v[2]);
    }
    return out;
}

// Same shape, node for node, as far as queries can tell: equal node counts and heights, and
// every ray and kNN query visits exactly as many nodes and tests exactly as many objects.
template <class Tree>
void expect_same_tree(const Tree& a, const Tree& b, std::uint64_t seed) {
    ASSERT_EQ(a.check_invariants(), "");
    ASSERT_EQ(b.check_invariants(), "");
    EXPECT_EQ(a.node_count(), b.node_count());
    EXPECT_EQ(a.height(), b.height());
    // Sums in preorder of every node's volume and box area: the same volumes in the same
    // order, bit for bit.
    EXPECT_EQ(a.node_surface_areas(), b.node_surface_areas());
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    using Pt = typename Tree::point_type;
    for (int q = 0; q < 200; ++q) {
        Pt o, d;
        for (std::size_t k = 0; k < Tree::dimension; ++k) o[k] = u(rng), d[k] = u(rng) - 0.5;
        d[0] += 0.01;
        typename Tree::info_type x, y;
        const auto ha = a.intersect_object(o, d, 0.0, x);
        const auto sa = a.last_query_stats();
        const auto hb = b.intersect_object(o, d, 0.0, y);
        const auto sb = b.last_query_stats();
        EXPECT_EQ(ha == a.end(), hb == b.end());
        EXPECT_EQ(x.hit_time, y.hit_time);
        EXPECT_EQ(sa.nodes_visited, sb.nodes_visited) << "ray " << q;
        EXPECT_EQ(sa.objects_tested, sb.objects_tested) << "ray " << q;
        const auto na = a.find_nearest(o, 5);
        const auto nsa = a.last_query_stats();
        const auto nb = b.find_nearest(o, 5);
        const auto nsb = b.last_query_stats();
        ASSERT_EQ(na.size(), nb.size());
        for (std::size_t i = 0; i < na.size(); ++i) EXPECT_TRUE(*na[i] == *nb[i]);
        EXPECT_EQ(nsa.nodes_visited, nsb.nodes_visited) << "knn " << q;
    }
}

template <class O, class BV, class Config>
void check_parallel_build(const std::vector<O>& data, std::uint64_t seed) {
    bvh<O, BV, Config> sequential(data.begin(), data.end());
    bvh<O, BV, Config> parallel(data.begin(), data.end(), par);
    {
        SCOPED_TRACE((std::string("built by the constructor, ") + bvh<O, BV, Config>::volume_name()));
        expect_same_tree(sequential, parallel, seed);
        // The same capacities too: the parallel replay reserves at once the headroom the
        // sequential build ends with. (Not for the copies below: a copy's arrays are exact.)
        EXPECT_EQ(sequential.memory_bytes(), parallel.memory_bytes());
        // The quality the parallel build sums from its plan is quality(), bit for bit.
        EXPECT_EQ(parallel.quality_at_build(), parallel.quality());
        EXPECT_EQ(sequential.quality_at_build(), parallel.quality_at_build());
    }
    // rebuild(par) of a tree grown by single inserts: the same as rebuild().
    bvh<O, BV, Config> grown, grown_copy;
    for (const O& x : data) grown.insert(x);
    grown_copy = grown;
    grown.rebuild();
    grown_copy.rebuild(par);
    SCOPED_TRACE((std::string("rebuilt, ") + bvh<O, BV, Config>::volume_name()));
    expect_same_tree(grown, grown_copy, seed + 1);
}

}  // namespace

TEST(bvh_parallel, build_of_triangles_is_the_sequential_tree_for_every_builder_and_volume) {
    const std::uint64_t seed = spatial_test::test_seed(71);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    const auto data = random_triangles(20000, seed);
    check_parallel_build<tri, aabb<double, 3>, bvh_sah_config<>>(data, seed);
    check_parallel_build<tri, aabb<double, 3>, bvh_median_config<>>(data, seed);
    check_parallel_build<tri, sphere<double, 3>, bvh_sah_config<>>(data, seed);
    check_parallel_build<tri, obb<double, 3>, bvh_sah_config<>>(data, seed);
    check_parallel_build<tri, kdop<double, 3, 14>, bvh_median_config<8>>(data, seed);
}

// A batch of at least bvh_detail::parallel_split_items objects: the root's split is binned on
// every core (chunks merged in item order), and the root's bounds are taken while the items
// are listed: still the sequential tree.
TEST(bvh_parallel, build_large_enough_to_bin_its_top_splits_on_every_core_is_the_sequential_tree) {
    const std::uint64_t seed = spatial_test::test_seed(74);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    auto data = random_triangles(bvh_detail::parallel_split_items + 9000, seed);
    // The smallest first coordinate is a zero, held by flat triangles of both signs: -0 in the
    // first 16,384 items (the first chunk of the listing), +0 after. One pass in item order
    // keeps the first, -0; chunks merged in any other order would give +0.
    for (std::size_t i = 0; i < data.size(); ++i) {
        std::array<P3, 3> v{data[i].vertex(0), data[i].vertex(1), data[i].vertex(2)};
        for (P3& p : v) p[0] = i % 97 == 0 ? (i < 16384 ? -0.0 : 0.0) : std::max(p[0], 0.001);
        data[i] = tri(v[0], v[1], v[2]);
    }
    check_parallel_build<tri, aabb<double, 3>, bvh_sah_config<>>(data, seed);
    check_parallel_build<tri, sphere<double, 3>, bvh_sah_config<>>(data, seed);
    const bvh<tri> sequential(data.begin(), data.end()), parallel(data.begin(), data.end(), par);
    EXPECT_EQ(sequential.root_volume().lo[0], 0.0);
    EXPECT_TRUE(std::signbit(sequential.root_volume().lo[0]));
    EXPECT_TRUE(std::signbit(parallel.root_volume().lo[0]));
}

// insert(first, last, par) checks and stores the batch on every core: a batch with rejected
// objects stores nothing and names the first of them, into an empty tree and into a full one.
TEST(bvh_parallel, parallel_insert_of_a_batch_with_bad_objects_names_the_first_and_stores_nothing) {
    const std::uint64_t seed = spatial_test::test_seed(75);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    auto data = random_triangles(100000, seed);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const P3 a = data[30000].vertex(0), b = data[30000].vertex(1);
    data[30000] = tri(P3{{a[0], a[1], nan}}, a, b);  // the first: coordinate 2
    data[70000] = tri(P3{{nan, a[1], a[2]}}, a, b);  // a later one: coordinate 0
    data[99999] = tri(P3{{std::numeric_limits<double>::infinity(), 0, 0}}, a, b);
    const auto good = random_triangles(20000, seed + 1);
    bvh<tri> empty, full(good.begin(), good.end());
    for (bvh<tri>* t : {&empty, &full}) {
        const auto before = spatial_test::contents(*t);
        try {
            t->insert(data.begin(), data.end(), par);
            FAIL() << "a batch with NaN coordinates was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("insert(first, last)"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("coordinate 2"), std::string::npos) << e.what();
        }
        EXPECT_EQ(spatial_test::contents(*t), before);
        EXPECT_EQ(t->check_invariants(), "");
        // Still usable: the good part of the batch goes in.
        t->insert(data.begin(), data.begin() + 30000, par);
        EXPECT_EQ(t->size(), before.size() + 30000);
        EXPECT_EQ(t->check_invariants(), "");
    }
}

TEST(bvh_parallel, build_of_points_skewed_and_identical_inputs_is_the_sequential_tree) {
    const std::uint64_t seed = spatial_test::test_seed(72);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<P3> skewed, identical(12000, P3{{0.25, 0.5, 0.75}});
    // Geometrically spaced along a line: SAH splits off small groups, the planner's skewed
    // branch iterates instead of recursing.
    for (int i = 0; i < 20000; ++i) skewed.push_back(P3{{std::pow(1.001, i), u(rng) * 1e-3, 0}});
    check_parallel_build<P3, aabb<double, 3>, bvh_sah_config<>>(skewed, seed);
    check_parallel_build<P3, aabb<double, 3>, bvh_sah_config<>>(identical, seed);
    check_parallel_build<P3, aabb<double, 3>, bvh_median_config<16>>(identical, seed);
}

// prepare_rays(par) gathers the wide layout's leaves on every core: the same layout as
// prepare_rays(), as far as rays can tell (same hits, hit times, nodes visited and objects
// tested on every ray) and byte for byte in size.
TEST(bvh_parallel, ray_layout_gathered_on_every_core_is_the_sequential_layout) {
    const std::uint64_t seed = spatial_test::test_seed(79);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    const auto data = random_triangles(30000, seed);
    bvh<tri> one(data.begin(), data.end()), many(data.begin(), data.end());
    one.prepare_rays();
    many.prepare_rays(par);
    EXPECT_EQ(one.memory_bytes(), many.memory_bytes());
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    std::size_t hits = 0;
    for (int q = 0; q < 3000; ++q) {
        const P3 o{{u(rng), u(rng), u(rng)}}, d{{u(rng) - 0.5 + 0.01, u(rng) - 0.5, u(rng) - 0.5}};
        intersect_info<P3> x, y;
        const auto ha = one.intersect_object(o, d, 0.0, x);
        const auto sa = one.last_query_stats();
        const auto hb = many.intersect_object(o, d, 0.0, y);
        const auto sb = many.last_query_stats();
        ASSERT_EQ(ha == one.end(), hb == many.end()) << "ray " << q;
        if (ha != one.end()) {
            EXPECT_TRUE(*ha == *hb) << "ray " << q;
            ++hits;
        }
        EXPECT_EQ(x.hit_time, y.hit_time) << "ray " << q;
        EXPECT_TRUE(sa.wide_ray_layout && sb.wide_ray_layout) << "ray " << q;
        EXPECT_EQ(sa.nodes_visited, sb.nodes_visited) << "ray " << q;
        EXPECT_EQ(sa.objects_tested, sb.objects_tested) << "ray " << q;
    }
    EXPECT_GT(hits, 300u);
}

// A binary tree as wide_ray_layout::build reads one (the bvh's binary_view), built here by
// median splits of the objects' centres on a fixed axis per level, down to leaves of
// `leaf` objects; `chain` splits one object off at each level instead (a tree as deep as
// it has objects).
struct test_binary_tree {
    using node_index = std::uint32_t;
    struct node {
        P3 lo, hi;
        bool leaf = false;
        std::uint32_t first = 0, count = 0;  // leaf: slots [first, first + count); inner: left child
    };
    std::vector<tri> objects;
    std::vector<std::uint32_t> order;  // slots in leaf order
    std::vector<node> nodes;

    test_binary_tree(std::vector<tri> objs, std::size_t leaf, bool chain) : objects(std::move(objs)) {
        for (std::uint32_t i = 0; i < objects.size(); ++i) order.push_back(i);
        nodes.emplace_back();
        build(0, 0, static_cast<std::uint32_t>(objects.size()), 0, leaf, chain);
    }
    void build(std::size_t n, std::uint32_t b, std::uint32_t e, std::size_t depth, std::size_t leaf, bool chain) {
        for (std::size_t a = 0; a < 3; ++a) nodes[n].lo[a] = 1e300, nodes[n].hi[a] = -1e300;
        for (std::uint32_t i = b; i < e; ++i)
            for (std::size_t k = 0; k < 3; ++k)
                for (std::size_t a = 0; a < 3; ++a)
                    nodes[n].lo[a] = std::min(nodes[n].lo[a], objects[order[i]].vertex(k)[a]),
                    nodes[n].hi[a] = std::max(nodes[n].hi[a], objects[order[i]].vertex(k)[a]);
        if (e - b <= leaf) {
            nodes[n].leaf = true, nodes[n].first = b, nodes[n].count = e - b;
            return;
        }
        const std::size_t axis = depth % 3;
        const std::uint32_t m = chain ? b + 1 : b + (e - b) / 2;
        std::nth_element(order.begin() + b, order.begin() + m, order.begin() + e, [&](std::uint32_t x, std::uint32_t y) {
            return objects[x].vertex(0)[axis] < objects[y].vertex(0)[axis];
        });
        const auto left = static_cast<std::uint32_t>(nodes.size());
        nodes[n].first = left;
        nodes.emplace_back();
        nodes.emplace_back();
        build(left, b, m, depth + 1, leaf, chain);
        build(left + 1, m, e, depth + 1, leaf, chain);
    }
    // What wide_ray_layout::build reads.
    node_index root() const { return 0; }
    bool is_leaf(node_index n) const { return nodes[n].leaf; }
    node_index left(node_index n) const { return nodes[n].first; }
    double lower(node_index n, std::size_t a) const { return nodes[n].lo[a]; }
    double upper(node_index n, std::size_t a) const { return nodes[n].hi[a]; }
    std::size_t leaf_size(node_index n) const { return nodes[n].count; }
    std::size_t object_count() const { return objects.size(); }
    std::uint32_t leaf_slot(node_index n, std::size_t i) const { return order[nodes[n].first + i]; }
    const tri& value(std::uint32_t slot) const { return objects[slot]; }
};

// The collapse into wide nodes on every core (wide_ray_layout::collapse_on_every_core: the
// top of the tree in order, the subtrees of at most collapse_grain objects concurrently, then
// renumbered) lays out exactly the sequential collapse's nodes, in the same order: compared
// node by node, for balanced trees with small and large leaves (subtrees far above and just
// above the grain), 4- and 8-wide layouts, and a chain as deep as it has objects.
TEST(bvh_parallel, ray_layout_collapsed_on_every_core_is_the_sequential_layout_node_for_node) {
    const std::uint64_t seed = spatial_test::test_seed(83);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    const auto compare = [](const test_binary_tree& tree, auto layout_type) {
        decltype(layout_type) one, many;
        one.build(tree, false);
        many.build(tree, true);
        ASSERT_GT(one.node_count(), 1u);
        ASSERT_EQ(one.node_count(), many.node_count());
        const auto a = one.nodes(), b = many.nodes();
        for (std::size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(a[i] == b[i]) << "wide node " << i << " of " << a.size();
        EXPECT_EQ(one.memory_bytes(), many.memory_bytes());
    };
    using wide8 = bvh_detail::wide_ray_layout<tri, double, 3, 8>;
    using wide4 = bvh_detail::wide_ray_layout<tri, double, 3, 4>;
    for (const std::size_t n : {2100u, 30000u, 100000u}) {
        SCOPED_TRACE(n);
        for (const std::size_t leaf : {1u, 2u, 7u}) {
            const test_binary_tree tree(random_triangles(n, seed + n + leaf), leaf, false);
            compare(tree, wide8{});
            compare(tree, wide4{});
        }
    }
    const test_binary_tree chain(random_triangles(5000, seed), 1, true);
    compare(chain, wide8{});
}

TEST(bvh_parallel, batched_casts_equal_single_casts_with_both_policies) {
    const std::uint64_t seed = spatial_test::test_seed(73);
    SCOPED_TRACE(spatial_test::replay_hint(seed));
    const auto data = random_triangles(30000, seed);
    bvh<tri> tree(data.begin(), data.end(), par);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-0.2, 1.2);
    std::vector<ray<P3>> rays;
    for (int i = 0; i < 5000; ++i)
        rays.push_back({P3{{u(rng), u(rng), -0.5}}, P3{{u(rng) - 0.5, u(rng) - 0.5, 1}}, i % 7 == 0 ? 0.002 : 0.0});
    std::vector<intersect_info<P3>> single(rays.size()), seq_infos(rays.size()), par_infos(rays.size());
    for (std::size_t i = 0; i < rays.size(); i += 3) single[i].hit_time = seq_infos[i].hit_time = par_infos[i].hit_time = 0.8;
    std::vector<bvh<tri>::iterator> seq_hits(rays.size()), par_hits(rays.size());
    tree.intersect_batch(rays, seq_hits, seq_infos, seq);
    tree.intersect_batch(rays, par_hits, par_infos, par);
    std::size_t hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const auto it = tree.intersect_object(rays[i].origin, rays[i].direction, rays[i].thickness, single[i]);
        EXPECT_EQ(seq_hits[i] == tree.end(), it == tree.end()) << "ray " << i;
        EXPECT_EQ(par_hits[i] == tree.end(), it == tree.end()) << "ray " << i;
        EXPECT_EQ(seq_infos[i].hit_time, single[i].hit_time) << "ray " << i;
        EXPECT_EQ(par_infos[i].hit_time, single[i].hit_time) << "ray " << i;
        hit_count += it != tree.end();
    }
    EXPECT_GT(hit_count, 500u);
}

TEST(bvh_parallel, batched_casts_reject_bad_input_before_casting) {
    const auto data = random_triangles(100, 5);
    bvh<tri> tree(data.begin(), data.end());
    std::vector<ray<P3>> rays(3, ray<P3>{P3{{0.5, 0.5, -1}}, P3{{0, 0, 1}}, 0.0});
    std::vector<bvh<tri>::iterator> hits(3, tree.end());
    std::vector<intersect_info<P3>> infos(2);
    EXPECT_THROW(tree.intersect_batch(rays, hits, infos, par), std::invalid_argument);
    infos.resize(3);
    rays[2].direction = P3{{0, 0, 0}};
    try {
        tree.intersect_batch(rays, hits, infos, par);
        FAIL() << "a zero direction must be rejected";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("direction"), std::string::npos) << e.what();
    }
    for (const auto& info : infos) EXPECT_EQ(info.hit_time, std::numeric_limits<double>::infinity());  // untouched
}
