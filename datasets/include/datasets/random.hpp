#pragma once
// A seeded random stream whose output is bit-identical on every machine and standard library.
//
// Why not std::uniform_real_distribution / std::normal_distribution: the standard fixes the
// engines (std::mt19937_64 produces the same sequence everywhere) but leaves the
// distributions' algorithms to the implementation, so libstdc++, libc++ and MSVC turn the
// same bits into different numbers. Here the engine supplies raw bits and every transform
// from bits to numbers is ours: uniform [0, 1) from the top 53 (double) or 24 (float) bits,
// unbiased integers by rejection, and Gaussians by Box–Muller (Box & Muller 1958) with the
// transcendental functions from deterministic_math.hpp.
//
// Sub-seeds: independent streams (data, queries, cluster centres, ...) are derived from one
// user seed with splitmix64 (Steele, Lea & Flood 2014), whose output mixing makes nearby
// inputs (seed, seed + 1) give unrelated engine seeds.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string_view>
#include <type_traits>

#include "datasets/deterministic_math.hpp"

namespace datasets {

// One splitmix64 step: a bijective 64-bit mix. O(1).
constexpr std::uint64_t splitmix64(std::uint64_t x) noexcept {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// Seed of sub-stream `stream` of the user seed `seed`. Distinct streams of one seed, and the
// same stream of distinct seeds, give unrelated values.
constexpr std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) noexcept {
    return splitmix64(splitmix64(seed) ^ splitmix64(~stream));
}

// The stream number of a text label (a workload, a mesh file name): FNV-1a (Fowler, Noll &
// Vo), the same on every standard library (std::hash is implementation-defined). Pass it to
// derive_seed as the stream. O(length).
constexpr std::uint64_t label_stream(std::string_view label) noexcept {
    std::uint64_t h = 14695981039346656037ull;
    for (const char c : label) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    return h;
}

class random_stream {
public:
    explicit random_stream(std::uint64_t seed) : engine_(seed) {}

    // 64 raw bits.
    std::uint64_t bits() { return engine_(); }

    // Uniform in [0, 1), exactly representable: k * 2^-53 (double) or k * 2^-24 (float), so
    // 1 is never returned and every value is equally likely.
    template <class T>
    T uniform01() {
        static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>,
                      "uniform01<T>: T must be float or double");
        if constexpr (std::is_same_v<T, float>) {
            return static_cast<float>(bits() >> 40) * 0x1p-24f;
        } else {
            return static_cast<double>(bits() >> 11) * 0x1p-53;
        }
    }

    // Uniform integer in [0, bound), bound > 0, without modulo bias: draws below
    // 2^64 mod bound are rejected (expected < 2 draws for any bound).
    std::uint64_t uniform_index(std::uint64_t bound) {
        const std::uint64_t threshold = (0 - bound) % bound;  // = 2^64 mod bound
        for (;;) {
            const std::uint64_t r = bits();
            if (r >= threshold) return r % bound;
        }
    }

    // Standard normal N(0, 1). Box–Muller makes two per pair of uniforms; the second is kept
    // for the next call, so the sequence depends only on the seed and the call order.
    double gaussian() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        const double u1 = 1.0 - uniform01<double>();  // (0, 1]: log is finite
        const double u2 = uniform01<double>();        // [0, 1): one full turn
        const double r = std::sqrt(-2.0 * detail::deterministic_log(u1));
        const detail::sin_cos sc = detail::deterministic_sin_cos_turns(u2);
        spare_ = r * sc.sin;
        has_spare_ = true;
        return r * sc.cos;
    }

private:
    std::mt19937_64 engine_;
    double spare_ = 0.0;
    bool has_spare_ = false;
};

// D standard normals (a uniformly random direction once divided by `length`), drawn again
// while they are all exactly 0 (u1 = 1 in each pair); `length` receives their norm (> 0), the
// squares summed in order with std::fma.
template <std::size_t D>
std::array<double, D> nonzero_gaussian_vector(random_stream& rng, double& length) {
    std::array<double, D> g{};
    length = 0.0;
    while (!(length > 0.0)) {
        double sum = 0.0;
        for (auto& x : g) {
            x = rng.gaussian();
            sum = std::fma(x, x, sum);
        }
        length = std::sqrt(sum);
    }
    return g;
}

}  // namespace datasets
