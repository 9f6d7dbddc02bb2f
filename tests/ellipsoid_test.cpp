// spatial::ellipsoid<T, D>, float and double, 2D and 3D. References written here:
//   * the minimum-volume enclosing ellipsoid: known cases (a simplex's is its Steiner
//     circumellipsoid; points spread over a known ellipsoid's surface have that ellipsoid),
//     and fit_khachiyan itself at tolerance 1e-9 (its certificate checked independently);
//   * overlap: the Perram-Wertheim contact function in long double with Eigen (inverse shape
//     matrices formed directly, golden-section maximisation), exactly tangent pairs built
//     geometrically (opposite normals at a known surface point), and point sampling;
//   * point-ellipsoid distance by dense parametric sampling plus local refinement;
//   * surface area by numerical quadrature and closed forms for spheroids.

#include "spatial/bv/ellipsoid.hpp"

#include <gtest/gtest.h>

#include "spatial/bv/eigen_dense.hpp"
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bv_test_support.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

using rng_t = std::mt19937_64;
using spatial_test::unit;
inline double gauss(rng_t& r) {  // Box-Muller
    const double u1 = std::max(unit(r), 1e-300), u2 = unit(r);
    return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}
constexpr double pi = 3.14159265358979323846;

template <std::size_t D>
using mat = std::array<std::array<double, D>, D>;

template <std::size_t D>
mat<D> random_rotation(rng_t& r) {
    return spatial_test::random_rotation<D>(r, gauss);
}

// An ellipsoid with a random frame, semi-axes in [lo, hi] and centre c.
template <class T, std::size_t D>
ellipsoid<T, D> random_ellipsoid(rng_t& rng, double lo, double hi, const std::array<double, D>& c) {
    ellipsoid<T, D> e;
    const auto r = random_rotation<D>(rng);
    for (std::size_t k = 0; k < D; ++k) {
        for (std::size_t i = 0; i < D; ++i) e.axes[k][i] = static_cast<T>(r[k][i]);
        e.semi_axes[k] = static_cast<T>(lo + (hi - lo) * unit(rng));
        e.center[k] = static_cast<T>(c[k]);
    }
    return e;
}

// The point c + U^-1 diag(a) (scale z) of the STORED form sum_k (u_k . (x - c) / a_k)^2
// (for a frame rounded to float, U^-1 differs from U^T by ~1e-7): on the surface for |z| = 1.
template <class T, std::size_t D>
std::array<double, D> surface_point(const ellipsoid<T, D>& e, const std::array<double, D>& z, double scale = 1) {
    Eigen::Matrix<double, int(D), int(D)> u;
    for (std::size_t i = 0; i < D; ++i)
        for (std::size_t j = 0; j < D; ++j) u(int(i), int(j)) = static_cast<double>(e.axes[i][j]);
    const Eigen::Matrix<double, int(D), int(D)> ui = u.inverse();
    std::array<double, D> x;
    for (std::size_t i = 0; i < D; ++i) {
        x[i] = static_cast<double>(e.center[i]);
        for (std::size_t k = 0; k < D; ++k)
            x[i] += scale * static_cast<double>(e.semi_axes[k]) * z[k] * ui(int(i), int(k));
    }
    return x;
}
template <std::size_t D>
std::array<double, D> random_unit(rng_t& rng) {
    std::array<double, D> z;
    double n = 0;
    for (auto& x : z) x = gauss(rng), n += x * x;
    n = std::sqrt(n);
    for (auto& x : z) x /= n;
    return z;
}
template <class T, std::size_t D>
point<T, D> to_point(const std::array<double, D>& x) {
    point<T, D> p;
    for (std::size_t i = 0; i < D; ++i) p[i] = static_cast<T>(x[i]);
    return p;
}

// Named hard-case sets.
template <class T, std::size_t D>
spatial_test::named_point_sets<T, D> hard_sets(std::uint64_t seed) {
    rng_t rng(seed);
    spatial_test::named_point_sets<T, D> out;
    auto make = [&](const std::string& name, std::size_t n, auto f) {
        out.push_back({name, spatial_test::points_from<T, D>(n, f)});
    };
    make("random", 500, [&](std::size_t, std::size_t) { return unit(rng) * 10 - 5; });
    make("gaussian", 2000, [&](std::size_t, std::size_t d) { return gauss(rng) * static_cast<double>(d + 1); });
    make("one point", 1, [&](std::size_t, std::size_t d) { return 1.5 + static_cast<double>(d); });
    make("two points", 2, [&](std::size_t i, std::size_t d) { return static_cast<double>(i * 3 + d); });
    make("three points", 3, [&](std::size_t i, std::size_t d) { return std::sin(static_cast<double>(7 * i + 3 * d)); });
    make("all equal", 100, [&](std::size_t, std::size_t) { return 0.25; });
    make("all zero", 10, [&](std::size_t, std::size_t) { return 0.0; });
    make("collinear", 200,
         [&](std::size_t i, std::size_t d) { return static_cast<double>(i) * 0.01 * static_cast<double>(d + 1); });
    make("coplanar", 200, [&](std::size_t, std::size_t d) { return d + 1 == D ? 0.5 : unit(rng); });
    make("offset 1e8", 200, [&](std::size_t, std::size_t) { return 1e8 + unit(rng) * (sizeof(T) == 4 ? 1e3 : 1.0); });
    make("spread 1e-12", 200, [&](std::size_t, std::size_t) { return 0.5 + unit(rng) * 1e-12; });
    make("near duplicates", 200, [&](std::size_t i, std::size_t d) {
        return static_cast<double>(i % 3) * static_cast<double>(d * d + 1) + 1e-13 * unit(rng);
    });
    make("thin slab 1e-9", 300, [&](std::size_t, std::size_t d) { return d + 1 == D ? 1e-9 * unit(rng) : unit(rng); });
    make("one outlier", 300,
         [&](std::size_t i, std::size_t d) { return i == 7 ? 50.0 : gauss(rng) * 0.1 + static_cast<double>(d); });
    {
        const auto rot = random_rotation<D>(rng);
        std::vector<point<T, D>> v;
        for (int i = 0; i < 400; ++i) {
            const auto z = random_unit<D>(rng);
            std::array<double, D> x{};
            for (std::size_t r = 0; r < D; ++r) {
                x[r] = 3;
                for (std::size_t c = 0; c < D; ++c) x[r] += rot[r][c] * z[c] * (c == 0 ? 4.0 : (c == 1 ? 1.0 : 0.25));
            }
            v.push_back(to_point<T, D>(x));
        }
        out.push_back({"ellipsoid surface", v});
    }
    return out;
}

template <class T, std::size_t D>
double frame_error(const ellipsoid<T, D>& e) {
    double err = 0;
    for (std::size_t a = 0; a < D; ++a)
        for (std::size_t b = 0; b < D; ++b) {
            double s = 0;
            for (std::size_t i = 0; i < D; ++i)
                s += static_cast<double>(e.axes[a][i]) * static_cast<double>(e.axes[b][i]);
            err = std::max(err, std::abs(s - (a == b ? 1.0 : 0.0)));
        }
    return err;
}

// ---------------------------------------------------------------- long double references

template <std::size_t D>
using lmat = Eigen::Matrix<long double, int(D), int(D)>;
template <std::size_t D>
using lvec = Eigen::Matrix<long double, int(D), 1>;

// A^-1 for the stored form x^T U^T diag(1/a^2) U x: U^-1 diag(a^2) U^-T.
template <class T, std::size_t D>
lmat<D> inverse_shape(const ellipsoid<T, D>& e) {
    lmat<D> u;
    for (std::size_t i = 0; i < D; ++i)
        for (std::size_t j = 0; j < D; ++j) u(int(i), int(j)) = static_cast<long double>(e.axes[i][j]);
    lmat<D> d = lmat<D>::Zero();
    for (std::size_t k = 0; k < D; ++k)
        d(int(k), int(k)) = static_cast<long double>(e.semi_axes[k]) * static_cast<long double>(e.semi_axes[k]);
    const lmat<D> ui = u.inverse();
    return ui * d * ui.transpose();
}

// max over l of the Perram-Wertheim contact function (golden section in long double).
template <class T, std::size_t D>
long double pw_reference(const ellipsoid<T, D>& a, const ellipsoid<T, D>& b) {
    const lmat<D> ai = inverse_shape(a), bi = inverse_shape(b);
    lvec<D> r;
    for (std::size_t i = 0; i < D; ++i)
        r[int(i)] = static_cast<long double>(b.center[i]) - static_cast<long double>(a.center[i]);
    auto f = [&](long double l) -> long double {
        const lmat<D> m = (1 - l) * ai + l * bi;
        return l * (1 - l) * r.dot(m.partialPivLu().solve(r));
    };
    long double lo = 0, hi = 1;
    const long double g = (std::sqrt(5.0L) - 1) / 2;
    long double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
    for (int it = 0; it < 200 && hi - lo > 1e-17L; ++it) {
        if (f1 < f2)
            lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
        else
            hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
    }
    return std::max(f1, f2);
}

template <class C>
class ellipsoid_typed : public spatial_test::dims_fixture<C> {};

TYPED_TEST_SUITE(ellipsoid_typed, spatial_test::dim_types);

// ------------------------------------------------------------------------------------------

TYPED_TEST(ellipsoid_typed, fits_contain_every_point_on_random_and_hard_sets) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    const spatial_test::logged_seed seed(11);
    const double frame_tol = sizeof(T) == 4 ? 1e-6 : 1e-14;
    for (const auto& [name, pts] : hard_sets<T, D>(seed)) {
        SCOPED_TRACE(name);
        const std::span<const point<T, D>> s(pts);
        khachiyan_report rep;
        const E pca = E::fit_pca(s);
        const E kh = E::fit_khachiyan(s, 1e-3, &rep);
        const E kh_loose = E::fit_khachiyan(s, 0.5);
        for (const E* e : {&pca, &kh, &kh_loose}) {
            ASSERT_FALSE(e->is_empty());
            for (std::size_t k = 0; k < D; ++k) {
                ASSERT_TRUE(std::isfinite(e->semi_axes[k]) && e->semi_axes[k] > 0) << e->semi_axes[k];
                ASSERT_TRUE(std::isfinite(e->center[k]));
            }
            EXPECT_LE(frame_error(*e), frame_tol);
            for (const auto& p : pts) ASSERT_TRUE(e->contains(p)) << p << " q=" << e->quadratic_form(p);
            ASSERT_TRUE(std::isfinite(static_cast<double>(e->volume())));
            ASSERT_TRUE(std::isfinite(static_cast<double>(e->surface_area())));
        }
        // Khachiyan's ellipsoid is never larger than PCA's, up to its tolerance (the bound
        // is on the MVEE, which is no larger than any enclosing ellipsoid).
        const double slack = 1 + 1e-3 + (sizeof(T) == 4 ? 1e-5 : 1e-9);
        if (rep.fitted_dimension == D) {
            EXPECT_LE(static_cast<double>(kh.volume()), static_cast<double>(pca.volume()) * slack);
            EXPECT_LE(rep.certified_ratio, 1 + 1e-3);
        }
        // Degenerate sets are thin but never NaN; one point or all equal gives a tiny ball.
        if (name == "one point" || name == "all equal" || name == "all zero") {
            EXPECT_EQ(rep.fitted_dimension, 0u);
            for (std::size_t k = 0; k < D; ++k) EXPECT_LE(static_cast<double>(kh.semi_axes[k]), 1e-5);
        }
        if (name == "collinear" && sizeof(T) == 8) {
            EXPECT_EQ(rep.fitted_dimension, 1u);
        }
    }
}

TYPED_TEST(ellipsoid_typed, invalid_input_is_rejected_and_empty_conventions_hold) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    std::vector<point<T, D>> pts(4);
    for (std::size_t i = 0; i < pts.size(); ++i) pts[i][0] = static_cast<T>(i);
    pts[2][D - 1] = std::numeric_limits<T>::quiet_NaN();
    EXPECT_THROW((void)E::fit_pca(pts), std::invalid_argument);
    EXPECT_THROW((void)E::fit_khachiyan(pts), std::invalid_argument);
    pts[2][D - 1] = -std::numeric_limits<T>::infinity();
    EXPECT_THROW((void)E::fit_pca(pts), std::invalid_argument);
    EXPECT_THROW((void)E::fit_khachiyan(pts), std::invalid_argument);
    pts[2][D - 1] = 0;
    EXPECT_THROW((void)E::fit_khachiyan(pts, 0.0), std::invalid_argument);
    EXPECT_THROW((void)E::fit_khachiyan(pts, std::nan("")), std::invalid_argument);
    EXPECT_TRUE(E::fit_pca({}).is_empty());
    EXPECT_TRUE(E::fit_khachiyan({}).is_empty());
    const E f = E::fit_pca(pts);
    spatial_test::expect_empty_conventions(E::empty(), f, [&](const E& m) {
        EXPECT_EQ(m.center, f.center);
        EXPECT_EQ(m.semi_axes, f.semi_axes);
    });
}

// The MVEE to tolerance: against itself at 1e-9 and against known minimum ellipsoids.
TYPED_TEST(ellipsoid_typed, khachiyan_is_within_tolerance_of_the_minimum) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    spatial_test::seeded_rng rng(22);
    const double rnd = sizeof(T) == 4 ? 1e-5 : 1e-9;  // rounding of the result to T
    // Random sets: uniform box, gaussian, few points, clusters.
    for (int trial = 0; trial < 12; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const std::size_t n = trial % 4 == 2 ? 5 + rng() % 20 : 300 + rng() % 700;
        const auto rot = random_rotation<D>(rng);
        std::vector<point<T, D>> pts;
        for (std::size_t i = 0; i < n; ++i) {
            std::array<double, D> z;
            for (std::size_t k = 0; k < D; ++k) {
                const double sc = 1.0 + static_cast<double>(k) * 2;
                z[k] = (trial % 4 == 1 ? gauss(rng) : unit(rng) - 0.5) * sc +
                       (trial % 4 == 3 ? static_cast<double>(i % 3) * 4 : 0.0);
            }
            std::array<double, D> x{};
            for (std::size_t r = 0; r < D; ++r)
                for (std::size_t c = 0; c < D; ++c) x[r] += rot[r][c] * z[c];
            pts.push_back(to_point<T, D>(x));
        }
        khachiyan_report ref_rep;
        const double ref_tol = sizeof(T) == 4 ? 1e-7 : 1e-9;
        const E ref = E::fit_khachiyan(pts, ref_tol, &ref_rep);
        ASSERT_EQ(ref_rep.fitted_dimension, D);
        EXPECT_LE(ref_rep.certified_ratio, 1 + ref_tol);
        for (const auto& p : pts) ASSERT_TRUE(ref.contains(p));
        const double vref = static_cast<double>(ref.volume());
        for (double tol : {0.3, 1e-2, 1e-3}) {
            khachiyan_report rep;
            const E e = E::fit_khachiyan(pts, tol, &rep);
            for (const auto& p : pts) ASSERT_TRUE(e.contains(p));
            const double v = static_cast<double>(e.volume());
            EXPECT_LE(v, vref * (1 + tol) * (1 + rnd)) << "tol " << tol;
            EXPECT_GE(v, vref / (1 + ref_tol) * (1 - rnd)) << "tol " << tol;
            EXPECT_LE(rep.certified_ratio, 1 + tol);
            EXPECT_GE(rep.certified_ratio, 1.0 - 1e-9);
        }
    }
    // A simplex: its MVEE is the image of the regular simplex's circumball, of volume
    // omega_D / V_regular(D) times the simplex's (V_regular: unit circumradius).
    for (int trial = 0; trial < 6; ++trial) {
        std::vector<point<T, D>> pts;
        Eigen::Matrix<double, int(D), int(D)> edges;
        std::array<double, D> v0{};
        for (std::size_t i = 0; i <= D; ++i) {
            std::array<double, D> x;
            for (std::size_t c = 0; c < D; ++c)
                x[c] = unit(rng) * 4 - 2 + (trial == 5 ? (sizeof(T) == 4 ? 1e3 : 1e6) : 0.0);
            const point<T, D> p = to_point<T, D>(x);
            for (std::size_t c = 0; c < D; ++c) x[c] = static_cast<double>(p[c]);
            if (i == 0)
                v0 = x;
            else
                for (std::size_t c = 0; c < D; ++c) edges(int(c), int(i - 1)) = x[c] - v0[c];
            pts.push_back(p);
        }
        double fact = 1;
        for (std::size_t k = 2; k <= D; ++k) fact *= static_cast<double>(k);
        const double simplex = std::abs(edges.determinant()) / fact;
        const double dd = static_cast<double>(D);
        const double regular = std::pow(dd + 1, (dd + 1) / 2) / (fact * std::pow(dd, dd / 2));
        const double omega = D == 2 ? pi : 4 * pi / 3;
        const double expect = omega / regular * simplex;
        const double v = static_cast<double>(E::fit_khachiyan(pts, 1e-6).volume());
        // Offsets: the centre is stored in T (a float centre at 1e3 is quantised by 6e-5).
        // Float: the frame is rounded by ~6e-8, which a thin simplex amplifies by its aspect ratio.
        const double r = trial == 5 ? (sizeof(T) == 4 ? 1e-2 : 1e-7) : (sizeof(T) == 4 ? 1e-3 : rnd);
        EXPECT_LE(v, expect * (1 + 1e-6) * (1 + r)) << "simplex trial " << trial;
        EXPECT_GE(v, expect * (1 - r)) << "simplex trial " << trial;
    }
    // Points spread over a known ellipsoid's surface (symmetric pairs, many directions):
    // the MVEE is that ellipsoid.
    for (int trial = 0; trial < 4; ++trial) {
        std::array<double, D> c;
        for (auto& x : c) x = unit(rng) * 10 - 5 + (trial == 3 ? 1e4 : 0.0);
        const E known = random_ellipsoid<T, D>(rng, 0.3, 3.0, c);
        std::vector<point<T, D>> pts;
        for (int i = 0; i < 500; ++i) {
            auto z = random_unit<D>(rng);
            pts.push_back(to_point<T, D>(surface_point(known, z)));
            for (auto& x : z) x = -x;
            pts.push_back(to_point<T, D>(surface_point(known, z)));
        }
        const double vk = static_cast<double>(known.volume());
        // At offset 1e4 a float point is rounded by up to 5e-4: the set is only near the surface.
        const double r = trial == 3 ? (sizeof(T) == 4 ? 2e-2 : 1e-8) : (sizeof(T) == 4 ? 1e-4 : 1e-9);
        // Float-rounded surface points lie only within ~1e-7 (1e-4 at the offset) of the
        // ellipsoid: nearly all are active and tolerances below that are not reachable
        // within the iteration cap (documented), so float stops at 1e-6.
        for (double tol : {1e-3, sizeof(T) == 4 ? 1e-6 : 1e-9}) {
            const E e = E::fit_khachiyan(pts, tol);
            const double v = static_cast<double>(e.volume());
            EXPECT_LE(v, vk * (1 + tol) * (1 + r)) << "surface trial " << trial << " tol " << tol;
            EXPECT_GE(v, vk * (1 - r)) << "surface trial " << trial << " tol " << tol;
            if (tol < 1e-5) {
                double cd = 0;
                for (std::size_t i = 0; i < D; ++i)
                    cd = std::max(cd, std::abs(static_cast<double>(e.center[i]) - c[i]));
                EXPECT_LE(cd, sizeof(T) == 4 ? 1e-2 * (1 + std::abs(c[0])) * 1e-3 + 1e-3
                                             : 1e-5 * (1 + std::abs(c[0])) * 1e-3 + 1e-6);
            }
        }
    }
}

// Exactly tangent pairs (double): opposite normals at a known point; separated or
// penetrating by 1e-9 of the size; and the contact value against the long double reference.
// Found by fuzzing (fuzz/operations on bvh<point, ellipsoid>, docs/fuzzing.md): merging a ball of
// the smallest normal radius (the fit of two points a denormal apart) with a far point's fit
// gave the EMPTY ellipsoid, so the bvh's root contained nothing. The first candidate (the
// tiny ball's frame scaled to reach the far point) overflows and is empty, and an empty best
// was never replaced by the finite candidates.
TEST(ellipsoid_merge, merged_contains_both_when_one_is_a_ball_of_the_smallest_normal_radius) {
    using E = ellipsoid<double, 3>;
    using P = point<double, 3>;
    const std::vector<P> tiny{P{{-0.0, 0, std::numeric_limits<double>::denorm_min()}}, P{{0, 0, 0}}};
    const std::vector<P> far{P{{1, 1, 2}}};
    const E a = E::fit_pca(std::span<const P>(tiny)), b = E::fit_pca(std::span<const P>(far));
    for (const E& m : {a.merged(b), b.merged(a)}) {
        ASSERT_FALSE(m.is_empty());
        for (const P& p : {tiny[0], tiny[1], far[0]}) EXPECT_EQ(m.distance_lower_bound(p), 0.0);
    }
}

// Found by fuzzing (fuzz/operations on bvh<point, ellipsoid>, docs/fuzzing.md): merging a ball
// of the smallest normal radius at a denormal with the fit of two points at z = -1e30 and 1e30
// gave a ball of radius 2^-1022: the candidate in the tiny ball's frame divides 1e30 by 2^-1022
// (infinity), its certified scale became NaN, std::max dropped the NaN, and the scale 0 made
// that candidate the smallest. The bvh's root then missed both far points.
TEST(ellipsoid_merge, merged_contains_both_when_the_scale_of_a_candidate_is_not_a_number) {
    using E = ellipsoid<double, 3>;
    using P = point<double, 3>;
    const std::vector<P> tiny{P{{std::numeric_limits<double>::denorm_min(), 0, 0}}};
    const std::vector<P> far{P{{0, 0, -1e30}}, P{{0, 0, 1e30}}};
    const E a = E::fit_pca(std::span<const P>(tiny)), b = E::fit_pca(std::span<const P>(far));
    for (const E& m : {a.merged(b), b.merged(a)}) {
        ASSERT_FALSE(m.is_empty());
        for (const P& p : {tiny[0], far[0], far[1]}) EXPECT_TRUE(m.contains(p)) << p;
    }
}

TEST(ellipsoid_overlap, tangent_pairs_are_decided_exactly) {
    spatial_test::seeded_rng rng(33);
    auto run = [&](auto dim_tag) {
        constexpr std::size_t D = decltype(dim_tag)::value;
        using E = ellipsoid<double, D>;
        int checked = 0;
        for (int trial = 0; trial < 300; ++trial) {
            std::array<double, D> ca;
            for (auto& x : ca) x = unit(rng) * 4 - 2;
            const double lo = trial % 3 == 0 ? 0.05 : 0.3;  // some elongated ones
            const E a = random_ellipsoid<double, D>(rng, lo, 2.0, ca);
            E b = random_ellipsoid<double, D>(rng, lo, 2.0, std::array<double, D>{});
            // p on A with outward normal n (gradient of A's form), then B's point with
            // outward normal -n placed at p.
            const auto z = random_unit<D>(rng);
            const auto p = surface_point(a, z);
            Eigen::Matrix<double, int(D), 1> n = Eigen::Matrix<double, int(D), 1>::Zero(), xb;
            for (std::size_t k = 0; k < D; ++k)
                for (std::size_t i = 0; i < D; ++i) n[int(i)] += z[k] / a.semi_axes[k] * a.axes[k][i];
            n.normalize();
            Eigen::Matrix<double, int(D), int(D)> binv = Eigen::Matrix<double, int(D), int(D)>::Zero();
            for (std::size_t k = 0; k < D; ++k) {
                Eigen::Matrix<double, int(D), 1> u;
                for (std::size_t i = 0; i < D; ++i) u[int(i)] = b.axes[k][i];
                binv += b.semi_axes[k] * b.semi_axes[k] * u * u.transpose();
            }
            xb = binv * (-n) / std::sqrt(n.dot(binv * n));
            double size = 0;
            for (std::size_t k = 0; k < D; ++k) size = std::max({size, a.semi_axes[k], b.semi_axes[k]});
            for (double delta : {0.0, 1e-9, -1e-9, 1e-6, -1e-6}) {
                for (std::size_t i = 0; i < D; ++i) b.center[i] = p[i] - xb[int(i)] + delta * size * n[int(i)];
                const bool ov = a.overlaps(b), ov2 = b.overlaps(a);
                const auto c = a.contact_function(b);
                const long double ref = pw_reference(a, b);
                EXPECT_NEAR(c.value, static_cast<double>(ref), 1e-12 * static_cast<double>(ref) + 1e-13)
                    << "trial " << trial;
                if (delta <= 0) {
                    EXPECT_TRUE(ov && ov2) << "false negative, trial " << trial << " delta " << delta
                                           << " F=" << c.value << " ref=" << static_cast<double>(ref);
                } else {
                    EXPECT_FALSE(ov || ov2)
                        << "trial " << trial << " delta " << delta << " F=" << c.value << " tol=" << c.tolerance;
                    EXPECT_GT(static_cast<double>(ref), 1.0);
                }
                ++checked;
            }
        }
        EXPECT_EQ(checked, 1500);
    };
    run(std::integral_constant<std::size_t, 2>{});
    run(std::integral_constant<std::size_t, 3>{});
}

// Random rotated pairs placed at the reference contact distance times (1 + delta):
// no false negative at all; false positives only within the tolerance band.
TYPED_TEST(ellipsoid_typed, overlaps_has_no_false_negatives_against_the_long_double_reference) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    spatial_test::seeded_rng rng(44);
    int yes = 0, no = 0, band = 0, sampled = 0;
    for (int trial = 0; trial < 400; ++trial) {
        std::array<double, D> ca;
        for (auto& x : ca) x = unit(rng) * 4 - 2;
        const E a = random_ellipsoid<T, D>(rng, 0.2, 2.0, ca);
        E b = random_ellipsoid<T, D>(rng, 0.2, 2.0, ca);
        const auto dir = random_unit<D>(rng);
        for (std::size_t i = 0; i < D; ++i) b.center[i] = static_cast<T>(ca[i] + dir[i]);
        const long double f1 = pw_reference(a, b);  // F scales with |r|^2
        const double deltas[] = {-0.5, -1e-3, -1e-9, 0.0, 1e-9, 1e-3, 0.5};
        const double delta = deltas[trial % 7];
        const double t = static_cast<double>(1 / std::sqrt(f1)) * (1 + delta);
        for (std::size_t i = 0; i < D; ++i) b.center[i] = static_cast<T>(ca[i] + t * dir[i]);
        const long double ref = pw_reference(a, b);
        const bool ov = a.overlaps(b);
        EXPECT_EQ(ov, b.overlaps(a)) << "asymmetric, trial " << trial;
        const auto c = a.contact_function(b);
        if (ref <= 1) {
            ++yes;
            ASSERT_TRUE(ov) << "false negative, trial " << trial << " ref F=" << static_cast<double>(ref)
                            << " F=" << c.value;
        } else if (ref > 1 + 1e-10L) {
            ++no;
            ASSERT_FALSE(ov) << "false positive outside the band, trial " << trial
                             << " ref F=" << static_cast<double>(ref) << " F=" << c.value << " tol=" << c.tolerance;
        } else {
            ++band;
        }
        EXPECT_LE(c.tolerance, 1e-10);
        // Sampling: a point found in both proves an overlap.
        if (trial % 7 < 2) {
            for (int s = 0; s < 400; ++s) {
                auto z = random_unit<D>(rng);
                const point<T, D> q =
                    to_point<T, D>(surface_point(a, z, std::pow(unit(rng), 1.0 / static_cast<double>(D))));
                if (a.contains(q) && b.contains(q)) {
                    ++sampled;
                    ASSERT_TRUE(ov) << "a sample lies in both, trial " << trial;
                    break;
                }
            }
        }
    }
    EXPECT_GT(yes, 100);
    EXPECT_GT(no, 100);
    EXPECT_GT(sampled, 20);
    std::cout << "  [ellipsoid D=" << D << " " << (sizeof(T) == 4 ? "float" : "double") << "] overlapping " << yes
              << ", disjoint " << no << ", within the 1e-10 band " << band << ", sample-proven " << sampled << "\n";
}

TYPED_TEST(ellipsoid_typed, ray_intervals_agree_with_point_sampling) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    spatial_test::seeded_rng rng(55);
    const E e = random_ellipsoid<T, D>(rng, 0.3, 2.0, std::array<double, D>{});
    for (int trial = 0; trial < 400; ++trial) {
        point<T, D> o, d;
        spatial_test::random_trial_ray_from_doubles(trial, rng, o, d);  // axis rays: zero and negative-zero components
        T t0 = 0, t1 = 0;
        const bool hit = e.ray_interval(o, d, t0, t1);
        if (hit) {
            ASSERT_FALSE(std::isnan(t0) || std::isnan(t1));
            ASSERT_LE(t0, t1);
            point<T, D> mid;
            for (std::size_t c = 0; c < D; ++c) mid[c] = o[c] + (t0 + t1) / 2 * d[c];
            if (t1 - t0 > T(1e-3)) {
                EXPECT_TRUE(e.contains(mid));
            }
            // The end points are on the surface.
            for (T t : {t0, t1}) {
                point<T, D> q;
                for (std::size_t c = 0; c < D; ++c) q[c] = o[c] + t * d[c];
                EXPECT_NEAR(e.quadratic_form(q), 1.0, sizeof(T) == 4 ? 1e-3 : 1e-9);
            }
        }
        bool any_inside = false;
        ASSERT_NO_FATAL_FAILURE(
            spatial_test::expect_inside_samples_in_interval(e, o, d, hit, t0, t1, trial, any_inside));
    }
}

// distance_lower_bound: <= the distance to sampled-and-refined surface points (which is >=
// the true distance), and within 1e-6 of it (it is the exact distance), 0 inside.
TYPED_TEST(ellipsoid_typed, distance_lower_bound_is_the_exact_distance) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    spatial_test::seeded_rng rng(66);
    for (int shape = 0; shape < 3; ++shape) {
        const E e = random_ellipsoid<T, D>(rng, shape == 2 ? 0.05 : 0.3, 2.0, std::array<double, D>{0.5, -0.25});
        // Surface parametrisation of the stored form: c + U^-1 diag(a) z(th, ph).
        Eigen::Matrix<double, int(D), int(D)> u;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) u(int(i), int(j)) = static_cast<double>(e.axes[i][j]);
        const Eigen::Matrix<double, int(D), int(D)> ui = u.inverse();
        auto surf = [&](double th, double ph) {
            std::array<double, D> z;
            if constexpr (D == 2)
                z = {std::cos(th), std::sin(th)};
            else
                z = {std::cos(th) * std::sin(ph), std::sin(th) * std::sin(ph), std::cos(ph)};
            std::array<double, D> x;
            for (std::size_t i = 0; i < D; ++i) {
                x[i] = static_cast<double>(e.center[i]);
                for (std::size_t k = 0; k < D; ++k)
                    x[i] += static_cast<double>(e.semi_axes[k]) * z[k] * ui(int(i), int(k));
            }
            return x;
        };
#ifdef NDEBUG
        const int queries = 40;
#else
        const int queries = 12;  // sanitizer builds: keep the run short
#endif
        for (int q = 0; q < queries; ++q) {
            point<T, D> p;
            for (std::size_t c = 0; c < D; ++c) p[c] = static_cast<T>(unit(rng) * 8 - 4);
            const double lb = static_cast<double>(e.distance_lower_bound(p));
            if (e.contains(p)) {
                EXPECT_EQ(lb, 0.0);
                continue;
            }
            auto dist = [&](double th, double ph) {
                const auto x = surf(th, ph);
                double s = 0;
                for (std::size_t c = 0; c < D; ++c)
                    s += (x[c] - static_cast<double>(p[c])) * (x[c] - static_cast<double>(p[c]));
                return std::sqrt(s);
            };
            double bt = 0, bp = 0, best = 1e300;
            const int nt = D == 2 ? 4000 : 200, np = D == 2 ? 1 : 100;
            for (int i = 0; i < nt; ++i)
                for (int j = 0; j < np; ++j) {
                    const double th = 2 * pi * i / nt, ph = D == 2 ? 0.0 : pi * (j + 0.5) / np;
                    const double dd = dist(th, ph);
                    if (dd < best) best = dd, bt = th, bp = ph;
                }
            // Local refinement: shrinking pattern search.
            for (double h = 2 * pi / nt; h > 1e-13; h /= 2) {
                bool moved = true;
                while (moved) {
                    moved = false;
                    for (int dt = -1; dt <= 1; ++dt)
                        for (int dp = (D == 2 ? 0 : -1); dp <= (D == 2 ? 0 : 1); ++dp) {
                            const double dd = dist(bt + dt * h, bp + dp * h);
                            if (dd < best) best = dd, bt += dt * h, bp += dp * h, moved = true;
                        }
                }
            }
            ASSERT_LE(lb, best * (1 + 1e-12) + 1e-12) << "not a lower bound at " << p;
            EXPECT_GE(lb, best * (1 - (sizeof(T) == 4 ? 1e-5 : 1e-9)) - 1e-9) << "not tight at " << p;
        }
    }
}

TYPED_TEST(ellipsoid_typed, merged_contains_both_and_transformed_is_exact) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    spatial_test::seeded_rng rng(77);
    const double inner = sizeof(T) == 4 ? 1 - 1e-5 : 1 - 1e-12;  // boundary samples pulled in by rounding
    for (int trial = 0; trial < 60; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        std::array<double, D> ca, cb;
        for (std::size_t i = 0; i < D; ++i) {
            ca[i] = unit(rng) * 4 - 2;
            cb[i] = trial % 5 == 0 ? ca[i] : (trial % 5 == 1 ? ca[i] + 0.01 : unit(rng) * 8 - 4);
        }
        const E a = random_ellipsoid<T, D>(rng, 0.05, 2.0, ca);
        E b = trial % 5 == 0
                  ? a
                  : random_ellipsoid<T, D>(rng, trial % 5 == 1 ? 0.01 : 0.05, trial % 5 == 1 ? 0.04 : 2.0, cb);
        const E m = a.merged(b);
        ASSERT_FALSE(m.is_empty());
        for (const E* src : {static_cast<const E*>(&a), static_cast<const E*>(&b)})
            for (int s = 0; s < 300; ++s) {
                const auto z = random_unit<D>(rng);
                const point<T, D> q = to_point<T, D>(surface_point(*src, z, inner));
                ASSERT_TRUE(src->contains(q));
                ASSERT_TRUE(m.contains(q)) << "merged misses a point of an input, q=" << m.quadratic_form(q);
            }
        const double va = static_cast<double>(a.volume()), vb = static_cast<double>(b.volume()),
                     vm = static_cast<double>(m.volume());
        EXPECT_GE(vm, std::max(va, vb) * (1 - 1e-5));
        if (trial % 5 == 0 || trial % 5 == 1) {  // identical inputs; b nested in a
            EXPECT_NEAR(vm, va, 1e-5 * va);
        }
        EXPECT_LE(frame_error(m), sizeof(T) == 4 ? 1e-6 : 1e-14);
        // transformed: moved samples inside; volume unchanged.
        rigid_transform<T, D> xf;
        const auto rot = random_rotation<D>(rng);
        for (std::size_t i = 0; i < D; ++i) {
            for (std::size_t j = 0; j < D; ++j) xf.rotation[i][j] = static_cast<T>(rot[i][j]);
            xf.translation[i] = static_cast<T>(unit(rng) * 10 - 5 + (trial % 7 == 0 ? 1e4 : 0.0));
        }
        const E moved = a.transformed(xf);
        for (int s = 0; s < 200; ++s) {
            const auto z = random_unit<D>(rng);
            const point<T, D> q = to_point<T, D>(surface_point(a, z, inner));
            ASSERT_TRUE(moved.contains(xf.apply(q))) << "q=" << moved.quadratic_form(xf.apply(q));
        }
        // Volume: unchanged up to the pad for the T-rounding of xf.apply (~eps_T |t| / a_min).
        double amin = 1e300;
        for (std::size_t k = 0; k < D; ++k) amin = std::min(amin, static_cast<double>(a.semi_axes[k]));
        const double rho = 8 * static_cast<double>(std::numeric_limits<T>::epsilon()) * (trial % 7 == 0 ? 1e4 : 10.0);
        EXPECT_GE(static_cast<double>(moved.volume()), va * (1 - 1e-6));
        EXPECT_LE(static_cast<double>(moved.volume()), va * std::pow(1 + 4 * rho / amin, double(D)) * (1 + 1e-6));
        EXPECT_LE(frame_error(moved), sizeof(T) == 4 ? 1e-6 : 1e-14);
        // The inverse motion brings it back (centre).
        const E back = moved.transformed(xf.inverse());
        for (std::size_t i = 0; i < D; ++i)
            EXPECT_NEAR(static_cast<double>(back.center[i]), static_cast<double>(a.center[i]),
                        sizeof(T) == 4 ? 1e-2 : 1e-9);
    }
}

TYPED_TEST(ellipsoid_typed, volume_and_surface_area_are_exact) {
    SPATIAL_DIMS_NAMES;
    using E = ellipsoid<T, D>;
    const double rel = sizeof(T) == 4 ? 1e-5 : 1e-9;
    E s;
    s.semi_axes.fill(T(1.5));
    EXPECT_NEAR(static_cast<double>(s.volume()), D == 2 ? pi * 2.25 : 4 * pi / 3 * 3.375, rel * 20);
    EXPECT_NEAR(static_cast<double>(s.surface_area()), D == 2 ? 2 * pi * 1.5 : 4 * pi * 2.25, rel * 30);
    const std::uint64_t seed = spatial_test::test_seed(88);
    rng_t rng(seed);
    for (int trial = 0; trial < 8; ++trial) {
        E e = random_ellipsoid<T, D>(rng, trial < 2 ? 1e-3 : 0.2, 3.0, std::array<double, D>{});
        double a[3] = {static_cast<double>(e.semi_axes[0]), static_cast<double>(e.semi_axes[1]),
                       D == 3 ? static_cast<double>(e.semi_axes[D - 1]) : 0.0};
        double v = D == 2 ? pi * a[0] * a[1] : 4 * pi / 3 * a[0] * a[1] * a[2];
        EXPECT_NEAR(static_cast<double>(e.volume()), v, rel * v);
        // Quadrature of the surface measure (midpoint rule, smooth periodic integrand).
        double area = 0;
        if constexpr (D == 2) {
            const int n = 20000;
            for (int i = 0; i < n; ++i) {
                const double t = 2 * pi * (i + 0.5) / n;
                area += std::hypot(a[0] * std::sin(t), a[1] * std::cos(t)) * 2 * pi / n;
            }
        } else {
            const int nt = 1200, np = 600;
            for (int i = 0; i < nt; ++i)
                for (int j = 0; j < np; ++j) {
                    const double th = 2 * pi * (i + 0.5) / nt, ph = pi * (j + 0.5) / np;
                    // |x_th x x_ph| for x = (a cos th sin ph, b sin th sin ph, c cos ph)
                    const double st = std::sin(th), ct = std::cos(th), sp = std::sin(ph), cp = std::cos(ph);
                    const double nx = a[1] * a[2] * ct * sp * sp, ny = a[0] * a[2] * st * sp * sp,
                                 nz = a[0] * a[1] * sp * cp;
                    area += std::sqrt(nx * nx + ny * ny + nz * nz) * (2 * pi / nt) * (pi / np);
                }
        }
        EXPECT_NEAR(static_cast<double>(e.surface_area()), area, (D == 2 ? 1e-9 : 1e-5) * area + rel * area)
            << "trial " << trial;
    }
    if constexpr (D == 3) {
        // Spheroids (closed forms) and the flat limit.
        E p;
        p.semi_axes = {T(3), T(1), T(1)};  // prolate
        const double e1 = std::sqrt(1 - 1.0 / 9);
        EXPECT_NEAR(static_cast<double>(p.surface_area()), 2 * pi * (1 + 3 / e1 * std::asin(e1)), rel * 40);
        p.semi_axes = {T(3), T(3), T(1)};  // oblate
        const double e2 = std::sqrt(1 - 1.0 / 9);
        EXPECT_NEAR(static_cast<double>(p.surface_area()), 2 * pi * 9 * (1 + (1 - e2 * e2) / e2 * std::atanh(e2)),
                    rel * 100);
        p.semi_axes = {T(2), T(1), T(0)};
        EXPECT_NEAR(static_cast<double>(p.surface_area()), 2 * pi * 2, rel * 20);
        EXPECT_EQ(p.volume(), T(0));
        p.semi_axes = {T(2), T(1), T(1e-7)};  // nearly flat: continuous with the limit
        EXPECT_NEAR(static_cast<double>(p.surface_area()), 2 * pi * 2, 1e-5);
        p.semi_axes = {T(1), T(1), T(1) - std::numeric_limits<T>::epsilon()};  // nearly a ball
        EXPECT_NEAR(static_cast<double>(p.surface_area()), 4 * pi, 1e-5);
    }
}

TEST(ellipsoid_report, fit_timings) {
    // Not a correctness test (containment is still checked): fit times and Khachiyan's work.
#ifdef NDEBUG
    const std::vector<std::size_t> sizes = {100000, 1000000};
#else
    const std::vector<std::size_t> sizes = {10000};
#endif
    rng_t rng(spatial_test::test_seed(99));
    using E = ellipsoid<double, 3>;
    for (const char* shape : {"cube", "gaussian", "sphere surface"}) {
        for (std::size_t n : sizes) {
            std::vector<point<double, 3>> pts(n);
            for (auto& p : pts) {
                const std::string s = shape;
                if (s == "cube")
                    for (std::size_t c = 0; c < 3; ++c) p[c] = unit(rng);
                else if (s == "gaussian")
                    for (std::size_t c = 0; c < 3; ++c) p[c] = gauss(rng) * static_cast<double>(c + 1);
                else {
                    const auto z = random_unit<3>(rng);
                    for (std::size_t c = 0; c < 3; ++c) p[c] = z[c] * static_cast<double>(3 - c);
                }
            }
            const auto t0 = std::chrono::steady_clock::now();
            const E pca = E::fit_pca(pts);
            const auto t1 = std::chrono::steady_clock::now();
            khachiyan_report rep;
            const E kh = E::fit_khachiyan(pts, 1e-3, &rep);
            const auto t2 = std::chrono::steady_clock::now();
            for (std::size_t i = 0; i < n; i += 97) ASSERT_TRUE(kh.contains(pts[i]) && pca.contains(pts[i]));
            std::cout << "  [ellipsoid<double,3> " << shape << " n=" << n << "] fit_pca "
                      << std::chrono::duration<double>(t1 - t0).count() * 1e3 << " ms (volume " << pca.volume()
                      << "), fit_khachiyan(1e-3) " << std::chrono::duration<double>(t2 - t1).count() * 1e3
                      << " ms (volume " << kh.volume() << ", rounds " << rep.rounds << ", active " << rep.active_points
                      << ", iterations " << rep.iterations << ", certified " << rep.certified_ratio << ")\n";
        }
    }
    // Overlap test cost.
    std::vector<E> es;
    for (int i = 0; i < 300; ++i) {
        std::array<double, 3> c;
        for (auto& x : c) x = unit(rng) * 6;
        es.push_back(random_ellipsoid<double, 3>(rng, 0.2, 1.5, c));
    }
    std::size_t pos = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& x : es)
        for (const auto& y : es) pos += x.overlaps(y);
    const auto t1 = std::chrono::steady_clock::now();
    std::cout << "  [ellipsoid<double,3>] overlaps: " << std::chrono::duration<double>(t1 - t0).count() / 90000.0 * 1e9
              << " ns/pair (" << pos << " of 90000 positive)\n";
    EXPECT_GT(pos, 300u);
}

}  // namespace
