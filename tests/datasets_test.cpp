// datasets module: the seeded workload generators (size, reproducibility, the geometric
// property each workload promises, pinned output bits), the Morton ordering, and the
// point-set loaders (committed samples, malformed input, fetched real data when present).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/generators.hpp"
#include "datasets/ply_check.hpp"
#include "datasets/point_set_io.hpp"

namespace {

namespace fs = std::filesystem;

template <class T, std::size_t D>
struct config {
    using scalar = T;
    static constexpr std::size_t dim = D;
    using point = spatial::point<T, D>;
};

using configs = ::testing::Types<config<float, 2>, config<float, 3>, config<double, 2>,
                                 config<double, 3>>;

template <class C>
class generators : public ::testing::Test {};
TYPED_TEST_SUITE(generators, configs);

const std::vector<std::string> all_workloads{"uniform", "clusters", "sphere",     "plane",
                                             "line",    "lattice",  "duplicates", "clusters_far"};
constexpr std::uint64_t seed = 20240611;

template <class P>
double distance_squared(const P& a, const P& b) {
    double sum = 0.0;
    for (std::size_t d = 0; d < P::dimension; ++d) {
        const double diff = static_cast<double>(a[d]) - static_cast<double>(b[d]);
        sum += diff * diff;
    }
    return sum;
}

template <class P>
bool point_less(const P& a, const P& b) {
    return a.coords < b.coords;
}

template <class P>
std::size_t distinct_count(std::vector<P> pts) {
    std::sort(pts.begin(), pts.end(), point_less<P>);
    return static_cast<std::size_t>(std::unique(pts.begin(), pts.end()) - pts.begin());
}

// ---------------------------------------------------------------------------- names

TEST(workload_names, lists_the_eight_workloads_in_order) {
    const auto names = datasets::point_workload_names();
    ASSERT_EQ(names.size(), all_workloads.size());
    for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], all_workloads[i]);
}

TEST(workload_names, unknown_workload_throws_naming_it_and_listing_valid_ones) {
    try {
        (void)datasets::generate_points<double, 3>("gaussian_blobs", 10, seed);
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("\"gaussian_blobs\""), std::string::npos) << what;
        for (const auto& w : all_workloads) EXPECT_NE(what.find(w), std::string::npos) << what;
    }
    EXPECT_THROW((void)(datasets::generate_queries<float, 2>("Uniform", 10, seed, 10)),
                 std::invalid_argument);
    EXPECT_THROW((void)(datasets::generate_points<float, 2>("", 10, seed)), std::invalid_argument);
}

// ---------------------------------------------------------------------------- generic

TYPED_TEST(generators, every_workload_returns_exactly_n_points) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (const auto& w : all_workloads) {
        for (std::size_t n : {0u, 1u, 2u, 7u, 100u, 1000u}) {
            EXPECT_EQ((datasets::generate_points<T, D>(w, n, seed).size()), n) << w << " n=" << n;
        }
    }
}

TYPED_TEST(generators, same_seed_gives_identical_points_and_another_seed_different_ones) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (const auto& w : all_workloads) {
        const auto a = datasets::generate_points<T, D>(w, 500, seed);
        const auto b = datasets::generate_points<T, D>(w, 500, seed);
        const auto c = datasets::generate_points<T, D>(w, 500, seed + 1);
        EXPECT_EQ(a, b) << w;
        EXPECT_NE(a, c) << w;
    }
}

TYPED_TEST(generators, workloads_of_one_seed_are_not_copies_of_each_other) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    // uniform and plane read the same kind of uniforms; their streams must still differ.
    const auto u = datasets::generate_points<T, D>("uniform", 50, seed);
    const auto p = datasets::generate_points<T, D>("plane", 50, seed);
    EXPECT_NE(u[0][0], p[0][0]);
}

TYPED_TEST(generators, all_coordinates_are_finite_and_in_roughly_the_unit_cube) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (const auto& w : all_workloads) {
        // Box–Muller from 53-bit uniforms stays within 8.58 sigma of a centre in [0.1, 0.9).
        const bool clustered = w == "clusters" || w == "clusters_far";
        const double lo = clustered ? 0.1 - 8.6 * 0.02 : 0.0;
        const double hi = clustered ? 0.9 + 8.6 * 0.02 : 1.0;
        for (const auto& p : datasets::generate_points<T, D>(w, 3000, seed)) {
            for (std::size_t d = 0; d < D; ++d) {
                ASSERT_TRUE(std::isfinite(p[d])) << w;
                ASSERT_GE(p[d], lo) << w << " " << p;
                ASSERT_LE(p[d], hi) << w << " " << p;
            }
        }
    }
}

// ---------------------------------------------------------------------------- per workload

TYPED_TEST(generators, uniform_is_in_the_half_open_cube_with_mean_one_half) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    const auto pts = datasets::generate_points<T, D>("uniform", 20000, seed);
    for (std::size_t d = 0; d < D; ++d) {
        double sum = 0.0;
        for (const auto& p : pts) {
            ASSERT_GE(p[d], T(0));
            ASSERT_LT(p[d], T(1));
            sum += static_cast<double>(p[d]);
        }
        // Standard error of the mean: sqrt(1/12 / 20000) = 0.002; allow 5 of them.
        EXPECT_NEAR(sum / 20000.0, 0.5, 0.01) << "axis " << d;
    }
}

TYPED_TEST(generators, clusters_stay_within_eight_point_six_sigma_of_a_shared_centre) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    const auto centres = datasets::detail::cluster_centres<D>(seed);
    for (const auto& c : centres) {
        for (double x : c) {
            EXPECT_GE(x, 0.1);
            EXPECT_LT(x, 0.9);
        }
    }
    const auto near_some_centre = [&](const auto& p) {
        return std::any_of(centres.begin(), centres.end(), [&](const auto& c) {
            for (std::size_t d = 0; d < D; ++d) {
                if (std::abs(static_cast<double>(p[d]) - c[d]) > 8.6 * 0.02) return false;
            }
            return true;
        });
    };
    std::vector<std::size_t> hits(centres.size(), 0);
    const auto pts = datasets::generate_points<T, D>("clusters", 4000, seed);
    for (const auto& p : pts) {
        ASSERT_TRUE(near_some_centre(p)) << p;
        // Attribute to the nearest centre to see that every cluster is used.
        std::size_t best = 0;
        double best_d2 = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < centres.size(); ++i) {
            double d2 = 0.0;
            for (std::size_t d = 0; d < D; ++d) {
                const double diff = static_cast<double>(p[d]) - centres[i][d];
                d2 += diff * diff;
            }
            if (d2 < best_d2) best_d2 = d2, best = i;
        }
        ++hits[best];
    }
    for (std::size_t i = 0; i < hits.size(); ++i) EXPECT_GT(hits[i], 100u) << "cluster " << i;
    // The queries use the same centres.
    for (const auto& q : datasets::generate_queries<T, D>("clusters", 500, seed, 4000)) {
        ASSERT_TRUE(near_some_centre(q)) << q;
    }
}

// clusters_far: the clusters' points, queried from everywhere. Its queries are uniform in
// the unit cube, so (unlike clusters' queries, drawn from the clusters) most of them are far
// from every point: the workload that measures how a search proves a far cluster empty.
TYPED_TEST(generators, clusters_far_has_the_clusters_points_and_uniform_queries_far_from_them) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    const auto pts = datasets::generate_points<T, D>("clusters_far", 3000, seed);
    EXPECT_EQ(pts, (datasets::generate_points<T, D>("clusters", 3000, seed)));
    const auto nearest = [&](const auto& q) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& p : pts) best = std::min(best, distance_squared(p, q));
        return std::sqrt(best);
    };
    const auto far_queries = datasets::generate_queries<T, D>("clusters_far", 400, seed, 3000);
    const auto near_queries = datasets::generate_queries<T, D>("clusters", 400, seed, 3000);
    ASSERT_EQ(far_queries.size(), 400u);
    std::size_t far_count = 0, near_far_count = 0;
    std::vector<double> mean(D, 0.0);
    for (const auto& q : far_queries) {
        for (std::size_t d = 0; d < D; ++d) {
            ASSERT_GE(q[d], T(0)) << q;
            ASSERT_LT(q[d], T(1)) << q;
            mean[d] += static_cast<double>(q[d]) / 400.0;
        }
        // Three cluster sigmas (0.06) from the nearest point: outside every cluster's core.
        if (nearest(q) > 0.06) ++far_count;
    }
    for (const auto& q : near_queries)
        if (nearest(q) > 0.06) ++near_far_count;
    for (std::size_t d = 0; d < D; ++d) EXPECT_NEAR(mean[d], 0.5, 0.05) << "axis " << d;
    // 16 clusters of radius ~3 sigma cover a small part of the cube (in 2D about 16 pi 0.06^2
    // = 18 %, less in 3D): most uniform queries are far, almost no clustered one is.
    EXPECT_GT(far_count, 400u / 2) << "queries far from every point";
    EXPECT_LT(near_far_count, 400u / 20) << "clusters' own queries far from every point";
    // Its own query stream: not the uniform workload's queries.
    EXPECT_NE(far_queries, (datasets::generate_queries<T, D>("uniform", 400, seed, 3000)));
}

TYPED_TEST(generators, sphere_points_are_on_the_sphere_and_cover_it) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    spatial::point<T, D> centre;
    centre.coords.fill(T(0.5));
    const auto pts = datasets::generate_points<T, D>("sphere", 5000, seed);
    std::vector<double> mean(D, 0.0);
    for (const auto& p : pts) {
        ASSERT_NEAR(std::sqrt(distance_squared(p, centre)), 0.5, 1e-6) << p;
        for (std::size_t d = 0; d < D; ++d) mean[d] += static_cast<double>(p[d]) / 5000.0;
    }
    // Uniform on the sphere: the mean is the centre (coordinate s.d. ~ 0.5/sqrt(D), / sqrt(n)).
    for (std::size_t d = 0; d < D; ++d) EXPECT_NEAR(mean[d], 0.5, 0.03) << "axis " << d;
}

TYPED_TEST(generators, plane_points_have_last_coordinate_exactly_one_half) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    const auto pts = datasets::generate_points<T, D>("plane", 2000, seed);
    for (const auto& p : pts) ASSERT_EQ(p[D - 1], T(0.5)) << p;
    // ... and are spread over the other axes (a (D-1)-dimensional set, not a point).
    for (std::size_t d = 0; d + 1 < D; ++d) {
        const auto [mn, mx] = std::minmax_element(
            pts.begin(), pts.end(), [d](const auto& a, const auto& b) { return a[d] < b[d]; });
        EXPECT_GT((*mx)[d] - (*mn)[d], T(0.9)) << "axis " << d;
    }
}

TYPED_TEST(generators, line_points_are_exactly_collinear_on_the_diagonal) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    const auto pts = datasets::generate_points<T, D>("line", 2000, seed);
    T mn = T(1), mx = T(0);
    for (const auto& p : pts) {
        for (std::size_t d = 1; d < D; ++d) ASSERT_EQ(p[d], p[0]) << p;
        mn = std::min(mn, p[0]);
        mx = std::max(mx, p[0]);
    }
    EXPECT_GT(mx - mn, T(0.9));
}

TYPED_TEST(generators, lattice_points_are_distinct_grid_points_with_many_distance_ties) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    const std::size_t n = 1000;
    const std::uint64_t s = datasets::detail::lattice_side<D>(n);
    EXPECT_EQ(s, D == 2 ? 32u : 10u);  // ceil(sqrt(1000)) = 32, ceil(cbrt(1000)) = 10
    const auto pts = datasets::generate_points<T, D>("lattice", n, seed);
    for (const auto& p : pts) {
        for (std::size_t d = 0; d < D; ++d) {
            const double k = std::round(static_cast<double>(p[d]) * static_cast<double>(s));
            ASSERT_GE(k, 0.0);
            ASSERT_LT(k, static_cast<double>(s));
            ASSERT_EQ(p[d], static_cast<T>(k) / static_cast<T>(s)) << p;
        }
    }
    EXPECT_EQ(distinct_count(pts), n);
    // Ties: most squared distances from one point to the others (computed in T, as a
    // structure would) are shared with another point; in general position none are.
    std::map<T, std::size_t> multiplicity;
    for (const auto& p : pts) {
        T sum = 0;
        for (std::size_t d = 0; d < D; ++d) sum += (p[d] - pts[0][d]) * (p[d] - pts[0][d]);
        ++multiplicity[sum];
    }
    std::size_t tied = 0;
    for (const auto& [distance, count] : multiplicity) tied += count > 1 ? count : 0;
    EXPECT_GT(tied, n / 2) << "too few exact distance ties";
    // n = s^D: the whole grid, each point once.
    const std::size_t full = D == 2 ? 16 * 16 : 6 * 6 * 6;
    EXPECT_EQ(distinct_count(datasets::generate_points<T, D>("lattice", full, seed)), full);
}

TYPED_TEST(generators, duplicates_have_at_most_n_over_ten_distinct_points) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (std::size_t n : {1u, 9u, 10u, 1000u, 5000u}) {
        const auto pts = datasets::generate_points<T, D>("duplicates", n, seed);
        const std::size_t distinct = distinct_count(pts);
        EXPECT_LE(distinct, std::max<std::size_t>(1, n / 10)) << "n=" << n;
        if (n >= 1000) {
            EXPECT_GT(distinct, n / 20) << "n=" << n;  // nearly all are used
        }
    }
}

// ---------------------------------------------------------------------------- queries

TYPED_TEST(generators, queries_are_reproducible_and_independent_of_the_data) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (const auto& w : all_workloads) {
        const auto q1 = datasets::generate_queries<T, D>(w, 301, seed, 1000);
        const auto q2 = datasets::generate_queries<T, D>(w, 301, seed, 1000);
        const auto q3 = datasets::generate_queries<T, D>(w, 301, seed + 1, 1000);
        ASSERT_EQ(q1.size(), 301u) << w;
        EXPECT_EQ(q1, q2) << w;
        EXPECT_NE(q1, q3) << w;
        const auto data = datasets::generate_points<T, D>(w, 301, seed);
        EXPECT_NE(q1, data) << w << ": queries must not replay the data stream";
        EXPECT_TRUE((datasets::generate_queries<T, D>(w, 0, seed, 1000).empty())) << w;
    }
}

TYPED_TEST(generators, sphere_plane_and_line_queries_follow_the_data_distribution) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    spatial::point<T, D> centre;
    centre.coords.fill(T(0.5));
    for (const auto& q : datasets::generate_queries<T, D>("sphere", 300, seed, 0)) {
        ASSERT_NEAR(std::sqrt(distance_squared(q, centre)), 0.5, 1e-6);
    }
    for (const auto& q : datasets::generate_queries<T, D>("plane", 300, seed, 0)) {
        ASSERT_EQ(q[D - 1], T(0.5));
    }
    for (const auto& q : datasets::generate_queries<T, D>("line", 300, seed, 0)) {
        for (std::size_t d = 1; d < D; ++d) ASSERT_EQ(q[d], q[0]);
    }
}

TYPED_TEST(generators, lattice_and_duplicates_queries_hit_data_points_at_even_indices) {
    using T = typename TypeParam::scalar;
    constexpr std::size_t D = TypeParam::dim;
    for (const std::string w : {"lattice", "duplicates"}) {
        const std::size_t n = 2000;
        auto data = datasets::generate_points<T, D>(w, n, seed);
        std::sort(data.begin(), data.end(), point_less<spatial::point<T, D>>);
        const auto queries = datasets::generate_queries<T, D>(w, 101, seed, n);
        std::size_t odd_hits = 0;
        for (std::size_t i = 0; i < queries.size(); ++i) {
            const bool in_data = std::binary_search(data.begin(), data.end(), queries[i],
                                                    point_less<spatial::point<T, D>>);
            if (i % 2 == 0) {
                EXPECT_TRUE(in_data) << w << " query " << i << " " << queries[i];
            } else {
                odd_hits += in_data;
                for (std::size_t d = 0; d < D; ++d) {
                    EXPECT_GE(queries[i][d], T(0));
                    EXPECT_LT(queries[i][d], T(1));
                }
            }
        }
        EXPECT_EQ(odd_hits, 0u) << w << ": odd queries are meant to be in general position";
        EXPECT_THROW((void)(datasets::generate_queries<T, D>(w, 5, seed, 0)), std::invalid_argument);
    }
}

// ---------------------------------------------------------------------------- pinned bits

// FNV-1a over the bit patterns of all coordinates.
template <class P>
std::uint64_t fingerprint(const std::vector<P>& pts) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const auto& p : pts) {
        for (std::size_t d = 0; d < P::dimension; ++d) {
            std::uint64_t bits = 0;
            if constexpr (sizeof(p[d]) == 4) {
                bits = std::bit_cast<std::uint32_t>(p[d]);
            } else {
                bits = std::bit_cast<std::uint64_t>(p[d]);
            }
            for (int byte = 0; byte < 8; ++byte) {
                h ^= (bits >> (8 * byte)) & 0xffu;
                h *= 0x100000001b3ull;
            }
        }
    }
    return h;
}

// The output for a fixed seed is part of the interface: published results name a workload
// and a seed, and anyone must be able to regenerate the same points on any machine. These
// values were produced on x86-64 (g++ 12, with and without -march=native); a change here
// means every recorded benchmark input changed.
struct golden {
    const char* workload;
    std::uint64_t float2, float3, double2, double3;
};

// clang-format off
constexpr golden golden_fingerprints[] = {
    {"uniform",    0xc5735b2ba4316005ull, 0x3124169a4f70f6d5ull, 0xb4b7b6da24466d3eull, 0x9368a58d58ee69f2ull},
    {"clusters",   0x88d81a8f62c09c2cull, 0xd8de963e40cb53c2ull, 0x520a51b8b9fb5739ull, 0x38d53e4383f59f7eull},
    {"sphere",     0x9abb28f6c5b66dcfull, 0xa6362add05a45c41ull, 0xff6116bfaf17a7d6ull, 0x963e3b83ab7c1717ull},
    {"plane",      0x6c5ee56cdfce54f4ull, 0xbf02ea48b13857d2ull, 0x3c7d7cc620a76bfeull, 0x5c41d02b861fedeaull},
    {"line",       0x7132b8d07f6b0bf9ull, 0x4782dde4a22b0fc4ull, 0x66f8e986e3752f9dull, 0x15ede4043ba603abull},
    {"lattice",    0x94091179d1f63b9cull, 0x809abbde61dc596full, 0x747e9c4c7a644630ull, 0x936b617465e7977full},
    {"duplicates", 0xeef74cb9098478c7ull, 0xbb634936dd2b1e06ull, 0x8cc466fa1001f251ull, 0x0268d35f26f5fc7full},
    // The points of clusters, by definition.
    {"clusters_far", 0x88d81a8f62c09c2cull, 0xd8de963e40cb53c2ull, 0x520a51b8b9fb5739ull, 0x38d53e4383f59f7eull},
};
// clang-format on

TEST(generators_golden, output_bits_are_pinned_for_a_fixed_seed) {
    constexpr std::size_t n = 257;
    constexpr std::uint64_t golden_seed = 42;
    for (const auto& g : golden_fingerprints) {
        const std::uint64_t f2 = fingerprint(datasets::generate_points<float, 2>(g.workload, n, golden_seed));
        const std::uint64_t f3 = fingerprint(datasets::generate_points<float, 3>(g.workload, n, golden_seed));
        const std::uint64_t d2 = fingerprint(datasets::generate_points<double, 2>(g.workload, n, golden_seed));
        const std::uint64_t d3 = fingerprint(datasets::generate_points<double, 3>(g.workload, n, golden_seed));
        EXPECT_EQ(f2, g.float2) << g.workload << " float 2D";
        EXPECT_EQ(f3, g.float3) << g.workload << " float 3D";
        EXPECT_EQ(d2, g.double2) << g.workload << " double 2D";
        EXPECT_EQ(d3, g.double3) << g.workload << " double 3D";
        if (f2 == g.float2 && f3 == g.float3 && d2 == g.double2 && d3 == g.double3) continue;
        std::printf("    {\"%s\", 0x%016llxull, 0x%016llxull, 0x%016llxull, 0x%016llxull},\n",
                    g.workload, static_cast<unsigned long long>(f2),
                    static_cast<unsigned long long>(f3), static_cast<unsigned long long>(d2),
                    static_cast<unsigned long long>(d3));
    }
}

// ---------------------------------------------------------------------------- random parts

TEST(random_stream, derived_seeds_differ_between_streams_and_seeds) {
    std::set<std::uint64_t> seen;
    for (std::uint64_t s = 0; s < 64; ++s) {
        for (std::uint64_t stream = 0; stream < 64; ++stream) {
            seen.insert(datasets::derive_seed(s, stream));
        }
    }
    EXPECT_EQ(seen.size(), 64u * 64u);
}

TEST(random_stream, uniform_index_covers_the_range_evenly) {
    datasets::random_stream rng(7);
    std::vector<int> counts(10, 0);
    for (int i = 0; i < 100000; ++i) {
        const auto k = rng.uniform_index(10);
        ASSERT_LT(k, 10u);
        ++counts[k];
    }
    for (int c : counts) EXPECT_NEAR(c, 10000, 500);
    EXPECT_EQ(rng.uniform_index(1), 0u);
}

TEST(random_stream, gaussian_has_zero_mean_and_unit_variance) {
    datasets::random_stream rng(11);
    const int n = 200000;
    double sum = 0.0, sum2 = 0.0;
    int beyond_two_sigma = 0;
    for (int i = 0; i < n; ++i) {
        const double z = rng.gaussian();
        sum += z;
        sum2 += z * z;
        beyond_two_sigma += std::abs(z) > 2.0;
    }
    EXPECT_NEAR(sum / n, 0.0, 0.01);
    EXPECT_NEAR(sum2 / n, 1.0, 0.01);
    EXPECT_NEAR(static_cast<double>(beyond_two_sigma) / n, 0.0455, 0.002);
}

TEST(deterministic_math, log_and_sin_cos_agree_with_the_c_library) {
    datasets::random_stream rng(3);
    for (int i = 0; i < 100000; ++i) {
        const double u = 1.0 - rng.uniform01<double>();
        const double x = std::ldexp(u, -static_cast<int>(rng.uniform_index(60)));
        ASSERT_NEAR(datasets::detail::deterministic_log(x), std::log(x),
                    4e-16 * std::max(1.0, std::abs(std::log(x))))
            << x;
        const double t = rng.uniform01<double>();
        const auto sc = datasets::detail::deterministic_sin_cos_turns(t);
        const double angle = 2.0 * 3.14159265358979323846 * t;
        ASSERT_NEAR(sc.sin, std::sin(angle), 2e-15) << t;
        ASSERT_NEAR(sc.cos, std::cos(angle), 2e-15) << t;
    }
    EXPECT_EQ(datasets::detail::deterministic_log(1.0), 0.0);
    const auto zero = datasets::detail::deterministic_sin_cos_turns(0.0);
    EXPECT_EQ(zero.sin, 0.0);
    EXPECT_EQ(zero.cos, 1.0);
}

// ---------------------------------------------------------------------------- Morton order

TEST(spatially_sorted, orders_a_grid_along_the_z_curve) {
    using P = spatial::point<double, 2>;
    std::vector<P> grid;
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) grid.push_back(P{{x / 3.0, y / 3.0}});
    }
    std::vector<P> shuffled = grid;
    std::reverse(shuffled.begin(), shuffled.end());
    std::swap(shuffled[2], shuffled[9]);
    const auto sorted = datasets::spatially_sorted(shuffled);
    // Z order with x as the low bit: (0,0) (1,0) (0,1) (1,1) (2,0) (3,0) (2,1) (3,1) ...
    const int expected_xy[16][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {3, 0}, {2, 1}, {3, 1},
                                    {0, 2}, {1, 2}, {0, 3}, {1, 3}, {2, 2}, {3, 2}, {2, 3}, {3, 3}};
    ASSERT_EQ(sorted.size(), 16u);
    for (std::size_t i = 0; i < 16; ++i) {
        EXPECT_EQ(sorted[i], (P{{expected_xy[i][0] / 3.0, expected_xy[i][1] / 3.0}})) << i;
    }
}

TEST(spatially_sorted, is_a_permutation_that_makes_consecutive_points_close) {
    const auto pts = datasets::generate_points<float, 3>("uniform", 20000, seed);
    const auto sorted = datasets::spatially_sorted(pts);
    ASSERT_EQ(sorted.size(), pts.size());
    auto a = pts, b = sorted;
    std::sort(a.begin(), a.end(), point_less<spatial::point<float, 3>>);
    std::sort(b.begin(), b.end(), point_less<spatial::point<float, 3>>);
    EXPECT_EQ(a, b);
    const auto mean_step = [](const auto& v) {
        double sum = 0.0;
        for (std::size_t i = 1; i < v.size(); ++i) sum += std::sqrt(distance_squared(v[i - 1], v[i]));
        return sum / static_cast<double>(v.size() - 1);
    };
    EXPECT_LT(mean_step(sorted), 0.1 * mean_step(pts));
    EXPECT_EQ(datasets::spatially_sorted(sorted), sorted) << "sorting is idempotent";
}

TEST(spatially_sorted, handles_degenerate_sets_and_rejects_non_finite_coordinates) {
    using P = spatial::point<double, 3>;
    EXPECT_TRUE(datasets::spatially_sorted(std::vector<P>{}).empty());
    const std::vector<P> same(5, P{{0.25, 0.25, 0.25}});
    EXPECT_EQ(datasets::spatially_sorted(same), same);
    const auto line = datasets::generate_points<double, 3>("line", 100, seed);
    const auto sorted_line = datasets::spatially_sorted(line);
    EXPECT_TRUE(std::is_sorted(sorted_line.begin(), sorted_line.end(),
                               [](const P& a, const P& b) { return a[0] < b[0]; }));
    std::vector<P> bad{P{{0, 0, 0}}, P{{1, std::numeric_limits<double>::quiet_NaN(), 0}}};
    try {
        (void)datasets::spatially_sorted(bad);
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("point 1"), std::string::npos) << e.what();
    }
}

// ---------------------------------------------------------------------------- loaders

const fs::path samples = SPATIAL_DATASETS_SAMPLES_DIR;

// A file in the temp directory, removed when the test ends.
class temp_file {
public:
    temp_file(const std::string& name, std::string_view content) {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() /
                ("datasets_test_" + std::string(info->name()) + "_" + name);
        std::ofstream out(path_, std::ios::binary);
        out << content;
    }
    ~temp_file() {
        std::error_code ec;
        fs::remove(path_, ec);
    }
    temp_file(const temp_file&) = delete;
    temp_file& operator=(const temp_file&) = delete;
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

// The load_error message of loading `file`, or "" if it loaded.
std::string load_error_of(const fs::path& file) {
    try {
        (void)datasets::load_point_set(file);
    } catch (const datasets::load_error& e) {
        return e.what();
    }
    return "";
}

#define EXPECT_CONTAINS(haystack, needle) \
    EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "message: " << (haystack)

// The load error of a temporary file `name` holding `content` names every fragment.
void expect_load_error(const std::string& name, std::string_view content,
                       std::initializer_list<std::string_view> fragments) {
    SCOPED_TRACE(name);
    const temp_file f(name, content);
    const std::string message = load_error_of(f.path());
    for (const auto fragment : fragments) EXPECT_CONTAINS(message, fragment);
}

TEST(load_point_set, reads_the_committed_xyz_sample_ignoring_normals_and_comments) {
    const auto pts = datasets::load_point_set(samples / "tetrahedron_normals.xyz");
    ASSERT_EQ(pts.size(), 4u);
    EXPECT_EQ(pts[0], (spatial::point<double, 3>{{0.0, 0.0, 1.0}}));
    EXPECT_EQ(pts[3], (spatial::point<double, 3>{{-0.4714045208, -0.8164965809, -0.3333333333}}));
}

TEST(load_point_set, reads_the_committed_off_and_obj_samples) {
    const auto off = datasets::load_point_set(samples / "square_pyramid.off");
    ASSERT_EQ(off.size(), 5u);
    EXPECT_EQ(off[4], (spatial::point<double, 3>{{0.5, 0.5, 1.0}}));
    const auto obj = datasets::load_point_set(samples / "two_triangles.obj");
    ASSERT_EQ(obj.size(), 4u);
    EXPECT_EQ(obj[2], (spatial::point<double, 3>{{1.0, 1.0, 0.0}}));
}

TEST(load_point_set, reads_the_committed_ascii_and_binary_ply_samples) {
    if (!datasets::can_load_ply()) {
        EXPECT_CONTAINS(load_error_of(samples / "octahedron.ply"), "SPATIAL_WITH_CGAL");
        GTEST_SKIP() << "built without CGAL: PLY loading is off";
    }
    const auto octahedron = datasets::load_point_set(samples / "octahedron.ply");
    ASSERT_EQ(octahedron.size(), 6u);
    EXPECT_EQ(octahedron[5], (spatial::point<double, 3>{{0.0, 0.0, -1.0}}));
    auto cube = datasets::load_point_set(samples / "cube_corners_binary.ply");
    ASSERT_EQ(cube.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) {
        const spatial::point<double, 3> corner{
            {static_cast<double>(i & 1), static_cast<double>((i >> 1) & 1),
             static_cast<double>((i >> 2) & 1)}};
        EXPECT_EQ(cube[i], corner) << i;
    }
}

TEST(load_point_set, malformed_xyz_line_names_file_line_and_expectation) {
    const temp_file f("short_line.xyz",
                      "# a comment\n"
                      "0 0 0\n"
                      "1 2 3 0 0 1\n"
                      "\n"
                      "4 5\n"
                      "6 7 8\n");
    const std::string message = load_error_of(f.path());
    EXPECT_CONTAINS(message, f.path().string());
    EXPECT_CONTAINS(message, "line 5");
    EXPECT_CONTAINS(message, "expected at least 3 numbers (x y z)");
    EXPECT_CONTAINS(message, "found 2");
}

TEST(load_point_set, non_numeric_token_names_the_line_and_the_token) {
    expect_load_error("word.xyz", "0 0 0\r\n1 abc 3\r\n", {"line 2", "for y", "\"abc\""});
}

TEST(load_point_set, nan_and_infinite_coordinates_are_rejected_with_the_line) {
    expect_load_error("nan.xyz", "0 0 0\n1 1 1\nnan 1 2\n", {"line 3", "x = nan is not finite"});
    expect_load_error("inf.pwn", "0 0 0 0 0 1\n1 1 -inf 0 0 1\n", {"line 2", "z = -inf is not finite"});
}

TEST(load_point_set, accepts_crlf_commas_plus_signs_and_a_count_header) {
    const temp_file f("counted.xyzn", "3\r\n+1.5,2,3\r\n4 5 6e-001\r\n  7\t8\t9 extra words\r\n");
    const auto pts = datasets::load_point_set(f.path());
    ASSERT_EQ(pts.size(), 3u);
    EXPECT_EQ(pts[0], (spatial::point<double, 3>{{1.5, 2.0, 3.0}}));
    EXPECT_EQ(pts[1], (spatial::point<double, 3>{{4.0, 5.0, 0.6}}));
    EXPECT_EQ(pts[2], (spatial::point<double, 3>{{7.0, 8.0, 9.0}}));
}

TEST(load_point_set, empty_missing_and_unknown_files_are_rejected) {
    expect_load_error("empty.xyz", "", {"contains no points"});
    expect_load_error("only_comments.xyz", "# nothing\n\n   \n# here\n", {"contains no points"});
    EXPECT_CONTAINS(load_error_of(samples / "does_not_exist.xyz"), "cannot open");

    const temp_file txt("points.txt", "0 0 0\n");
    const std::string message = load_error_of(txt.path());
    EXPECT_CONTAINS(message, "unsupported extension \".txt\"");
    for (const auto ext : datasets::supported_point_set_extensions()) EXPECT_CONTAINS(message, std::string(ext));
    EXPECT_CONTAINS(load_error_of(samples / "README"), "(none)");
}

TEST(load_point_set, extension_match_is_case_insensitive) {
    const temp_file f("upper.XYZ", "1 2 3\n");
    EXPECT_EQ(datasets::load_point_set(f.path()).size(), 1u);
}

TEST(load_point_set, off_errors_name_the_line) {
    expect_load_error("bad_vertex.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 x 0\n3 0 1 2\n", {"line 5", "vertex line"});
    expect_load_error("truncated.off", "OFF 4 1 0\n0 0 0\n1 0 0\n", {"declares 4 vertices", "ends after 2"});
    expect_load_error("homogeneous.off", "4OFF\n1 0 0\n0 0 0 1\n", {"unsupported OFF variant \"4OFF\""});
    expect_load_error("binary.off", "OFF BINARY\n", {"binary OFF is not supported"});
    expect_load_error("no_vertices.off", "OFF\n0 0 0\n", {"contains no points"});
    expect_load_error("not_off.off", "PLY\n1 0 0\n", {"line 1"});

    // Colour OFF with the counts on the header line, and a headerless file.
    const temp_file coff("colour.off", "COFF 2 0 0\n0 0 0 255 0 0 255\n1 1 1 0 255 0 255\n");
    EXPECT_EQ(datasets::load_point_set(coff.path()).size(), 2u);
    const temp_file headerless("headerless.off", "2 0 0\n0 0 0\n1 1 1\n");
    EXPECT_EQ(datasets::load_point_set(headerless.path()).size(), 2u);
}

TEST(load_point_set, obj_errors_name_the_line) {
    expect_load_error("bad.obj", "v 0 0 0\nvn 0 0 1\nv 1 inf 0\n", {"line 3", "y = inf is not finite"});
}

TEST(load_point_set, corrupt_ply_names_the_file_and_the_problem) {
    const temp_file no_end("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n");
    std::string message = load_error_of(no_end.path());
    EXPECT_CONTAINS(message, no_end.path().string());
    if (!datasets::can_load_ply()) {
        EXPECT_CONTAINS(message, "SPATIAL_WITH_CGAL");
        GTEST_SKIP() << "built without CGAL: PLY loading is off";
    }
    EXPECT_CONTAINS(message, "no end_header");

    // CGAL alone would return (x, y, 0) points here.
    const temp_file no_z("no_z.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                     "property float y\nend_header\n1 2\n");
    EXPECT_CONTAINS(load_error_of(no_z.path()), "no property z");

    const temp_file truncated("truncated.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"
                                               "property float x\nproperty float y\nproperty float z\n"
                                               "end_header\n1 2 3\n");
    EXPECT_CONTAINS(load_error_of(truncated.path()), "the file ends in row 1 of element vertex, property x");

    // Binary PLY cannot name a line, so a NaN is reported by vertex index.
    std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
                         "property double y\nproperty double z\nend_header\n";
    const double values[6] = {0.0, 1.0, 2.0, 3.0, std::numeric_limits<double>::quiet_NaN(), 5.0};
    static_assert(std::endian::native == std::endian::little, "the sample below is little-endian");
    binary.append(reinterpret_cast<const char*>(values), sizeof values);
    const temp_file nan_binary("nan_binary.ply", binary);
    message = load_error_of(nan_binary.path());
    EXPECT_CONTAINS(message, "vertex 1 has a non-finite coordinate");
}

// Found by fuzzing (fuzz/point_set, docs/fuzzing.md): headers that CGAL's PLY reader accepts
// and then dereferences a null pointer on (in release builds, where CGAL's assertions are
// off): a property line before any element line (it is added to the last element of an empty
// list), and a vertex coordinate that is neither float nor double (its value is read through a
// failed dynamic_cast). Each must be a load_error naming the problem, not a crash.
TEST(load_point_set, ply_headers_cgal_cannot_read_are_errors_not_crashes) {
    if (!datasets::can_load_ply()) GTEST_SKIP() << "built without CGAL: PLY loading is off";
    expect_load_error("property_first.ply",
                      "ply\nformat ascii 1.0\nproperty double x\nelement vertex 1\nproperty double x\n"
                      "property double y\nproperty double z\nend_header\n1 2 3\n",
                      {"line 3", "before any element"});
    expect_load_error("int_x.ply",
                      "ply\nformat ascii 1.0\nelement vertex 1\nproperty int x\nproperty double y\n"
                      "property double z\nend_header\n1 2 3\n",
                      {"line 4", "property x", "float or double"});
    expect_load_error("list_z.ply",
                      "ply\nformat ascii 1.0\nelement vertices 1\nproperty double x\nproperty double y\n"
                      "property list uchar float z\nend_header\n1 2 1 3\n",
                      {"line 6", "property z", "float or double"});
}

// datasets/ply_check.hpp on its own: every rule CGAL's reader needs, the line it names, and
// the vertex count summed over the vertex elements ("vertex" and "vertices", as CGAL reads both).
TEST(ply_header, rejects_what_cgals_reader_cannot_read_and_sums_the_vertex_elements) {
    const auto check = [](const std::string& text, datasets::ply_use use = datasets::ply_use::mesh) {
        std::istringstream in(text);
        return datasets::check_ply_header(in, use);
    };
    const std::string head = "ply\nformat ascii 1.0\n", xyz = "property float x\nproperty float y\nproperty double z\n";
    const auto fine = check(head + "comment two vertex elements\nelement vertex 3\n" + xyz + "element vertices 2\n" + xyz +
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n");
    EXPECT_EQ(fine.problem, "");
    EXPECT_EQ(fine.vertex_count, 5u);
    const auto expect_problem = [&](const std::string& text, std::size_t line, std::string_view fragment,
                                    datasets::ply_use use = datasets::ply_use::mesh) {
        const auto r = check(text, use);
        EXPECT_EQ(r.line, line) << text;
        EXPECT_CONTAINS(r.problem, fragment);
    };
    expect_problem("plx\n", 1, "magic line");
    expect_problem("ply\nformat binary_middle_endian 1.0\n", 2, "format ascii");
    expect_problem(head + "element vertex three\n", 3, "element <name> <count>");
    expect_problem(head + "element vertex 1\n" + xyz + "property int128 w\nend_header\n", 7, "unknown property type");
    expect_problem(head + "element face 1\nproperty list float int vertex_indices\n", 4, "unknown list types");
    expect_problem(head + "element vertex 1\nproperty float x\nproperty float y\nend_header\n", 3, "no property z");
    expect_problem(head + "element face 1\nend_header\n", 0, "no vertex element");
    expect_problem(head + "element vertex 1\n" + xyz, 0, "no end_header");
    // Meshes only: a halfedge's source and target must be uint, colours all uchar or ignored.
    const std::string halfedge = head + "element vertex 1\n" + xyz + "element halfedge 1\nproperty int source\nend_header\n";
    expect_problem(halfedge, 8, "source of the halfedge element");
    EXPECT_EQ(check(halfedge, datasets::ply_use::points).problem, "");
    const std::string float_colours = head + "element vertex 1\n" + xyz +
                                      "property float red\nproperty float green\nproperty float blue\nend_header\n";
    EXPECT_EQ(check(float_colours).problem, "") << "colours CGAL ignores (not all uchar) are fine";
    expect_problem(head + "element vertex 1\n" + xyz + "property uchar r\nproperty uchar g\nproperty uchar b\n" +
                       "property uchar red\nproperty short green\nproperty uchar blue\nend_header\n",
                   11, "colour property green");
}

// Found by fuzzing (fuzz/point_set, docs/fuzzing.md): CGAL's PLY reader resizes a list to its
// declared count before reading its items (PLY_read_typed_list_with_typed_size::get), so a
// binary file of a few hundred bytes whose face list declares 2^31 - 1 indices of a 32-bit count
// type made the loader allocate 8 GB (libFuzzer: "out-of-memory (malloc(7650410496))"); a
// release build got a bad_alloc at best, the OOM killer at worst. datasets::check_ply walks the
// body first, each list count against the bytes left.
TEST(load_point_set, a_ply_list_longer_than_the_file_is_an_error_before_any_allocation) {
    if (!datasets::can_load_ply()) GTEST_SKIP() << "built without CGAL: PLY loading is off";
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\n"
                      "property double y\nproperty double z\nelement face 1\n"
                      "property list uint int vertex_indices\nend_header\n";
    const double xyz[3] = {0, 1, 2};
    const std::uint32_t count = 0x7fffffff;
    static_assert(std::endian::native == std::endian::little, "the sample below is little-endian");
    ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    ply.append(reinterpret_cast<const char*>(&count), sizeof count);
    expect_load_error("long_list.ply", ply, {"row 0 of element face, property vertex_indices", "2147483647 items"});
}

// datasets::check_ply on its own: the body's declared sizes, binary (both byte orders, fixed
// rows and lists, signed counts) and ASCII (the line of a list count), against what follows.
TEST(ply_check, the_body_holds_what_the_header_declares) {
    const auto check = [](const std::string& text) {
        std::istringstream in(text);
        return datasets::check_ply(in, datasets::ply_use::mesh);
    };
    const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
    const auto binary = [&](std::string_view format, std::string_view count_type, std::uint32_t vertices,
                            std::string_view body) {
        return "ply\nformat " + std::string(format) + " 1.0\nelement vertex " + std::to_string(vertices) + "\n" + xyz +
               "element face 1\nproperty list " + std::string(count_type) + " int vertex_indices\nend_header\n" +
               std::string(body);
    };
    const std::string vertex(12, '\0');  // one vertex: three floats
    const std::string three = vertex + vertex + vertex;
    // A triangle, little and big endian; bytes after the last element are ignored.
    EXPECT_EQ(check(binary("binary_little_endian", "uchar", 3, three + '\3' + std::string(12, '\0'))).problem, "");
    EXPECT_EQ(check(binary("binary_big_endian", "ushort", 3, three + std::string("\0\3", 2) + std::string(12, '\0') + "tail"))
                  .problem,
              "");
    const auto expect_problem = [&](const std::string& text, std::size_t line, std::string_view fragment) {
        const auto r = check(text);
        EXPECT_EQ(r.line, line) << r.problem;
        EXPECT_CONTAINS(r.problem, fragment);
    };
    expect_problem(binary("binary_little_endian", "uchar", 4, three), 0, "element vertex declares 4 rows of 12 bytes but 36");
    expect_problem(binary("binary_little_endian", "uchar", 3, three), 0, "the file ends in row 0 of element face");
    expect_problem(binary("binary_little_endian", "uchar", 3, three + '\4' + std::string(12, '\0')), 0,
                   "the list declares 4 items of 4 bytes but 12 bytes follow");
    expect_problem(binary("binary_big_endian", "ushort", 3, three + std::string("\1\0", 2) + std::string(12, '\0')), 0,
                   "the list declares 256 items");
    expect_problem(binary("binary_little_endian", "int", 3, three + std::string("\xff\xff\xff\xff", 4)), 0,
                   "a negative list count");

    const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                              "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    EXPECT_EQ(check(ascii + "3 0 1 2\n3 2 1 0\n").problem, "");
    EXPECT_EQ(check(ascii + "3 0 1\n2\n3 2 1 0 trailing words\n").problem, "") << "words, not lines, as CGAL reads them";
    expect_problem(ascii + "3 0 1 2\n4 2 1 0\n", 14, "row 1 of element face, property vertex_indices: the list declares 4 items but the file ends after 3");
    expect_problem(ascii + "-1 0 1 2\n", 13, "a negative list count -1");
    expect_problem(ascii + "three 0 1 2\n", 13, "expected a list count but found \"three\"");
    expect_problem(ascii + "3 0 1 2\n", 0, "the file ends in row 1 of element face");
    expect_problem("ply\nformat ascii 1.0\nelement vertex 2\n" + xyz + "end_header\n1 2 3\n4 5\n", 0,
                   "the file ends in row 1 of element vertex, property z");
}

// The files datasets/fetch_real_data.sh places (see datasets/README.md), with their counts.
TEST(load_point_set, fetched_real_data_loads_with_the_documented_counts) {
    const fs::path real = SPATIAL_DATASETS_REAL_DIR;
    if (!fs::is_directory(real)) GTEST_SKIP() << "run datasets/fetch_real_data.sh first";
    const std::pair<const char*, std::size_t> expected[] = {
        {"ChineseDragon-10kv.off", 10000},
        {"armadillo.off", 26002},
        {"b9_training.ply", 22300},
        {"ball.ply", 31374},
        {"blobby.xyz", 3288},
        {"building.ply", 100000},
        {"bunny.obj", 34835},
        {"bunny00.off", 37706},
        {"circles.ply", 1101},
        {"cube.pwn", 50000},
        {"fandisk_large.off", 15843},
        {"hippo1.ply", 6104},
        {"kitten.off", 5210},
        {"kitten.xyz", 5210},
        {"oneK.xyz", 1000},
        {"oni.pwn", 1435},
        {"point_set_3.xyz", 8075},
        {"poste_france.xyz", 9031},
        {"radar.xyz", 20950},
        {"refined_elephant.off", 44460},
        {"sphere_20k.xyz", 21000},
        {"spheres.ply", 5969},
    };
    std::size_t checked = 0;
    for (const auto& [name, count] : expected) {
        const fs::path file = real / name;
        if (!fs::exists(file)) continue;
        if (file.extension() == ".ply" && !datasets::can_load_ply()) continue;
        const auto pts = datasets::load_point_set(file);
        EXPECT_EQ(pts.size(), count) << name;
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << "no fetched files in " << real;
}

}  // namespace
