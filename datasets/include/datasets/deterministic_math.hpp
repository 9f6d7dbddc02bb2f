#pragma once
// Natural logarithm and sine/cosine that return the same bits on every IEEE-754 machine.
//
// Why not <cmath>: std::log, std::sin and std::cos come from the C library, and different
// libraries (glibc, musl, Apple's libm, the MSVC CRT) round them differently in the last
// bit. The workload generators promise bit-identical output for a given seed on any
// machine, so the two transcendental functions Box–Muller needs are written here with
// operations IEEE-754 defines exactly: +, -, *, /, std::sqrt, std::floor, std::frexp and
// std::fma (fused multiply-add, correctly rounded by definition).
//
// Why every multiply-then-add is an explicit std::fma: compilers may fuse `a * b + c` into
// one FMA instruction when the target has one (g++ does so under -std=c++20 with
// -march=native, and always on AArch64), which changes the rounding. An explicit std::fma
// leaves nothing to fuse, so the result is the same with and without hardware FMA.
// (-ffast-math voids every guarantee here; do not compile the generators with it.)
//
// Accuracy is a few ulps, ample for generating workloads; the functions are not meant as
// general replacements for <cmath>.

#include <array>
#include <cmath>
#include <cstddef>

namespace datasets::detail {

// 1 / k!, folded at compile time (constant folding is exact IEEE arithmetic in g++/clang).
constexpr double inverse_factorial(int k) noexcept {
    double f = 1.0;
    for (int i = 2; i <= k; ++i) f *= static_cast<double>(i);
    return 1.0 / f;
}

// The coefficients of the series below, highest power first, folded at compile time.
// odd_reciprocals<N>(top): 1/top, 1/(top - 2), ..., N of them.
template <std::size_t N>
constexpr std::array<double, N> odd_reciprocals(int top) noexcept {
    std::array<double, N> c{};
    for (std::size_t i = 0; i < N; ++i) c[i] = 1.0 / static_cast<double>(top - 2 * static_cast<int>(i));
    return c;
}
// taylor_coefficients<N>(top): +-1/n! for n = top, top - 2, ..., N of them, signed as in the
// series of sin (odd n) and cos (even n): + where n mod 4 is 2 or 3, - where it is 0 or 1.
template <std::size_t N>
constexpr std::array<double, N> taylor_coefficients(int top) noexcept {
    std::array<double, N> c{};
    for (std::size_t i = 0; i < N; ++i) {
        const int n = top - 2 * static_cast<int>(i);
        c[i] = n % 4 >= 2 ? inverse_factorial(n) : -inverse_factorial(n);
    }
    return c;
}

// Horner's rule in y, one std::fma a step: c[0] y^(N-1) + c[1] y^(N-2) + ... + c[N-1].
template <std::size_t N>
inline double horner_fma(const std::array<double, N>& c, double y) noexcept {
    double p = c[0];
    for (std::size_t i = 1; i < N; ++i) p = std::fma(p, y, c[i]);
    return p;
}

// log(x) for finite x > 0. O(1): 12 FMAs.
// Method: x = m * 2^e with m in [sqrt(1/2), sqrt(2)); log(m) = 2 atanh(s) with
// s = (m - 1) / (m + 1), |s| <= 0.1716, summed as the odd series 2 (s + s^3/3 + s^5/5 + ...);
// the first omitted term, s^25 / 25, is below 2^-65 relative.
inline double deterministic_log(double x) noexcept {
    int e = 0;
    double m = std::frexp(x, &e);  // exact: m in [0.5, 1)
    if (m < 0.70710678118654752440) {
        m *= 2.0;  // exact
        --e;
    }
    const double s = (m - 1.0) / (m + 1.0);  // m - 1 is exact (Sterbenz)
    const double s2 = s * s;
    static constexpr auto odd = odd_reciprocals<12>(23);  // 1/23, 1/21, ..., 1/3, 1
    const double p = horner_fma(odd, s2);
    const double log_m = (2.0 * s) * p;
    constexpr double ln2 = 0.693147180559945309417232121458;
    return std::fma(static_cast<double>(e), ln2, log_m);
}

struct sin_cos {
    double sin;
    double cos;
};

// sin and cos of the angle 2*pi*turns, for turns in [0, 1). O(1): about 20 FMAs.
// Method: the quadrant q = floor(4 * turns) and the fraction f inside it are exact; f is
// folded into [0, 1/2] (sin(pi/2 - x) = cos x), so the Taylor series only ever sees
// x in [0, pi/4], where stopping after x^17 (sin) and x^18 (cos) leaves < 1e-19.
inline sin_cos deterministic_sin_cos_turns(double turns) noexcept {
    const double v = turns * 4.0;  // exact
    const double quadrant = std::floor(v);
    double f = v - quadrant;  // exact, in [0, 1)
    const bool folded = f > 0.5;
    if (folded) f = 1.0 - f;  // exact (Sterbenz)
    constexpr double half_pi = 1.57079632679489661923132169163975;
    const double x = f * half_pi;
    const double x2 = x * x;

    // -1/17!, +1/15!, ..., +1/3!: sin x = x - x^3/3! + ... = x * (1 - x2 * (1/3! - x2 * (...))):
    // the signs build the inner bracket, so sin x = x - x * x2 * ps.
    static constexpr auto sin_c = taylor_coefficients<8>(17);
    const double ps = horner_fma(sin_c, x2);
    const double sin_x = std::fma(-x * x2, ps, x);

    // +1/18!, -1/16!, ..., +1/2!: cos x = 1 - x2/2! + x2^2/4! - ... = 1 - x2 * pc.
    static constexpr auto cos_c = taylor_coefficients<9>(18);
    const double pc = horner_fma(cos_c, x2);
    const double cos_x = std::fma(-x2, pc, 1.0);

    const double s = folded ? cos_x : sin_x;
    const double c = folded ? sin_x : cos_x;
    // Rotate by whole quadrants: only sign changes and swaps, all exact.
    switch (static_cast<int>(quadrant)) {
        case 0: return {s, c};
        case 1: return {c, -s};
        case 2: return {-s, -c};
        default: return {-c, s};
    }
}

}  // namespace datasets::detail
