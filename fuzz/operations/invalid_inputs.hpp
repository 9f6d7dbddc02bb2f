#pragma once
// Inputs the contract says are rejected (docs/contract.md, "Errors" and "Exception safety"):
// NaN and infinite coordinates in stored values and queries, an inverted box, a zero ray
// direction or one whose squared length underflows or overflows, a negative, NaN or infinite
// radius, eps or thickness; a bulk insert or a batched motion whose LAST element is bad. Each
// must throw std::invalid_argument from the structure AND from the oracle, and leave the
// structure exactly as it was: the same objects in the same slots, the same end().

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "hard_values.hpp"
#include "mirror.hpp"
#include "rejection.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/intersect_info.hpp"

namespace spatial_fuzz {

template <class C>
class invalid_inputs {
public:
    using O = typename C::value_type;
    using Q = typename C::point_type;
    using T = typename C::scalar_type;
    static constexpr std::size_t D = C::dimension;

    invalid_inputs(mirror<C>& m, const operation_log& log, fuzz_input& in, value_source<O>& values)
        : m_(m), log_(log), in_(in), values_(values) {}

    // One rejected call, chosen by the input.
    void run() {
        const auto before = m_.state();
        if constexpr (spatial::spatial_container<C>) {
            switch (in_.below(6)) {
                case 0: stored_values(); break;
                case 1: lookups(); break;
                case 2: neighbour_queries(); break;
                case 3: rays(); break;
                case 4: motion(); break;
                default: expect_both([&](auto& c) { c.set_ray_thickness(bad_size()); }, "set_ray_thickness"); break;
            }
        } else {
            in_.flag() ? stored_values() : motion();
        }
        log_.require(m_.state() == before, "a rejected call changed the structure");
    }

private:
    // `call(container)` must throw std::invalid_argument for the structure and for the oracle.
    template <class F>
    void expect_both(F&& call, const char* what) {
        log_.trace([&] { return std::string(what); });
        log_.require(rejects([&] { call(m_.mine()); }), std::string("the structure accepted a bad ") + what);
        log_.require(rejects([&] { call(m_.oracle()); }), std::string("the oracle accepted a bad ") + what);
    }

    T bad_number() {
        static constexpr std::array<double, 3> bad{std::numeric_limits<double>::quiet_NaN(),
                                                   std::numeric_limits<double>::infinity(),
                                                   -std::numeric_limits<double>::infinity()};
        return static_cast<T>(in_.pick(bad));
    }
    T bad_size() { return in_.flag() ? bad_number() : -values_.size() - T(1e-300); }
    Q bad_point() {
        Q p = values_.point(m_.anchors());
        p[in_.below(D)] = bad_number();
        return p;
    }
    // A stored value with a NaN or infinite coordinate, or (boxes) an inverted bound.
    O bad_object() {
        if constexpr (spatial::point_object<O>) {
            return bad_point();
        } else {
            O b = values_.object(m_.anchors());
            const std::size_t i = in_.below(D);
            if (in_.flag()) (in_.flag() ? b.lo[i] : b.hi[i]) = bad_number();
            else b.lo[i] = b.hi[i] + (b.hi[i] == 0 ? T(1) : std::abs(b.hi[i]));  // lo > hi
            return b;
        }
    }

    void stored_values() {
        const O bad = bad_object();
        std::vector<O> batch;
        for (std::size_t k = in_.below(4); k > 0; --k) batch.push_back(values_.object(m_.anchors()));
        batch.push_back(bad);  // last: nothing before it may be stored either
        switch (in_.below(3)) {
            case 0: expect_both([&](auto& c) { c.insert(bad); }, "stored value"); break;
            case 1: expect_both([&](auto& c) { c.insert(batch.begin(), batch.end()); }, "bulk insert"); break;
            default:
                if constexpr (spatial::spatial_container<C>)
                    expect_both([&](auto& c) { c.insert(c.end(), bad); }, "hinted insert");
        }
    }
    void lookups() {
        const O bad = bad_object();
        switch (in_.below(3)) {
            case 0: expect_both([&](auto& c) { (void)c.find(bad); }, "find"); break;
            case 1: expect_both([&](auto& c) { (void)c.count(bad); }, "count"); break;
            default: expect_both([&](auto& c) { (void)c.erase(bad); }, "erase(value)");
        }
    }
    void neighbour_queries() {
        const Q good = values_.point(m_.anchors()), bad = bad_point();
        switch (in_.below(5)) {
            case 0: expect_both([&](auto& c) { (void)c.find_nearest(bad, 3); }, "kNN query point"); break;
            case 1: expect_both([&](auto& c) { (void)c.find_nearest(good, 3, bad_size()); }, "kNN eps"); break;
            case 2: expect_both([&](auto& c) { (void)c.find_in_ball(bad, T(1)); }, "ball centre"); break;
            case 3: expect_both([&](auto& c) { (void)c.find_in_ball(good, bad_size()); }, "ball radius"); break;
            default: expect_both([&](auto& c) { (void)c.find_in_box(in_.flag() ? bad : good, bad); }, "box corner");
        }
    }
    void rays() {
        // Directions with all components 0, 1e-200 (the squared length underflows to 0), 1e160 or
        // -1e200 (it overflows to infinity).
        static constexpr std::array<double, 4> degenerate{0.0, 1e-200, 1e160, -1e200};
        Q o = values_.point(m_.anchors()), d{};
        d[0] = T(1);
        T thickness = values_.size();
        switch (in_.below(4)) {
            case 0: o = bad_point(); break;
            case 1: d = bad_point(); break;
            case 2: {
                const T scale = static_cast<T>(in_.pick(degenerate));
                for (std::size_t i = 0; i < D; ++i) d[i] = scale;
                break;
            }
            default: thickness = bad_size();
        }
        expect_both(
            [&](auto& c) {
                spatial::intersect_info<Q> info;
                (void)c.intersect_object(o, d, thickness, info);
            },
            "ray");
    }
    void motion() {
        if (m_.size() == 0) return;
        const std::size_t i = in_.below(m_.size());
        const O bad = bad_object();
        if constexpr (spatial::single_motion<C>) {
            log_.require(rejects([&] { (void)m_.mine().update(m_.live()[i].mine, bad); }), "update accepted a bad value");
        }
        if constexpr (spatial::batched_motion<C>) {
            spatial::motion_batch<C> moves;
            for (std::size_t k = 0; k < i && k < 4; ++k) moves.emplace_back(m_.live()[k].mine, *m_.live()[k].mine);
            moves.emplace_back(m_.live()[i].mine, bad);  // last
            log_.require(rejects([&] { m_.mine().update(moves.begin(), moves.end()); }),
                         "update(first, last) accepted a bad value");
        }
    }

    mirror<C>& m_;
    const operation_log& log_;
    fuzz_input& in_;
    value_source<O>& values_;
};

}  // namespace spatial_fuzz
