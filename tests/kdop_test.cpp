// spatial::kdop<T, D, K>: every supported K in 2D (4, 8, 16) and 3D (6, 14, 18, 26), float and
// double. References written here, independent of the header:
//   * an EXACT integer reference: on k-DOPs whose slab values lie on a dyadic grid, vertices
//     by exact rational plane intersection, overlap by the separating-axis test over face
//     normals and all cross products of edge-direction candidates (n_i x n_j) x (n_k x n_l)
//     on the exact vertex sets, and by exact non-emptiness of A ∩ B;
//   * Monte Carlo volume and Cauchy's mean-projection formula for the surface area;
//   * the aabb for K = 6 / 4.

#include "spatial/bv/kdop.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "spatial/bv/aabb.hpp"
#include "bv_test_support.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

template <std::size_t K>
using k_tag = std::integral_constant<std::size_t, K>;

// Calls f(k_tag<K>{}) for every supported K of dimension D, with
// "K=<K>" in the trace of any failure inside f.
template <std::size_t D, class F>
void for_each_k(F&& f) {
    auto traced = [&](auto kc) {
        SCOPED_TRACE("K=" + std::to_string(decltype(kc)::value));
        f(kc);
    };
    if constexpr (D == 2) {
        traced(std::integral_constant<std::size_t, 4>{});
        traced(std::integral_constant<std::size_t, 8>{});
        traced(std::integral_constant<std::size_t, 16>{});
    } else {
        traced(std::integral_constant<std::size_t, 6>{});
        traced(std::integral_constant<std::size_t, 14>{});
        traced(std::integral_constant<std::size_t, 18>{});
        traced(std::integral_constant<std::size_t, 26>{});
    }
}

using rng_t = std::mt19937_64;
using spatial_test::unit;
inline double gauss(rng_t& r) {
    double s = 0;
    for (int i = 0; i < 12; ++i) s += unit(r);
    return s - 6;
}

// A random rotation matrix (row-major).
template <std::size_t D>
std::array<std::array<double, D>, D> random_rotation(rng_t& r) {
    return spatial_test::random_rotation<D>(r, gauss);
}

// Named hard-case sets (as in bv_test) plus near-duplicates and a rotated blob.
template <class T, std::size_t D>
spatial_test::named_point_sets<T, D> hard_sets(std::uint64_t seed) {
    rng_t rng(seed);
    auto out = spatial_test::basic_hard_sets<T, D>(500, [&] { return unit(rng); });
    auto make = [&](const std::string& name, std::size_t n, auto f) {
        out.push_back({name, spatial_test::points_from<T, D>(n, f)});
    };
    make("near duplicates", 200, [&](std::size_t i, std::size_t d) {
        return static_cast<double>(i % 3) + static_cast<double>(d) + 1e-13 * unit(rng);
    });
    make("negative zero and tiny", 50, [&](std::size_t i, std::size_t) { return i % 2 ? -0.0 : 1e-300 * unit(rng); });
    {
        const auto rot = random_rotation<D>(rng);
        std::vector<point<T, D>> v;
        for (int i = 0; i < 300; ++i) {
            std::array<double, D> x;
            for (std::size_t d = 0; d < D; ++d) x[d] = gauss(rng) * (d == 0 ? 3 : 0.5);
            point<T, D> p;
            for (std::size_t r = 0; r < D; ++r) {
                double s = 7;
                for (std::size_t c = 0; c < D; ++c) s += rot[r][c] * x[c];
                p[r] = static_cast<T>(s);
            }
            v.push_back(p);
        }
        out.push_back({"rotated blob", v});
    }
    return out;
}

// Calls f(name, s, box) for every set of hard_sets(seed) (its name traced): s its points, box
// their aabb.
template <class T, std::size_t D, class F>
void for_each_hard_set(std::uint64_t seed, F&& f) {
    for (const auto& [name, pts] : hard_sets<T, D>(seed)) {
        SCOPED_TRACE(name);
        const std::span<const point<T, D>> s(pts);
        f(name, s, aabb<T, D>::fit(s));
    }
}

// ------------------------------------------------------------------------------------------
// The exact integer reference. Slab values are integers (units of 1 / grid); a vertex is
// X / det with integer X and det > 0.

template <std::size_t D>
struct rvertex {
    std::array<long long, D> x{};
    long long det = 1;
};

template <std::size_t D, std::size_t K>
std::vector<rvertex<D>> exact_vertices(const std::array<long long, K / 2>& lo, const std::array<long long, K / 2>& hi) {
    constexpr std::size_t A = K / 2;
    const auto& n = kdop<double, D, K>::directions;
    std::vector<rvertex<D>> out;
    for (std::size_t j = 0; j < A; ++j)
        if (lo[j] > hi[j]) return out;
    auto try_planes = [&](const std::array<std::size_t, D>& idx) {
        // Cofactor matrix of the normal matrix M (rows n_idx): M^-1 = cof^T / det.
        long long m[D][D];
        for (std::size_t r = 0; r < D; ++r)
            for (std::size_t c = 0; c < D; ++c) m[r][c] = n[idx[r]][c];
        long long det, inv[D][D];  // inv = adj(M) = cof^T
        if constexpr (D == 2) {
            det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            inv[0][0] = m[1][1], inv[0][1] = -m[0][1], inv[1][0] = -m[1][0], inv[1][1] = m[0][0];
        } else {
            for (std::size_t r = 0; r < 3; ++r)
                for (std::size_t c = 0; c < 3; ++c) {
                    const std::size_t r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
                    inv[c][r] = m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];  // cofactor(r, c) into adj(c, r)
                }
            det = m[0][0] * inv[0][0] + m[0][1] * inv[1][0] + m[0][2] * inv[2][0];
        }
        if (det == 0) return;
        for (unsigned mask = 0; mask < (1u << D); ++mask) {
            long long b[D];
            for (std::size_t k = 0; k < D; ++k) b[k] = (mask >> k & 1u) ? hi[idx[k]] : lo[idx[k]];
            rvertex<D> v;
            for (std::size_t r = 0; r < D; ++r) {
                long long s = 0;
                for (std::size_t k = 0; k < D; ++k) s += inv[r][k] * b[k];
                v.x[r] = s;
            }
            v.det = det;
            if (v.det < 0) {
                v.det = -v.det;
                for (auto& c : v.x) c = -c;
            }
            bool ok = true;
            for (std::size_t j = 0; j < A && ok; ++j) {
                long long s = 0;
                for (std::size_t c = 0; c < D; ++c) s += n[j][c] * v.x[c];
                ok = lo[j] * v.det <= s && s <= hi[j] * v.det;
            }
            if (!ok) continue;
            bool dup = false;
            for (const auto& w : out) {
                bool same = true;
                for (std::size_t c = 0; c < D; ++c) same &= v.x[c] * w.det == w.x[c] * v.det;
                dup |= same;
            }
            if (!dup) out.push_back(v);
        }
    };
    std::array<std::size_t, D> idx{};
    if constexpr (D == 2) {
        for (idx[0] = 0; idx[0] < A; ++idx[0])
            for (idx[1] = idx[0] + 1; idx[1] < A; ++idx[1]) try_planes(idx);
    } else {
        for (idx[0] = 0; idx[0] < A; ++idx[0])
            for (idx[1] = idx[0] + 1; idx[1] < A; ++idx[1])
                for (idx[2] = idx[1] + 1; idx[2] < A; ++idx[2]) try_planes(idx);
    }
    return out;
}

using ivec3 = std::array<long long, 3>;
inline ivec3 icross(const ivec3& a, const ivec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Separating-axis reference on explicit exact vertex sets. Candidate axes: every face normal
// and, in 3D, every cross product e x f of edge-direction candidates e, f in {n_i x n_j}.
// True iff no candidate axis separates strictly (touching overlaps). Complete for
// full-dimensional polytopes (every edge of a k-DOP lies on two of its planes).
template <std::size_t D, std::size_t K>
bool sat_reference(const std::vector<rvertex<D>>& a, const std::vector<rvertex<D>>& b) {
    if (a.empty() || b.empty()) return false;
    const auto& n = kdop<double, D, K>::directions;
    std::vector<std::array<long long, D>> axes;
    for (const auto& d : n) {
        std::array<long long, D> v;
        for (std::size_t c = 0; c < D; ++c) v[c] = d[c];
        axes.push_back(v);
    }
    if constexpr (D == 3) {
        std::vector<ivec3> edges;
        for (std::size_t i = 0; i < n.size(); ++i)
            for (std::size_t j = i + 1; j < n.size(); ++j) {
                const ivec3 e = icross({n[i][0], n[i][1], n[i][2]}, {n[j][0], n[j][1], n[j][2]});
                if (e != ivec3{0, 0, 0}) edges.push_back(e);
            }
        for (std::size_t i = 0; i < edges.size(); ++i)
            for (std::size_t j = i + 1; j < edges.size(); ++j) {
                const ivec3 ax = icross(edges[i], edges[j]);
                if (ax != ivec3{0, 0, 0}) axes.push_back(ax);
            }
    }
    // Compare p / q < r / s with q, s > 0.
    auto less = [](long long p, long long q, long long r, long long s) { return p * s < r * q; };
    for (const auto& ax : axes) {
        auto project = [&](const std::vector<rvertex<D>>& vs, long long& minn, long long& mind, long long& maxn,
                           long long& maxd) {
            bool first = true;
            for (const auto& v : vs) {
                long long s = 0;
                for (std::size_t c = 0; c < D; ++c) s += ax[c] * v.x[c];
                if (first || less(s, v.det, minn, mind)) minn = s, mind = v.det;
                if (first || less(maxn, maxd, s, v.det)) maxn = s, maxd = v.det;
                first = false;
            }
        };
        long long amin = 0, amind = 1, amax = 0, amaxd = 1, bmin = 0, bmind = 1, bmax = 0, bmaxd = 1;
        project(a, amin, amind, amax, amaxd);
        project(b, bmin, bmind, bmax, bmaxd);
        if (less(amax, amaxd, bmin, bmind) || less(bmax, bmaxd, amin, amind)) return false;
    }
    return true;
}

// Exact non-emptiness of A ∩ B (a second, different reference).
template <std::size_t D, std::size_t K>
bool intersection_reference(const std::array<long long, K / 2>& alo, const std::array<long long, K / 2>& ahi,
                            const std::array<long long, K / 2>& blo, const std::array<long long, K / 2>& bhi) {
    std::array<long long, K / 2> lo, hi;
    for (std::size_t j = 0; j < K / 2; ++j) lo[j] = std::max(alo[j], blo[j]), hi[j] = std::min(ahi[j], bhi[j]);
    return !exact_vertices<D, K>(lo, hi).empty();
}

constexpr double grid = 256;  // slab values in units of 1/256: exact in float and double

template <class T, std::size_t D, std::size_t K>
kdop<T, D, K> from_integers(const std::array<long long, K / 2>& lo, const std::array<long long, K / 2>& hi) {
    kdop<T, D, K> b;
    for (std::size_t j = 0; j < K / 2; ++j) {
        b.lo[j] = static_cast<T>(static_cast<double>(lo[j]) / grid);
        b.hi[j] = static_cast<T>(static_cast<double>(hi[j]) / grid);
    }
    return b;
}

// A random rotated point cloud on the grid; returns the exact integer slabs of its tight
// k-DOP, optionally snapped from a float/double fit (outward to the grid).
template <class T, std::size_t D, std::size_t K>
void random_grid_kdop(rng_t& rng, double size, std::array<long long, K / 2>& lo, std::array<long long, K / 2>& hi,
                      bool via_fit) {
    const auto rot = random_rotation<D>(rng);
    std::array<double, D> ext, off;
    for (std::size_t d = 0; d < D; ++d) ext[d] = size * (0.2 + unit(rng)), off[d] = (unit(rng) - 0.5) * 2 * size;
    std::vector<point<T, D>> pts;
    const int n = 4 + static_cast<int>(rng() % 40);
    for (int i = 0; i < n; ++i) {
        std::array<double, D> x;
        for (std::size_t d = 0; d < D; ++d) x[d] = (unit(rng) - 0.5) * ext[d];
        point<T, D> p;
        for (std::size_t r = 0; r < D; ++r) {
            double s = off[r];
            for (std::size_t c = 0; c < D; ++c) s += rot[r][c] * x[c];
            p[r] = static_cast<T>(std::round(s * grid) / grid);
        }
        pts.push_back(p);
    }
    if (via_fit) {
        const auto b = kdop<T, D, K>::fit(pts);
        for (std::size_t j = 0; j < K / 2; ++j) {
            lo[j] = static_cast<long long>(std::floor(static_cast<long double>(b.lo[j]) * grid));
            hi[j] = static_cast<long long>(std::ceil(static_cast<long double>(b.hi[j]) * grid));
        }
    } else {
        const auto& n_ = kdop<T, D, K>::directions;
        lo.fill(std::numeric_limits<long long>::max());
        hi.fill(std::numeric_limits<long long>::min());
        for (const auto& p : pts)
            for (std::size_t j = 0; j < K / 2; ++j) {
                long long s = 0;
                for (std::size_t c = 0; c < D; ++c) s += n_[j][c] * std::llround(static_cast<double>(p[c]) * grid);
                lo[j] = std::min(lo[j], s);
                hi[j] = std::max(hi[j], s);
            }
    }
}

// A random_grid_kdop: its exact slabs and the k-DOP of T they give.
template <class T, std::size_t D, std::size_t K>
struct grid_kdop {
    std::array<long long, K / 2> lo, hi;
    kdop<T, D, K> b;
};
template <class T, std::size_t D, std::size_t K>
grid_kdop<T, D, K> random_grid_kdop(rng_t& rng, double size, bool via_fit) {
    grid_kdop<T, D, K> g;
    random_grid_kdop<T, D, K>(rng, size, g.lo, g.hi, via_fit);
    g.b = from_integers<T, D, K>(g.lo, g.hi);
    return g;
}

template <class C>
class kdop_typed : public spatial_test::dims_fixture<C> {};

TYPED_TEST_SUITE(kdop_typed, spatial_test::dim_types);

// ------------------------------------------------------------------------------------------

TYPED_TEST(kdop_typed, fit_contains_every_point_on_random_and_hard_sets) {
    SPATIAL_DIMS_NAMES;
    const spatial_test::logged_seed seed(101);
    for_each_hard_set<T, D>(seed, [&](const std::string& name, std::span<const point<T, D>> s, const aabb<T, D>& box) {
        for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
            const auto b = kdop<T, D, K>::fit(s);
            ASSERT_FALSE(b.is_empty());
            for (std::size_t j = 0; j < K / 2; ++j) {
                ASSERT_TRUE(std::isfinite(b.lo[j]) && std::isfinite(b.hi[j]));
                ASSERT_LE(b.lo[j], b.hi[j]);
            }
            // The axis slabs are exactly the box.
            for (std::size_t d = 0; d < D; ++d) {
                EXPECT_EQ(b.lo[d], box.lo[d]);
                EXPECT_EQ(b.hi[d], box.hi[d]);
            }
            for (const auto& p : s) {
                ASSERT_TRUE(b.contains(p)) << p;
                // The exact polytope contains the exact point (long double has 64 bits: the
                // sum of <= 3 exact small-integer multiples of T values is exact or nearly).
                for (std::size_t j = 0; j < K / 2; ++j) {
                    long double v = 0;
                    for (std::size_t c = 0; c < D; ++c)
                        v += static_cast<long double>(kdop<T, D, K>::directions[j][c]) * static_cast<long double>(p[c]);
                    ASSERT_LE(static_cast<long double>(b.lo[j]), v) << "direction " << j;
                    ASSERT_GE(static_cast<long double>(b.hi[j]), v) << "direction " << j;
                }
                EXPECT_EQ(b.distance_lower_bound(p), T(0));
            }
            const auto verts = b.vertices();
            ASSERT_FALSE(verts.empty());
            const double vol = static_cast<double>(b.volume()), area = static_cast<double>(b.surface_area());
            ASSERT_TRUE(std::isfinite(vol) && std::isfinite(area));
            EXPECT_GE(vol, 0.0);
            EXPECT_LE(vol, static_cast<double>(box.volume()) * (1 + (sizeof(T) == 4 ? 1e-5 : 1e-9)) + 1e-300);
            if (name == "all equal" || name == "one point") {
                EXPECT_LE(vol, 1e-9 * std::pow(static_cast<double>(box.surface_area()) + 1e-300, D == 3 ? 1.5 : 2.0));
            }
        });
    });
}

TYPED_TEST(kdop_typed, nan_input_is_rejected_and_empty_conventions_hold) {
    SPATIAL_DIMS_NAMES;
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        using B = kdop<T, D, K>;
        std::vector<point<T, D>> pts(3);
        pts[1][0] = std::numeric_limits<T>::quiet_NaN();
        EXPECT_THROW((void)B::fit(pts), std::invalid_argument);
        pts[1][0] = std::numeric_limits<T>::infinity();
        EXPECT_THROW((void)B::fit(pts), std::invalid_argument);
        const B e = B::empty();
        EXPECT_TRUE(B::fit({}).is_empty());
        EXPECT_TRUE(e.vertices().empty());
        std::vector<point<T, D>> one(1);
        one[0][0] = T(2);
        const B p = B::fit(one);
        EXPECT_FALSE(e.overlaps_exact(p));
        EXPECT_TRUE(p.overlaps_exact(p));  // a point touches itself (and overlaps itself, below)
        spatial_test::expect_empty_conventions(e, p, [&](const B& m) {
            EXPECT_EQ(m.lo, p.lo);
            EXPECT_EQ(m.hi, p.hi);
        });
    });
}

TYPED_TEST(kdop_typed, six_dop_equals_the_box_and_volumes_shrink_with_more_directions) {
    SPATIAL_DIMS_NAMES;
    const spatial_test::logged_seed seed(202);
    for_each_hard_set<T, D>(seed, [&](const std::string&, std::span<const point<T, D>> s, const aabb<T, D>& box) {
        constexpr std::size_t K0 = D == 2 ? 4 : 6;
        const auto b0 = kdop<T, D, K0>::fit(s);
        const double bv = static_cast<double>(box.volume()), ba = static_cast<double>(box.surface_area());
        EXPECT_NEAR(static_cast<double>(b0.volume()), bv, 1e-6 * bv + 1e-300);
        EXPECT_NEAR(static_cast<double>(b0.surface_area()), ba, 1e-6 * ba + 1e-300);
        // Nested direction sets give nested polytopes: volume and area never grow.
        auto vol = [&](auto kc) {
            constexpr std::size_t K = decltype(kc)::value;
            const auto b = kdop<T, D, K>::fit(s);
            return std::pair<double, double>{static_cast<double>(b.volume()), static_cast<double>(b.surface_area())};
        };
        const double slack = 1 + (sizeof(T) == 4 ? 1e-5 : 1e-9);
        // Vertices carry an absolute rounding error ~ eps * extent (not * thickness): for a
        // needle or a flat polytope the measures then have an absolute error ~ area * that.
        double extent = 0;
        for (std::size_t d = 0; d < D; ++d) extent = std::max(extent, static_cast<double>(box.hi[d] - box.lo[d]));
        const double vertex_err = 1024 * std::numeric_limits<double>::epsilon() * extent;
        const double abs_vol = static_cast<double>(b0.surface_area()) * vertex_err + 1e-300;
        const double abs_area = (D == 3 ? 12 * extent : 4.0) * vertex_err + 1e-300;
        if constexpr (D == 2) {
            const auto v4 = vol(std::integral_constant<std::size_t, 4>{}),
                       v8 = vol(std::integral_constant<std::size_t, 8>{}),
                       v16 = vol(std::integral_constant<std::size_t, 16>{});
            EXPECT_LE(v8.first, v4.first * slack + abs_vol);
            EXPECT_LE(v16.first, v8.first * slack + abs_vol);
            EXPECT_LE(v8.second, v4.second * slack + abs_area);
            EXPECT_LE(v16.second, v8.second * slack + abs_area);
        } else {
            const auto v6 = vol(std::integral_constant<std::size_t, 6>{}),
                       v14 = vol(std::integral_constant<std::size_t, 14>{}),
                       v18 = vol(std::integral_constant<std::size_t, 18>{}),
                       v26 = vol(std::integral_constant<std::size_t, 26>{});
            for (const auto& v : {v14, v18}) {
                EXPECT_LE(v.first, v6.first * slack + abs_vol);
                EXPECT_GE(v.first * slack + abs_vol, v26.first);
                EXPECT_LE(v.second, v6.second * slack + abs_area);
                EXPECT_GE(v.second * slack + abs_area, v26.second);
            }
        }
    });
}

TYPED_TEST(kdop_typed, known_shapes_have_exact_measures) {
    SPATIAL_DIMS_NAMES;
    // Cross-polytope vertices (+-e_i): a square rotated by 45 degrees / an octahedron.
    std::vector<point<T, D>> cross;
    for (std::size_t i = 0; i < D; ++i)
        for (int s : {-1, 1}) {
            point<T, D> p{};
            p[i] = static_cast<T>(s);
            cross.push_back(p);
        }
    std::vector<point<T, D>> cube;
    for (unsigned m = 0; m < (1u << D); ++m) {
        point<T, D> p{};
        for (std::size_t i = 0; i < D; ++i) p[i] = (m >> i & 1u) ? T(1) : T(-1);
        cube.push_back(p);
    }
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        const auto c = kdop<T, D, K>::fit(cube);  // every direction touches a cube corner
        EXPECT_NEAR(static_cast<double>(c.volume()), std::pow(2.0, double(D)), 1e-5);
        EXPECT_NEAR(static_cast<double>(c.surface_area()), D == 2 ? 8.0 : 24.0, 1e-5);
        EXPECT_EQ(c.vertices().size(), std::size_t(1) << D);
        const auto x = kdop<T, D, K>::fit(cross);
        const bool has_corner_dirs = D == 2 ? K >= 8 : (K == 14 || K == 26);
        if (has_corner_dirs) {  // the cross-polytope itself
            EXPECT_NEAR(static_cast<double>(x.volume()), D == 2 ? 2.0 : 4.0 / 3, 1e-5);
            EXPECT_NEAR(static_cast<double>(x.surface_area()), D == 2 ? 4 * std::sqrt(2.0) : 4 * std::sqrt(3.0), 1e-5);
            EXPECT_EQ(x.vertices().size(), 2 * D);
        } else if (K == 18) {  // |x|+|y|, |x|+|z|, |y|+|z| <= 1 within the cube: volume 2
            EXPECT_NEAR(static_cast<double>(x.volume()), 2.0, 1e-5);
        } else {
            EXPECT_NEAR(static_cast<double>(x.volume()), std::pow(2.0, double(D)), 1e-5);
        }
    });
}

// Volume against Monte Carlo, surface area against Cauchy's formula (3D: the surface area of
// a convex body is 4 times its mean projected area; 2D: the perimeter is pi times the mean
// width), both on the EXACT reference vertices.
TYPED_TEST(kdop_typed, volume_and_area_match_monte_carlo_and_cauchy) {
    SPATIAL_DIMS_NAMES;
    spatial_test::seeded_rng rng(303);
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        for (int trial = 0; trial < 3; ++trial) {
            const auto [lo, hi, b] = random_grid_kdop<T, D, K>(rng, 2.0, trial % 2 == 0);
            const auto ref = exact_vertices<D, K>(lo, hi);
            ASSERT_FALSE(ref.empty());
            // Vertices agree with the exact ones.
            const auto verts = b.vertices_double();
            EXPECT_EQ(verts.size(), ref.size());
            for (const auto& r : ref) {
                double best = 1e300;
                for (const auto& v : verts) {
                    double d = 0;
                    for (std::size_t c = 0; c < D; ++c)
                        d = std::max(d,
                                     std::abs(v[c] - static_cast<double>(r.x[c]) / static_cast<double>(r.det) / grid));
                    best = std::min(best, d);
                }
                EXPECT_LE(best, 1e-12);
            }
            // Monte Carlo over the axis box.
            double box = 1;
            for (std::size_t d = 0; d < D; ++d) box *= static_cast<double>(b.hi[d] - b.lo[d]);
            const int n = 100000;
            int in = 0;
            for (int i = 0; i < n; ++i) {
                point<T, D> p;
                for (std::size_t d = 0; d < D; ++d)
                    p[d] = static_cast<T>(b.lo[d] + (b.hi[d] - b.lo[d]) * static_cast<T>(unit(rng)));
                in += b.contains(p);
            }
            const double f = static_cast<double>(in) / n;
            const double sigma = std::sqrt(f * (1 - f) / n) * box;
            EXPECT_NEAR(static_cast<double>(b.volume()), f * box, 5 * sigma + 1e-4 * box);
            // Cauchy: directions uniform on the circle / Fibonacci sphere.
            std::vector<std::array<double, D>> rv;
            for (const auto& r : ref) {
                std::array<double, D> v;
                for (std::size_t c = 0; c < D; ++c)
                    v[c] = static_cast<double>(r.x[c]) / static_cast<double>(r.det) / grid;
                rv.push_back(v);
            }
            double mean = 0;
            if constexpr (D == 2) {
                const int m = 20000;
                for (int i = 0; i < m; ++i) {
                    const double a = 3.141592653589793 * (i + 0.5) / m;
                    double mn = 1e300, mx = -1e300;
                    for (const auto& v : rv) {
                        const double s = v[0] * std::cos(a) + v[1] * std::sin(a);
                        mn = std::min(mn, s), mx = std::max(mx, s);
                    }
                    mean += (mx - mn) / m;
                }
                EXPECT_NEAR(static_cast<double>(b.surface_area()), 3.141592653589793 * mean,
                            1e-5 * static_cast<double>(b.surface_area()));
            } else {
                const int m = 4000;
                for (int i = 0; i < m; ++i) {
                    const double z = 1 - (2.0 * i + 1) / m, r = std::sqrt(1 - z * z), ph = i * 2.399963229728653;
                    const std::array<double, 3> u{r * std::cos(ph), r * std::sin(ph), z};
                    // Projected area: 2D hull (monotone chain) of the projections.
                    std::array<double, 3> e1 = std::abs(u[0]) < 0.9 ? std::array<double, 3>{0, -u[2], u[1]}
                                                                    : std::array<double, 3>{-u[2], 0, u[0]};
                    const double l = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
                    for (auto& c : e1) c /= l;
                    const std::array<double, 3> e2{u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2],
                                                   u[0] * e1[1] - u[1] * e1[0]};
                    std::vector<std::array<double, 2>> q;
                    for (const auto& v : rv)
                        q.push_back(
                            {v[0] * e1[0] + v[1] * e1[1] + v[2] * e1[2], v[0] * e2[0] + v[1] * e2[1] + v[2] * e2[2]});
                    std::sort(q.begin(), q.end());
                    std::vector<std::array<double, 2>> h;
                    auto cr = [](const auto& o, const auto& a, const auto& bb) {
                        return (a[0] - o[0]) * (bb[1] - o[1]) - (a[1] - o[1]) * (bb[0] - o[0]);
                    };
                    for (int pass = 0; pass < 2; ++pass) {
                        const std::size_t base = h.size();
                        for (std::size_t k = 0; k < q.size(); ++k) {
                            const auto& p = pass == 0 ? q[k] : q[q.size() - 1 - k];
                            while (h.size() >= base + 2 && cr(h[h.size() - 2], h.back(), p) <= 0) h.pop_back();
                            h.push_back(p);
                        }
                        h.pop_back();
                    }
                    double area = 0;
                    for (std::size_t k = 0; k < h.size(); ++k) area += cr(h[0], h[k], h[(k + 1) % h.size()]);
                    mean += std::abs(area) / 2 / m;
                }
                EXPECT_NEAR(static_cast<double>(b.surface_area()), 4 * mean,
                            2e-3 * static_cast<double>(b.surface_area()));
            }
        }
    });
}

// Random rotated pairs, many of them touching (a face translated onto the other's face):
// overlaps() never gives a false negative against the exact references, and
// overlaps_exact() agrees with them exactly.
TYPED_TEST(kdop_typed, overlaps_is_conservative_and_overlaps_exact_matches_exact_references) {
    SPATIAL_DIMS_NAMES;
    spatial_test::seeded_rng rng(404);
    int slab_false_positives_3d = 0;
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        constexpr std::size_t A = K / 2;
        int touching = 0, conservative_fp = 0, disjoint = 0, overlapping = 0;
        const int trials = D == 3 ? 250 : 400;
        for (int trial = 0; trial < trials; ++trial) {
            std::array<long long, A> alo, ahi, blo, bhi;
            random_grid_kdop<T, D, K>(rng, 1.0, alo, ahi, trial % 3 == 0);
            random_grid_kdop<T, D, K>(rng, 1.0, blo, bhi, trial % 3 == 1);
            // Translate B by integer grid vectors t (slab i moves by n_i . t, exactly): first
            // onto A's axis-box centre plus a random offset, then (every other trial) along a
            // coordinate axis c until its face along a random direction j lands exactly on
            // A's opposite face, optionally one grid step further or closer.
            auto translate = [&](const std::array<long long, D>& tv) {
                for (std::size_t i = 0; i < A; ++i) {
                    long long d = 0;
                    for (std::size_t c = 0; c < D; ++c) d += kdop<T, D, K>::directions[i][c] * tv[c];
                    blo[i] += d;
                    bhi[i] += d;
                }
            };
            std::array<long long, D> tv{};
            for (std::size_t c = 0; c < D; ++c)
                tv[c] = (alo[c] + ahi[c]) / 2 - (blo[c] + bhi[c]) / 2 +
                        static_cast<long long>((unit(rng) - 0.5) * grid * 1.5);
            translate(tv);
            if (trial % 3 == 2) {
                // Along a random integer direction w, the first step at which B leaves A
                // (exact reference, bisection): just separated, or one step back (in contact).
                std::array<long long, D> w{};
                while (w == std::array<long long, D>{})
                    for (auto& c : w) c = static_cast<long long>(rng() % 7) - 3;
                auto meets_at = [&](long long k) {
                    std::array<long long, A> l2 = blo, h2 = bhi;
                    for (std::size_t i = 0; i < A; ++i) {
                        long long d = 0;
                        for (std::size_t c = 0; c < D; ++c) d += kdop<T, D, K>::directions[i][c] * w[c] * k;
                        l2[i] += d, h2[i] += d;
                    }
                    return intersection_reference<D, K>(alo, ahi, l2, h2);
                };
                if (meets_at(0)) {
                    long long lo_k = 0, hi_k = 1;
                    while (meets_at(hi_k)) lo_k = hi_k, hi_k *= 2;
                    while (hi_k - lo_k > 1) {
                        const long long mid = (lo_k + hi_k) / 2;
                        (meets_at(mid) ? lo_k : hi_k) = mid;
                    }
                    std::array<long long, D> sv;
                    for (std::size_t c = 0; c < D; ++c) sv[c] = w[c] * (trial % 2 ? hi_k : lo_k);
                    translate(sv);
                }
            } else if (trial % 3 == 1) {
                const std::size_t j = static_cast<std::size_t>(rng() % A);
                const auto& n = kdop<T, D, K>::directions[j];
                std::size_t c = 0;
                while (n[c] == 0) ++c;
                const long long gap = ahi[j] - blo[j];
                if (gap % n[c] == 0) {
                    const long long extra = trial % 2 == 0 ? 0 : static_cast<long long>(rng() % 3) - 1;
                    std::array<long long, D> sv{};
                    sv[c] = gap / n[c] + extra;
                    translate(sv);
                }
            }
            const auto a = from_integers<T, D, K>(alo, ahi);
            const auto b = from_integers<T, D, K>(blo, bhi);
            const bool ref = sat_reference<D, K>(exact_vertices<D, K>(alo, ahi), exact_vertices<D, K>(blo, bhi));
            const bool ref2 = intersection_reference<D, K>(alo, ahi, blo, bhi);
            ASSERT_EQ(ref, ref2) << "the two exact references disagree, trial " << trial;
            const bool cons = a.overlaps(b), exact = a.overlaps_exact(b);
            if (ref) {
                ASSERT_TRUE(cons) << "false negative of overlaps(), trial " << trial;
            }
            ASSERT_EQ(exact, ref) << "overlaps_exact, trial " << trial;
            EXPECT_EQ(b.overlaps_exact(a), exact);
            EXPECT_EQ(b.overlaps(a), cons);
            // Touching: some slab interval meets in exactly one value.
            bool touch = false;
            for (std::size_t j = 0; j < A; ++j) touch |= ahi[j] == blo[j] || bhi[j] == alo[j];
            touching += touch && ref;
            conservative_fp += cons && !ref;
            disjoint += !ref;
            overlapping += ref;
        }
        EXPECT_GE(touching, 3);
        EXPECT_GT(disjoint, 10);
        EXPECT_GT(overlapping, 10);
        if constexpr (D == 3 && K != 6) {
            // A dedicated search: pairs just separated along a random integer direction are
            // where the slab test (no edge-edge axes) is conservative. Stop at the first.
            int found = 0;
            for (int attempt = 0; attempt < 1000 && found == 0; ++attempt) {
                std::array<long long, A> alo, ahi, blo, bhi;
                random_grid_kdop<T, D, K>(rng, 0.5, alo, ahi, false);
                random_grid_kdop<T, D, K>(rng, 0.5, blo, bhi, false);
                std::array<long long, D> w{};
                while (w == std::array<long long, D>{})
                    for (auto& c : w) c = static_cast<long long>(rng() % 7) - 3;
                auto moved = [&](long long k, std::array<long long, A>& l2, std::array<long long, A>& h2) {
                    l2 = blo, h2 = bhi;
                    for (std::size_t i = 0; i < A; ++i) {
                        long long d = 0;
                        for (std::size_t c = 0; c < D; ++c)
                            d += kdop<T, D, K>::directions[i][c] *
                                 (w[c] * k + (alo[c] + ahi[c]) / 2 - (blo[c] + bhi[c]) / 2);
                        l2[i] += d, h2[i] += d;
                    }
                };
                std::array<long long, A> l2, h2;
                long long lo_k = 0, hi_k = 1;
                moved(0, l2, h2);
                if (!intersection_reference<D, K>(alo, ahi, l2, h2)) continue;
                for (moved(hi_k, l2, h2); intersection_reference<D, K>(alo, ahi, l2, h2); moved(hi_k, l2, h2))
                    lo_k = hi_k, hi_k *= 2;
                while (hi_k - lo_k > 1) {
                    const long long mid = (lo_k + hi_k) / 2;
                    moved(mid, l2, h2);
                    (intersection_reference<D, K>(alo, ahi, l2, h2) ? lo_k : hi_k) = mid;
                }
                moved(hi_k, l2, h2);  // just separated
                const auto a = from_integers<T, D, K>(alo, ahi), b = from_integers<T, D, K>(l2, h2);
                const bool sat = sat_reference<D, K>(exact_vertices<D, K>(alo, ahi), exact_vertices<D, K>(l2, h2));
                ASSERT_FALSE(sat);
                ASSERT_FALSE(a.overlaps_exact(b));
                found += a.overlaps(b);
            }
            slab_false_positives_3d += found;
            EXPECT_GT(found, 0) << "no slab-test false positive found for K=" << K;
        }
        if (K == 4 || K == 6) {
            EXPECT_EQ(conservative_fp, 0);
        }
        std::cout << "  [kdop D=" << D << " K=" << K << "] pairs " << trials << ": overlapping " << overlapping
                  << " (touching " << touching << "), disjoint " << disjoint << ", slab-test false positives "
                  << conservative_fp << "\n";
    });
    // In 3D the slab test is genuinely conservative beyond the boxes (edge-edge cases).
    if (D == 3) {
        EXPECT_GT(slab_false_positives_3d, 0);
    }
}

TYPED_TEST(kdop_typed, ray_intervals_agree_with_point_sampling_including_parallel_rays) {
    SPATIAL_DIMS_NAMES;
    spatial_test::seeded_rng rng(505);
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        const auto [lo, hi, b] = random_grid_kdop<T, D, K>(rng, 2.0, false);
        for (int trial = 0; trial < 300; ++trial) {
            point<T, D> o, d;
            // Axis rays: zero and negative-zero components.
            spatial_test::random_trial_ray_from_doubles(trial, rng, o, d);
            if (trial % 4 == 1) {  // parallel to a diagonal plane: n_j . d == 0 exactly
                const auto& n = kdop<T, D, K>::directions[K / 2 - 1];
                d = point<T, D>{};
                if constexpr (D == 2)
                    d[0] = static_cast<T>(-n[1]), d[1] = static_cast<T>(n[0]);
                else {
                    const std::array<int, 3> e{1, 2, 3};
                    d[0] = static_cast<T>(n[1] * e[2] - n[2] * e[1]);
                    d[1] = static_cast<T>(n[2] * e[0] - n[0] * e[2]);
                    d[2] = static_cast<T>(n[0] * e[1] - n[1] * e[0]);
                }
            }
            if (trial % 5 == 0) o[0] = b.lo[0];  // origin on a slab plane
            T t0 = 0, t1 = 0;
            const bool hit = b.ray_interval(o, d, t0, t1);
            if (hit) {
                ASSERT_TRUE(std::isfinite(t0) || std::isinf(t0));
                ASSERT_FALSE(std::isnan(t0) || std::isnan(t1));
                ASSERT_LE(t0, t1);
            }
            bool any = false;
            ASSERT_NO_FATAL_FAILURE(spatial_test::expect_inside_samples_in_interval(b, o, d, hit, t0, t1, trial, any));
            if (hit && std::isfinite(t0) && std::isfinite(t1) && t1 - t0 > T(0.05) && std::abs(t0) < 5 &&
                std::abs(t1) < 5) {
                EXPECT_TRUE(any) << "interval with no inside point, trial " << trial;
                point<T, D> mid;
                for (std::size_t c = 0; c < D; ++c) mid[c] = o[c] + (t0 + t1) / 2 * d[c];
                EXPECT_TRUE(b.contains(mid));
            }
        }
    });
}

// distance_lower_bound never exceeds the distance to any point of the polytope (vertices and
// points of the fitted cloud), is 0 inside, and is exact for a point facing a face.
TYPED_TEST(kdop_typed, distance_lower_bound_is_valid) {
    SPATIAL_DIMS_NAMES;
    spatial_test::seeded_rng rng(606);
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        for (int trial = 0; trial < 5; ++trial) {
            const auto [lo, hi, b] = random_grid_kdop<T, D, K>(rng, 1.0, false);
            const auto verts = b.vertices_double();
            // Interior sample: random convex combinations of vertices.
            std::vector<std::array<double, D>> inside(verts.begin(), verts.end());
            for (int i = 0; i < 300; ++i) {
                std::array<double, D> x{};
                double wsum = 0;
                std::vector<double> w(verts.size());
                for (auto& v : w) v = std::pow(unit(rng), 4), wsum += v;
                for (std::size_t k = 0; k < verts.size(); ++k)
                    for (std::size_t c = 0; c < D; ++c) x[c] += w[k] / wsum * verts[k][c];
                inside.push_back(x);
            }
            for (int q = 0; q < 200; ++q) {
                point<T, D> p;
                for (std::size_t c = 0; c < D; ++c) p[c] = static_cast<T>(unit(rng) * 8 - 4);
                const double lb = static_cast<double>(b.distance_lower_bound(p));
                ASSERT_GE(lb, 0.0);
                double best = 1e300;
                for (const auto& x : inside) {
                    double s = 0;
                    for (std::size_t c = 0; c < D; ++c)
                        s += (static_cast<double>(p[c]) - x[c]) * (static_cast<double>(p[c]) - x[c]);
                    best = std::min(best, s);
                }
                ASSERT_LE(lb, std::sqrt(best) * (1 + 1e-12) + 1e-12) << p;
                if (b.contains(p)) {
                    EXPECT_EQ(lb, 0.0);
                }
            }
        }
        // Facing the +x face of the unit cube's k-DOP: exact distance.
        std::vector<point<T, D>> cube;
        for (unsigned m = 0; m < (1u << D); ++m) {
            point<T, D> p{};
            for (std::size_t i = 0; i < D; ++i) p[i] = (m >> i & 1u) ? T(1) : T(-1);
            cube.push_back(p);
        }
        const auto c = kdop<T, D, K>::fit(cube);
        point<T, D> p{};
        p[0] = T(3.5);
        EXPECT_NEAR(static_cast<double>(c.distance_lower_bound(p)), 2.5, 1e-5);
    });
}

TYPED_TEST(kdop_typed, merged_is_the_kdop_of_the_union_and_transformed_contains_the_moved_set) {
    SPATIAL_DIMS_NAMES;
    const spatial_test::logged_seed seed(707);
    std::mt19937_64 rng(seed);
    const auto sets = hard_sets<T, D>(seed);
    for_each_k<D>([&]<std::size_t K>(k_tag<K>) {
        using B = kdop<T, D, K>;
        for (std::size_t s = 0; s + 1 < sets.size(); ++s) {
            const auto& pa = sets[s].second;
            const auto& pb = sets[s + 1].second;
            SCOPED_TRACE(sets[s].first + " + " + sets[s + 1].first);
            const B a = B::fit(pa), b = B::fit(pb);
            std::vector<point<T, D>> all(pa);
            all.insert(all.end(), pb.begin(), pb.end());
            const B u = B::fit(all), m = a.merged(b);
            for (const auto& p : all) ASSERT_TRUE(m.contains(p)) << p;
            double mabs = 0;
            for (const auto& p : all)
                for (std::size_t c = 0; c < D; ++c) mabs = std::max(mabs, std::abs(static_cast<double>(p[c])));
            for (std::size_t j = 0; j < K / 2; ++j) {  // equal up to the fits' rounding pads (<= 2 eps |n|_1 max|x|)
                const double tol =
                    16 * std::numeric_limits<double>::epsilon() * mabs +
                    4 * std::numeric_limits<T>::epsilon() *
                        (std::abs(static_cast<double>(u.hi[j])) + std::abs(static_cast<double>(u.lo[j]))) +
                    1e-300;
                EXPECT_NEAR(static_cast<double>(m.lo[j]), static_cast<double>(u.lo[j]), tol);
                EXPECT_NEAR(static_cast<double>(m.hi[j]), static_cast<double>(u.hi[j]), tol);
            }
        }
        // transformed: contains every moved point and every moved vertex; not smaller.
        for (const auto& [name, pts] : sets) {
            SCOPED_TRACE(name);
            const B b = B::fit(pts);
            rigid_transform<T, D> xf;
            const auto rot = random_rotation<D>(rng);
            for (std::size_t i = 0; i < D; ++i) {
                for (std::size_t j = 0; j < D; ++j) xf.rotation[i][j] = static_cast<T>(rot[i][j]);
                xf.translation[i] = static_cast<T>(unit(rng) * 4 - 2);
            }
            const B moved = b.transformed(xf);
            ASSERT_FALSE(moved.is_empty());
            for (const auto& p : pts) ASSERT_TRUE(moved.contains(xf.apply(p))) << p;
            if constexpr (sizeof(T) == 8) {  // the refit used exactly these moved vertices
                for (const auto& v : b.vertices()) ASSERT_TRUE(moved.contains(xf.apply(v))) << v;
            }
            const double v0 = static_cast<double>(b.volume()), v1 = static_cast<double>(moved.volume());
            EXPECT_GE(v1, v0 * (1 - 1e-4) - 1e-300);
            // Identity: unchanged up to the rounding pad.
            const B same = b.transformed(rigid_transform<T, D>::identity());
            for (std::size_t j = 0; j < K / 2; ++j) {
                EXPECT_LE(same.lo[j], b.lo[j]);
                EXPECT_GE(same.hi[j], b.hi[j]);
            }
            // The pad is ~ eps_T * max|x| per slab: the volume grows by at most area * pad.
            double mabs = 0;
            for (const auto& p : pts)
                for (std::size_t c = 0; c < D; ++c) mabs = std::max(mabs, std::abs(static_cast<double>(p[c])));
            double diam = 0;
            for (std::size_t c = 0; c < D; ++c) diam += static_cast<double>(b.hi[c] - b.lo[c]);
            const double pad = 256 * std::numeric_limits<T>::epsilon() * (mabs + diam + 1);
            EXPECT_NEAR(static_cast<double>(same.volume()), v0,
                        1e-4 * v0 + static_cast<double>(b.surface_area()) * pad * 8 +
                            diam * std::pow(pad * 8, double(D) - 1) * 8 + std::pow(pad * 8, double(D)) * 8);
        }
    });
}

TEST(kdop_report, fit_and_overlap_timings) {
    // Not a correctness test: prints fit and overlap timings (double, 3D, uniform cube).
#ifdef NDEBUG
    const std::size_t n = 1000000;
#else
    const std::size_t n = 20000;
#endif
    rng_t rng(spatial_test::test_seed(808));
    std::vector<point<double, 3>> pts(n);
    for (auto& p : pts)
        for (std::size_t c = 0; c < 3; ++c) p[c] = unit(rng);
    for_each_k<3>([&](auto kc) {
        constexpr std::size_t K = decltype(kc)::value;
        using B = kdop<double, 3, K>;
        const auto t0 = std::chrono::steady_clock::now();
        const B b = B::fit(pts);
        const auto t1 = std::chrono::steady_clock::now();
        ASSERT_TRUE(b.contains(pts[n / 2]));
        // Overlap tests on random pairs of small k-DOPs.
        std::vector<B> bs;
        for (int i = 0; i < 200; ++i) {
            std::array<long long, K / 2> lo, hi;
            random_grid_kdop<double, 3, K>(rng, 0.5, lo, hi, false);
            bs.push_back(from_integers<double, 3, K>(lo, hi));
        }
        std::size_t c1 = 0, c2 = 0;
        const auto t2 = std::chrono::steady_clock::now();
        for (const auto& x : bs)
            for (const auto& y : bs) c1 += x.overlaps(y);
        const auto t3 = std::chrono::steady_clock::now();
        for (const auto& x : bs)
            for (const auto& y : bs) c2 += x.overlaps_exact(y);
        const auto t4 = std::chrono::steady_clock::now();
        EXPECT_GE(c1, c2);
        const double pairs = static_cast<double>(bs.size() * bs.size());
        std::cout << "  [kdop<double,3," << K << ">] fit n=" << n << ": "
                  << std::chrono::duration<double>(t1 - t0).count() * 1e3 << " ms; overlaps "
                  << std::chrono::duration<double>(t3 - t2).count() / pairs * 1e9 << " ns/pair; overlaps_exact "
                  << std::chrono::duration<double>(t4 - t3).count() / pairs * 1e9 << " ns/pair (" << c1 << " / " << c2
                  << " positive)\n";
    });
}

}  // namespace
