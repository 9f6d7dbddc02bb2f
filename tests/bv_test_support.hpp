#pragma once
// The typed suites of the bounding-volume tests (bv, obb, kdop, ellipsoid, convex_hull): each
// runs on every scalar x dimension pair, and builds its adversarial inputs as named point sets.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial_test {

// The type parameter of the suites: a scalar and a dimension.
template <class T, std::size_t D>
struct dims {
    using scalar = T;
    static constexpr std::size_t dim = D;
};

using all_dim_types = ::testing::Types<dims<float, 2>, dims<float, 3>, dims<double, 2>, dims<double, 3>>;
// The sanitizer build runs a representative subset (CI time: SPATIAL_TEST_FULL_MATRIX=0): both
// scalars and both dimensions still appear; the release build runs all four.
#if SPATIAL_TEST_FULL_MATRIX
using dim_types = all_dim_types;
#else
using dim_types = ::testing::Types<dims<float, 2>, dims<double, 3>>;
#endif

// The fixture's names for its parameter; a suite derives its own fixture from it (the suite's
// name is the fixture's).
template <class C>
class dims_fixture : public ::testing::Test {
protected:
    using scalar_t = typename C::scalar;
    static constexpr std::size_t dim = C::dim;
    using point_t = spatial::point<scalar_t, dim>;
};

// The fixture's names as a typed test's body uses them: T (scalar), D (dimension), P (point).
#define SPATIAL_DIMS_NAMES                                       \
    using T [[maybe_unused]] = typename TestFixture::scalar_t;   \
    [[maybe_unused]] constexpr std::size_t D = TestFixture::dim; \
    using P [[maybe_unused]] = typename TestFixture::point_t

template <class T, std::size_t D>
using named_point_sets = std::vector<std::pair<std::string, std::vector<spatial::point<T, D>>>>;

// n points, coordinate d of point i being f(i, d) (called in that order: i, then d).
template <class T, std::size_t D, class F>
std::vector<spatial::point<T, D>> points_from(std::size_t n, F&& f) {
    std::vector<spatial::point<T, D>> v;
    for (std::size_t i = 0; i < n; ++i) {
        spatial::point<T, D> p;
        for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(f(i, d));
        v.push_back(p);
    }
    return v;
}

// The hard sets every fit must contain, first `n_random` uniform points in [-5, 5): one and two
// points, all equal, collinear, coplanar, offset by 1e8 and spread of 1e-12. u() draws in [0, 1).
template <class T, std::size_t D, class U>
named_point_sets<T, D> basic_hard_sets(std::size_t n_random, U&& u) {
    named_point_sets<T, D> out;
    auto make = [&](const std::string& name, std::size_t n, auto f) { out.push_back({name, points_from<T, D>(n, f)}); };
    make("random", n_random, [&](std::size_t, std::size_t) { return u() * 10 - 5; });
    make("one point", 1, [&](std::size_t, std::size_t d) { return 1.5 + static_cast<double>(d); });
    make("two points", 2, [&](std::size_t i, std::size_t d) { return static_cast<double>(i * 3 + d); });
    make("all equal", 100, [&](std::size_t, std::size_t) { return 0.25; });
    make("collinear", 200,
         [&](std::size_t i, std::size_t d) { return static_cast<double>(i) * 0.01 * static_cast<double>(d + 1); });
    make("coplanar", 200, [&](std::size_t, std::size_t d) { return d + 1 == D ? 0.5 : u(); });
    make("offset 1e8", 200, [&](std::size_t, std::size_t) { return 1e8 + u() * (sizeof(T) == 4 ? 1e3 : 1.0); });
    make("spread 1e-12", 200, [&](std::size_t, std::size_t) { return 0.5 + u() * 1e-12; });
    return out;
}

// A uniform draw in [0, 1) from the top 53 bits of rng.
inline double unit(std::mt19937_64& rng) {
    return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// A random rotation (as rows): in 2D by the angle 2 pi unit(rng); in 3D of the quaternion
// (gauss(rng) x 4) / |q|. Each suite passes its own normal draw, so its seeds keep their sets.
template <std::size_t D, class Gauss>
std::array<std::array<double, D>, D> random_rotation(std::mt19937_64& rng, Gauss&& gauss) {
    std::array<std::array<double, D>, D> m{};
    if constexpr (D == 2) {
        const double a = unit(rng) * 6.283185307179586;
        m = {{{std::cos(a), -std::sin(a)}, {std::sin(a), std::cos(a)}}};
    } else {
        double q[4], n = 0;
        for (auto& c : q) c = gauss(rng), n += c * c;
        n = std::sqrt(n);
        for (auto& c : q) c /= n;
        const double w = q[0], x = q[1], y = q[2], z = q[3];
        m = {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
              {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
              {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
    }
    return m;
}

// Every 4th ray of the ray tests is an axis ray: along axis (trial / 4) % D, its other direction
// components set to 0 (every 8th) or -0.
template <class P>
void make_axis_ray_every_4th(int trial, P& dir) {
    using T = typename P::scalar_type;
    constexpr std::size_t D = P::dimension;
    if (trial % 4 == 0)
        for (std::size_t d = 0; d < D; ++d)
            if (d != static_cast<std::size_t>(trial / 4) % D) dir[d] = trial % 8 == 0 ? T(0) : T(-0.0);
}

// The ray of trial `trial` in the ray tests: origin in [-4, 4)^D and direction in [-0.5, 0.5)^D
// from u() (drawn in the order o[0], dir[0], o[1], ...); every 4th is an axis ray whose other
// components are 0 (every 8th) or -0.
template <class P, class U>
void random_trial_ray(int trial, U&& u, P& o, P& dir) {
    using T = typename P::scalar_type;
    constexpr std::size_t D = P::dimension;
    for (std::size_t d = 0; d < D; ++d) o[d] = u() * 8 - 4, dir[d] = u() - T(0.5);
    make_axis_ray_every_4th(trial, dir);
}

// The same with the origin in [-3, 3)^D, each coordinate drawn in double from unit(rng) and
// rounded to T (the order o[0], dir[0], o[1], ...).
template <class P>
void random_trial_ray_from_doubles(int trial, std::mt19937_64& rng, P& o, P& dir) {
    using T = typename P::scalar_type;
    constexpr std::size_t D = P::dimension;
    for (std::size_t c = 0; c < D; ++c)
        o[c] = static_cast<T>(unit(rng) * 6 - 3), dir[c] = static_cast<T>(unit(rng) - 0.5);
    make_axis_ray_every_4th(trial, dir);
}

// The line o + t dir sampled at t = k / 100, |k| <= 600: a sample inside `b` means the ray hit
// (`hit`) and lies in its interval [t0, t1] up to 1e-3. `any_inside`: whether a sample was
// inside. Call it in ASSERT_NO_FATAL_FAILURE.
template <class B, class P, class T = typename P::scalar_type>
void expect_inside_samples_in_interval(const B& b, const P& o, const P& dir, bool hit, T t0, T t1, int trial,
                                       bool& any_inside) {
    constexpr std::size_t D = P::dimension;
    any_inside = false;
    for (int k = -600; k <= 600; ++k) {
        const T t = static_cast<T>(k) * T(0.01);
        P p;
        for (std::size_t c = 0; c < D; ++c) p[c] = o[c] + t * dir[c];
        if (!b.contains(p)) continue;
        any_inside = true;
        ASSERT_TRUE(hit) << "missed a line through the volume, trial " << trial;
        EXPECT_GE(t, t0 - T(1e-3));
        EXPECT_LE(t, t1 + T(1e-3));
    }
}

// An empty volume stays empty when transformed, and no ray meets it.
template <class B>
void expect_empty_stays_empty_and_is_missed(const B& e) {
    using T = typename B::scalar_type;
    constexpr std::size_t D = B::dimension;
    EXPECT_TRUE(e.transformed(spatial::rigid_transform<T, D>::identity()).is_empty());
    T t0, t1;
    spatial::point<T, D> d{};
    d[0] = 1;
    EXPECT_FALSE(e.ray_interval(spatial::point<T, D>{}, d, t0, t1));
}

// The conventions of the empty volume `e` next to a non-empty `f`: empty, containing nothing,
// no volume or area, overlapping nothing (f neither way round; f overlaps itself), merged with f
// giving f (`expect_same_as_f` checks it), empty when transformed and missed by every ray.
template <class B, class Same>
void expect_empty_conventions(const B& e, const B& f, Same&& expect_same_as_f) {
    using T = typename B::scalar_type;
    constexpr std::size_t D = B::dimension;
    EXPECT_TRUE(e.is_empty());
    EXPECT_FALSE(e.contains(spatial::point<T, D>{}));
    EXPECT_EQ(e.volume(), T(0));
    EXPECT_EQ(e.surface_area(), T(0));
    EXPECT_FALSE(e.overlaps(f));
    EXPECT_FALSE(f.overlaps(e));
    EXPECT_TRUE(f.overlaps(f));
    expect_same_as_f(e.merged(f));
    expect_empty_stays_empty_and_is_missed(e);
}

}  // namespace spatial_test
