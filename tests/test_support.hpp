#pragma once
// Helpers shared by the container tests: seeded generators, a user-defined point type; the
// comparison of answers by DISTANCE (not identity: ties make identity ambiguous) and by
// object signature is answer_comparison.hpp, included here.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <random>
#include <source_location>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "answer_comparison.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/objects/box.hpp"
#include "spatial/objects/sphere.hpp"
#include "spatial/objects/triangle.hpp"

namespace spatial_test {

// The 3D double point and box most tests are written for.
using P3 = spatial::point<double, 3>;
using B3 = spatial::objects::box<double, 3>;

// The type list of suites typed on the scalar alone.
using scalar_types = ::testing::Types<float, double>;

// Every stored element's iterator (handle), in iteration order.
template <class C>
std::vector<typename C::iterator> all_iterators(const C& c) {
    std::vector<typename C::iterator> v;
    for (auto it = c.begin(); it != c.end(); ++it) v.push_back(it);
    return v;
}

// The fixture of a typed suite that needs nothing of its own; the suite names it with
// `template <class T> using my_suite = spatial_test::plain_typed_suite<T>;`.
template <class T>
class plain_typed_suite : public ::testing::Test {};

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

// A user-defined BOUNDED object that is none of the ready-made ones: an axis-aligned box with a
// payload, exposing only what bounded_object requires (no squared_distance, overlaps_box or
// hull points), so containers take the documented fall-backs (its bounding box answers).
struct tagged_box {
    using scalar_type = double;
    using point_type = spatial::point<double, 3>;
    static constexpr std::size_t dimension = 3;
    double lo[3]{}, hi[3]{};
    int tag = 0;
    const double* get_min_bound() const { return lo; }
    const double* get_max_bound() const { return hi; }
    friend bool operator==(const tagged_box& a, const tagged_box& b) {
        for (int i = 0; i < 3; ++i)
            if (a.lo[i] != b.lo[i] || a.hi[i] != b.hi[i]) return false;
        return a.tag == b.tag;
    }
    // Delegates to the library's box (a user type may reuse library pieces).
    template <class Info>
    bool intersect(const point_type& o, const point_type& d, double thickness, Info& info) const {
        spatial::objects::box<double, 3> b;
        for (int i = 0; i < 3; ++i) b.lo[i] = lo[i], b.hi[i] = hi[i];
        return b.intersect(o, d, thickness, info);
    }
};

// Objects placed "at" a point, of half-size h: the contract suite's way to run the same
// scenarios on points and on objects with extent. For points, the point itself.
template <class V>
struct object_factory {
    using Q = V;
    static V at(const Q& q, double, int tag) {
        V v = q;
        if constexpr (std::is_same_v<V, tagged_point>) v.tag = tag;
        return v;
    }
    static V with_coord(V v, std::size_t i, double x) {
        if constexpr (std::is_same_v<V, tagged_point>) v.xyz[i] = x;
        else v[i] = static_cast<typename V::scalar_type>(x);
        return v;
    }
};
template <class T, std::size_t D>
struct object_factory<spatial::objects::box<T, D>> {
    using V = spatial::objects::box<T, D>;
    using Q = spatial::point<T, D>;
    static V at(const Q& q, double h, int) {
        V v;
        for (std::size_t i = 0; i < D; ++i) v.lo[i] = static_cast<T>(q[i] - h), v.hi[i] = static_cast<T>(q[i] + h);
        return v;
    }
    static V with_coord(V v, std::size_t i, double x) {
        v.lo[i] = v.hi[i] = static_cast<T>(x);
        return v;
    }
};
template <class T, std::size_t D>
struct object_factory<spatial::objects::sphere<T, D>> {
    using V = spatial::objects::sphere<T, D>;
    using Q = spatial::point<T, D>;
    static V at(const Q& q, double h, int) { return V(q, static_cast<T>(h)); }
    static V with_coord(const V& v, std::size_t i, double x) {
        Q c = v.center();
        c[i] = static_cast<T>(x);
        return V(c, v.radius());
    }
};
template <class T, std::size_t D>
struct object_factory<spatial::objects::triangle<T, D>> {
    using V = spatial::objects::triangle<T, D>;
    using Q = spatial::point<T, D>;
    // A small triangle containing q (q = a/4 + b/4 + c/2). In 3D it is tilted (normal along
    // (-1, -1, 2)) so that axis-parallel rays through q are not in its plane.
    static V at(const Q& q, double h, int) {
        const double off[3][3] = {{-h, -h, -h}, {h, -h, 0}, {0, h, h / 2}};
        Q p[3] = {q, q, q};
        for (int k = 0; k < 3; ++k)
            for (std::size_t i = 0; i < D; ++i) p[k][i] = static_cast<T>(q[i] + off[k][i]);
        return V(p[0], p[1], p[2]);
    }
    static V with_coord(const V& v, std::size_t i, double x) {
        Q p[3] = {v.vertex(0), v.vertex(1), v.vertex(2)};
        for (auto& pk : p) pk[i] = static_cast<T>(x);
        return V(p[0], p[1], p[2]);
    }
};
template <>
struct object_factory<tagged_box> {
    using Q = spatial::point<double, 3>;
    static tagged_box at(const Q& q, double h, int tag) {
        tagged_box b;
        for (int i = 0; i < 3; ++i) b.lo[i] = q[i] - h, b.hi[i] = q[i] + h;
        b.tag = tag;
        return b;
    }
    static tagged_box with_coord(tagged_box b, std::size_t i, double x) {
        b.lo[i] = b.hi[i] = x;
        return b;
    }
};

// A closed icosphere: the icosahedron subdivided `levels` times, vertices on the sphere of
// `radius` around `centre`. Shared vertices are computed once, so neighbouring triangles share
// exact coordinates (what the watertightness tests need).
template <class T>
std::vector<spatial::objects::triangle<T, 3>> icosphere(int levels, double radius = 1,
                                                       const std::array<double, 3>& centre = {0, 0, 0}) {
    using V = spatial::point<T, 3>;
    const double g = (1 + std::sqrt(5.0)) / 2;
    std::vector<std::array<double, 3>> vs = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                             {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            auto key = std::minmax(a, b);
            if (auto it = mid.find(key); it != mid.end()) return it->second;
            vs.push_back({(vs[a][0] + vs[b][0]) / 2, (vs[a][1] + vs[b][1]) / 2, (vs[a][2] + vs[b][2]) / 2});
            return mid[key] = static_cast<int>(vs.size() - 1);
        };
        std::vector<std::array<int, 3>> next;
        for (auto [a, b, c] : faces) {
            const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
        }
        faces = next;
    }
    std::vector<V> pts;
    for (auto& v : vs) {
        const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        pts.push_back(V{{T(centre[0] + radius * v[0] / n), T(centre[1] + radius * v[1] / n), T(centre[2] + radius * v[2] / n)}});
    }
    std::vector<spatial::objects::triangle<T, 3>> tris;
    for (auto [a, b, c] : faces) tris.emplace_back(pts[a], pts[b], pts[c]);
    return tris;
}

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

// test_seed(fallback), logged by replay_hint for as long as it lives (what SCOPED_TRACE does,
// at the caller's line), so a test's seed and its log stay one declaration.
class logged_seed {
public:
    explicit logged_seed(std::uint64_t fallback, std::source_location where = std::source_location::current())
        : value_(test_seed(fallback)), trace_(where.file_name(), static_cast<int>(where.line()), replay_hint(value_)) {}
    operator std::uint64_t() const { return value_; }

private:
    std::uint64_t value_;
    ::testing::ScopedTrace trace_;
};

// A std::mt19937_64 seeded by a logged_seed: `seeded_rng rng(22);` stands for the test_seed,
// SCOPED_TRACE(replay_hint) and generator lines of a randomized test. (The seed is a base, not a
// member, so that it is drawn and logged before the generator is seeded with it.)
class seeded_rng : private logged_seed, public std::mt19937_64 {
public:
    explicit seeded_rng(std::uint64_t fallback, std::source_location where = std::source_location::current())
        : logged_seed(fallback, where), std::mt19937_64(static_cast<std::uint64_t>(static_cast<const logged_seed&>(*this))) {}
    std::uint64_t logged() const { return static_cast<const logged_seed&>(*this); }
};

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
    // The next n points.
    std::vector<P> take(std::size_t n) {
        std::vector<P> v;
        for (std::size_t i = 0; i < n; ++i) v.push_back(next());
        return v;
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

}  // namespace spatial_test
