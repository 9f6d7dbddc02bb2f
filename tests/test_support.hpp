#pragma once
// Helpers shared by the container tests: seeded generators, a user-defined point type,
// and comparison of answers by DISTANCE (not identity: ties make identity ambiguous).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "spatial/core/distance.hpp"
#include "spatial/core/point.hpp"

namespace spatial_test {

// A user-defined point type that models spatial::point_object WITHOUT being spatial::point:
// it carries a payload (excluded from geometry, included in equality).
struct tagged_point {
    using scalar_type = double;
    static constexpr std::size_t dimension = 3;
    double xyz[3]{};
    int tag = 0;
    double operator[](std::size_t i) const { return xyz[i]; }
    friend bool operator==(const tagged_point& a, const tagged_point& b) {
        return a.xyz[0] == b.xyz[0] && a.xyz[1] == b.xyz[1] && a.xyz[2] == b.xyz[2] && a.tag == b.tag;
    }
    template <class Info>
    bool intersect(const tagged_point& o, const tagged_point& d, double thickness, Info& info) const {
        spatial::point<double, 3> p{{xyz[0], xyz[1], xyz[2]}}, po{{o.xyz[0], o.xyz[1], o.xyz[2]}},
            pd{{d.xyz[0], d.xyz[1], d.xyz[2]}};
        spatial::intersect_info<spatial::point<double, 3>> tmp;
        tmp.hit_time = info.hit_time;
        if (!p.intersect(po, pd, thickness, tmp)) return false;
        info.hit_time = tmp.hit_time;
        for (int i = 0; i < 3; ++i) info.hit_location.xyz[i] = tmp.hit_location[i];
        return true;
    }
};

// The seed for randomized tests: SPATIAL_TEST_SEED replays a failure; otherwise a fixed
// default per test so CI is reproducible. Every test logs it via SCOPED_TRACE.
inline std::uint64_t test_seed(std::uint64_t fallback) {
    if (const char* s = std::getenv("SPATIAL_TEST_SEED")) return std::strtoull(s, nullptr, 10);
    return fallback;
}
inline std::string replay_hint(std::uint64_t seed) {
    return "seed=" + std::to_string(seed) + " (replay: SPATIAL_TEST_SEED=" + std::to_string(seed) +
           " ctest -R <test>)";
}

template <class P>
P make_point(std::initializer_list<double> c, int tag = 0) {
    P p{};
    if constexpr (std::is_same_v<P, tagged_point>) {
        std::size_t i = 0;
        for (double v : c) p.xyz[i++] = v;
        p.tag = tag;
    } else {
        std::size_t i = 0;
        for (double v : c)
            if (i < P::dimension) p[i++] = static_cast<typename P::scalar_type>(v);
    }
    return p;
}

template <class P>
void set_coord(P& p, std::size_t i, double v) {
    if constexpr (std::is_same_v<P, tagged_point>) p.xyz[i] = v;
    else p[i] = static_cast<typename P::scalar_type>(v);
}

enum class distribution { uniform, lattice, duplicates, clusters, line };

inline const char* name_of(distribution d) {
    switch (d) {
        case distribution::uniform: return "uniform";
        case distribution::lattice: return "lattice";
        case distribution::duplicates: return "duplicates";
        case distribution::clusters: return "clusters";
        case distribution::line: return "line";
    }
    return "?";
}

template <class P>
class point_source {
public:
    point_source(distribution d, std::uint64_t seed) : dist_(d), rng_(seed) {
        for (int i = 0; i < 8; ++i) centers_.push_back(raw_uniform());
        for (int i = 0; i < 12; ++i) pool_.push_back(raw_uniform());
    }
    P next() {
        switch (dist_) {
            case distribution::uniform: return raw_uniform();
            case distribution::lattice: {
                P p{};
                for (std::size_t i = 0; i < P::dimension; ++i) set_coord(p, i, static_cast<double>(rng_() % 6));
                return p;
            }
            case distribution::duplicates: return pool_[rng_() % pool_.size()];
            case distribution::clusters: {
                P p = centers_[rng_() % centers_.size()];
                for (std::size_t i = 0; i < P::dimension; ++i) set_coord(p, i, p[i] + 0.01 * gauss());
                return p;
            }
            case distribution::line: {
                const double t = unit();
                P p{};
                for (std::size_t i = 0; i < P::dimension; ++i) set_coord(p, i, t * static_cast<double>(i + 1));
                return p;
            }
        }
        return P{};
    }
    double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
    std::uint64_t bits() { return rng_(); }

private:
    P raw_uniform() {
        P p{};
        for (std::size_t i = 0; i < P::dimension; ++i) set_coord(p, i, unit());
        return p;
    }
    double gauss() {
        double s = 0;
        for (int i = 0; i < 12; ++i) s += unit();
        return s - 6;
    }
    distribution dist_;
    std::mt19937_64 rng_;
    std::vector<P> centers_, pool_;
};

// Sorted squared distances from q of a list of iterators.
template <class P, class It>
std::vector<double> distances_from(const P& q, const std::vector<It>& its) {
    std::vector<double> d;
    for (const auto& it : its) d.push_back(static_cast<double>(spatial::squared_distance(*it, q)));
    std::sort(d.begin(), d.end());
    return d;
}

// Contents of a container as a sorted list of coordinate tuples (a multiset).
template <class C>
std::vector<std::vector<double>> contents(const C& c) {
    std::vector<std::vector<double>> v;
    for (const auto& p : c) {
        std::vector<double> t;
        for (std::size_t i = 0; i < C::dimension; ++i) t.push_back(static_cast<double>(p[i]));
        v.push_back(t);
    }
    std::sort(v.begin(), v.end());
    return v;
}

}  // namespace spatial_test
