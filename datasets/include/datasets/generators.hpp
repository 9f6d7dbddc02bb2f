#pragma once
// Seeded point workloads: the synthetic data sets every benchmark and test runs on.
//
// All workloads live in (roughly) the unit cube [0, 1]^D so the harness can choose query
// radii once for all of them. For the same (workload, n, seed, T, D) the output is
// bit-identical on every IEEE-754 machine and standard library (see random.hpp for how),
// provided the code is not compiled with -ffast-math.
//
//   uniform     uniform in [0, 1)^D.
//   clusters    16 isotropic Gaussian clusters, sigma 0.02, centres uniform in [0.1, 0.9)^D;
//               each point picks a cluster uniformly. Not clamped: Box–Muller from 53-bit
//               uniforms never exceeds 8.58 sigma, so points stay in [-0.072, 1.072]^D.
//   sphere      uniform on the sphere (circle in 2D) of centre (0.5, ..., 0.5), radius 0.5
//               (normalised Gaussian vectors, Muller 1959).
//   plane       uniform on the hyperplane x[D-1] = 0.5 exactly (a line in 2D): a degenerate
//               (D-1)-dimensional set.
//   line        uniform along the main diagonal: every coordinate of a point equals the same
//               t in [0, 1), so all points are exactly collinear.
//   lattice     points of the grid {0, 1, ..., s-1} / s in every axis, s = ceil(n^(1/D)),
//               shuffled, the first n kept: many equal distances. Ties are exact in real
//               arithmetic; in T most (not all) of them are also bit-equal, because k/s
//               rounds unless s is a power of two, so validators should treat near-equal
//               distances as ties.
//   duplicates  n points drawn with replacement from max(1, n/10) distinct uniform points:
//               exact duplicates.
//   clusters_far  the points of clusters (bit-identical for the same n and seed), queried from
//               everywhere: its queries are uniform in [0, 1)^D, so most lie in the empty space
//               between the clusters, far from every point. A search must then prove that
//               whole clusters hold nothing nearer, which a tree bounding its cells by split
//               planes alone cannot do cheaply (kd-tree.md, "Pruning by the children's key
//               ranges").
//
// Seeds: each (workload, purpose) pair reads its own stream derived from the user seed with
// splitmix64, so the data, the queries and the cluster centres are independent.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "datasets/morton.hpp"  // spatially_sorted, the ordering used with these workloads
#include "datasets/random.hpp"
#include "spatial/core/point.hpp"

namespace datasets {

// Appended only: the value is part of every derived seed (stream_seed).
enum class point_workload : unsigned { uniform, clusters, sphere, plane, line, lattice, duplicates, clusters_far };

namespace detail {
inline constexpr std::array<std::string_view, 8> point_workload_name_table{
    "uniform", "clusters", "sphere", "plane", "line", "lattice", "duplicates", "clusters_far"};
}  // namespace detail

// The workload names accepted by generate_points/generate_queries, in a fixed order.
inline std::span<const std::string_view> point_workload_names() noexcept {
    return detail::point_workload_name_table;
}

inline std::string_view to_string(point_workload w) noexcept {
    return detail::point_workload_name_table[static_cast<unsigned>(w)];
}

// Throws std::invalid_argument naming the unknown workload and listing the valid ones.
inline point_workload parse_point_workload(std::string_view name) {
    const auto& table = detail::point_workload_name_table;
    for (std::size_t i = 0; i < table.size(); ++i) {
        if (table[i] == name) return static_cast<point_workload>(i);
    }
    std::string message = "unknown point workload \"" + std::string(name) + "\"; valid workloads: ";
    for (std::size_t i = 0; i < table.size(); ++i) {
        message += (i ? ", " : "");
        message += table[i];
    }
    throw std::invalid_argument(message);
}

namespace detail {

// What a stream is used for; part of the derived seed, so it must never be renumbered
// (that would change every generated data set).
enum class stream_purpose : std::uint64_t { data = 1, queries = 2, cluster_centres = 3 };

inline std::uint64_t stream_seed(std::uint64_t seed, point_workload w, stream_purpose purpose) {
    return derive_seed(seed, ((static_cast<std::uint64_t>(w) + 1) << 8) |
                                 static_cast<std::uint64_t>(purpose));
}

inline constexpr std::size_t cluster_count = 16;
inline constexpr double cluster_sigma = 0.02;

template <class T, std::size_t D>
spatial::point<T, D> uniform_point(random_stream& rng) {
    spatial::point<T, D> p;
    for (std::size_t d = 0; d < D; ++d) p[d] = rng.uniform01<T>();
    return p;
}

// Centres depend only on the seed (not on n), so data and queries share them.
template <std::size_t D>
std::array<std::array<double, D>, cluster_count> cluster_centres(std::uint64_t seed) {
    random_stream rng(stream_seed(seed, point_workload::clusters, stream_purpose::cluster_centres));
    std::array<std::array<double, D>, cluster_count> centres{};
    for (auto& c : centres) {
        for (auto& x : c) x = std::fma(0.8, rng.uniform01<double>(), 0.1);
    }
    return centres;
}

template <class T, std::size_t D>
spatial::point<T, D> cluster_point(random_stream& rng,
                                   const std::array<std::array<double, D>, cluster_count>& centres) {
    const auto& c = centres[rng.uniform_index(cluster_count)];
    spatial::point<T, D> p;
    for (std::size_t d = 0; d < D; ++d) {
        p[d] = static_cast<T>(std::fma(cluster_sigma, rng.gaussian(), c[d]));
    }
    return p;
}

template <class T, std::size_t D>
spatial::point<T, D> sphere_point(random_stream& rng) {
    double length = 0.0;
    const std::array<double, D> g = nonzero_gaussian_vector<D>(rng, length);
    spatial::point<T, D> p;
    for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(std::fma(0.5, g[d] / length, 0.5));
    return p;
}

template <class T, std::size_t D>
spatial::point<T, D> plane_point(random_stream& rng) {
    spatial::point<T, D> p;
    for (std::size_t d = 0; d + 1 < D; ++d) p[d] = rng.uniform01<T>();
    p[D - 1] = T(0.5);
    return p;
}

template <class T, std::size_t D>
spatial::point<T, D> line_point(random_stream& rng) {
    const T t = rng.uniform01<T>();
    spatial::point<T, D> p;
    p.coords.fill(t);
    return p;
}

// Smallest s with s^D >= n, in integers (a floating-point root could be off by one).
template <std::size_t D>
std::uint64_t lattice_side(std::size_t n) {
    const auto reaches = [n](std::uint64_t s) {
        std::uint64_t power = 1;
        for (std::size_t d = 0; d < D; ++d) {
            if (power > std::numeric_limits<std::uint64_t>::max() / s) return true;
            power *= s;
        }
        return power >= n;
    };
    std::uint64_t s = 1;
    while (!reaches(s)) ++s;  // O(n^(1/D)) steps
    return s;
}

template <class T, std::size_t D>
std::vector<spatial::point<T, D>> lattice_points(random_stream& rng, std::size_t n) {
    if (n == 0) return {};
    const std::uint64_t s = lattice_side<D>(n);
    std::uint64_t total = 1;
    for (std::size_t d = 0; d < D; ++d) total *= s;
    // Partial Fisher–Yates: the first n slots of a uniform random permutation of all s^D
    // lattice indices. O(s^D) memory (at most about 2^D n for small n, ~n for large n).
    std::vector<std::uint64_t> index(total);
    std::iota(index.begin(), index.end(), std::uint64_t{0});
    for (std::size_t i = 0; i < n; ++i) {
        std::swap(index[i], index[i + rng.uniform_index(total - i)]);
    }
    const T side = static_cast<T>(s);
    std::vector<spatial::point<T, D>> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t rest = index[i];
        for (std::size_t d = 0; d < D; ++d) {
            out[i][d] = static_cast<T>(rest % s) / side;
            rest /= s;
        }
    }
    return out;
}

template <class T, std::size_t D>
std::vector<spatial::point<T, D>> duplicate_points(random_stream& rng, std::size_t n) {
    if (n == 0) return {};
    const std::size_t distinct_count = std::max<std::size_t>(1, n / 10);
    std::vector<spatial::point<T, D>> distinct(distinct_count);
    for (auto& p : distinct) p = uniform_point<T, D>(rng);
    std::vector<spatial::point<T, D>> out(n);
    for (auto& p : out) p = distinct[rng.uniform_index(distinct_count)];
    return out;
}

template <class T, std::size_t D, class Make>
std::vector<spatial::point<T, D>> repeat(std::size_t n, Make&& make) {
    std::vector<spatial::point<T, D>> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) out.push_back(make());
    return out;
}

// Points of workload w from an already seeded stream. Cluster centres come from `seed`.
template <class T, std::size_t D>
std::vector<spatial::point<T, D>> draw(point_workload w, std::size_t n, random_stream& rng,
                                       std::uint64_t seed) {
    switch (w) {
        case point_workload::uniform:
            return repeat<T, D>(n, [&] { return uniform_point<T, D>(rng); });
        case point_workload::clusters:
        case point_workload::clusters_far: {
            const auto centres = cluster_centres<D>(seed);
            return repeat<T, D>(n, [&] { return cluster_point<T, D>(rng, centres); });
        }
        case point_workload::sphere:
            return repeat<T, D>(n, [&] { return sphere_point<T, D>(rng); });
        case point_workload::plane:
            return repeat<T, D>(n, [&] { return plane_point<T, D>(rng); });
        case point_workload::line:
            return repeat<T, D>(n, [&] { return line_point<T, D>(rng); });
        case point_workload::lattice:
            return lattice_points<T, D>(rng, n);
        case point_workload::duplicates:
            return duplicate_points<T, D>(rng, n);
    }
    throw std::logic_error("datasets::detail::draw: unhandled workload");
}

}  // namespace detail

// n points of the named workload (see the table at the top of this file). O(n) time and
// memory, except lattice: O(s^D) with s^D < (n^(1/D) + 1)^D.
// Throws std::invalid_argument for an unknown workload name.
template <class T, std::size_t D>
std::vector<spatial::point<T, D>> generate_points(std::string_view workload, std::size_t n,
                                                  std::uint64_t seed) {
    static_assert(D >= 2, "generate_points: the workloads are defined for D >= 2");
    const point_workload w = parse_point_workload(workload);
    // clusters_far shares the clusters' points: it reads their stream.
    const point_workload data_stream = w == point_workload::clusters_far ? point_workload::clusters : w;
    random_stream rng(detail::stream_seed(seed, data_stream, detail::stream_purpose::data));
    return detail::draw<T, D>(w, n, rng, seed);
}

// `count` query points for data made by generate_points<T, D>(workload, data_n, seed).
//
//   uniform, clusters, sphere, plane, line: independent draws from the data's distribution
//     (a separate derived stream; clusters reuse the data's 16 centres).
//   clusters_far: uniform in [0, 1)^D (its own stream), whatever the data.
//   lattice, duplicates: queries with EVEN index are exact copies of data points (chosen
//     uniformly from the data regenerated from (data_n, seed)), so a query sits at distance
//     0 from one or more points and at tied distances from its lattice neighbours; queries
//     with ODD index are uniform in [0, 1)^D, in general position.
//
// data_n matters only for lattice and duplicates (the lattice side and the distinct set
// depend on it; those two cost O(data_n) extra time and memory to regenerate the data);
// for them data_n == 0 with count > 0 throws std::invalid_argument.
// Throws std::invalid_argument for an unknown workload name.
template <class T, std::size_t D>
std::vector<spatial::point<T, D>> generate_queries(std::string_view workload, std::size_t count,
                                                   std::uint64_t seed, std::size_t data_n) {
    static_assert(D >= 2, "generate_queries: the workloads are defined for D >= 2");
    const point_workload w = parse_point_workload(workload);
    random_stream rng(detail::stream_seed(seed, w, detail::stream_purpose::queries));
    if (w == point_workload::clusters_far) return detail::draw<T, D>(point_workload::uniform, count, rng, seed);
    if (w != point_workload::lattice && w != point_workload::duplicates) {
        return detail::draw<T, D>(w, count, rng, seed);
    }
    if (count == 0) return {};
    if (data_n == 0) {
        throw std::invalid_argument("generate_queries(\"" + std::string(workload) +
                                    "\"): data_n must be the n the data was generated with "
                                    "(half of the queries are copies of data points)");
    }
    const auto data = generate_points<T, D>(workload, data_n, seed);
    std::vector<spatial::point<T, D>> out;
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        out.push_back(i % 2 == 0 ? data[rng.uniform_index(data.size())]
                                 : detail::uniform_point<T, D>(rng));
    }
    return out;
}

}  // namespace datasets
