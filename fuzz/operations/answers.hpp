#pragma once
// The operations fuzzer's query checks: each query asked of the structure and of the oracle,
// the answers compared by identity where the answer is a set (ranges: exactly the oracle's
// objects, through the handle table) and by recomputed distance where ties allow several
// right answers (kNN: any equidistant set is right, spatial_test::distances_from). Every
// returned iterator must refer to a stored object, none twice. A query the oracle rejects
// (std::invalid_argument, e.g. a ray direction whose squared length underflows) must be
// rejected by the structure too.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "answer_comparison.hpp"
#include "mirror.hpp"
#include "rejection.hpp"
#include "value_text.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/object_geometry.hpp"

namespace spatial_fuzz {

// True when the oracle rejects a query; the structure must then reject it too.
template <class Mine, class Oracle>
bool both_reject(const operation_log& log, Mine&& mine, Oracle&& oracle) {
    const bool oracle_rejects = rejects(oracle);
    const bool mine_rejects = rejects(mine);
    log.require(mine_rejects == oracle_rejects, mine_rejects ? "rejected a query the oracle answers"
                                                             : "answered a query the oracle rejects");
    return oracle_rejects;
}

// The oracle slots of a structure's answer, sorted; a finding if an object is returned twice.
template <class C, class Its>
std::vector<spatial::slot_index> oracle_slots_of(const mirror<C>& m, const operation_log& log, const Its& its) {
    const auto map = m.oracle_slots();
    std::vector<spatial::slot_index> out;
    for (const auto& it : its) out.push_back(m.oracle_slot(map, it));
    std::sort(out.begin(), out.end());
    log.require(std::adjacent_find(out.begin(), out.end()) == out.end(), "an object was returned twice");
    return out;
}
template <class Its>
std::vector<spatial::slot_index> sorted_slots(const Its& its) {
    std::vector<spatial::slot_index> out;
    for (const auto& it : its) out.push_back(it.slot());
    std::sort(out.begin(), out.end());
    return out;
}

template <class C>
void check_find_count(mirror<C>& m, const operation_log& log, const typename C::value_type& v) {
    log.trace([&] { return value_text(v); });
    log.require(m.mine().count(v) == m.oracle().count(v), "count differs from the oracle's");
    const auto found = m.mine().find(v);
    const bool oracle_found = m.oracle().find(v) != m.oracle().end();
    log.require((found != m.mine().end()) == oracle_found, "find disagrees with the oracle");
    if (oracle_found) {
        (void)oracle_slots_of(m, log, std::vector{found});
        log.require(*found == v, "find returned another value");
    }
}

// kNN, exact (eps == 0) or (1+eps)-approximate: the i-th distance at most (1+eps) times the
// true i-th (compared squared, with a relative slack of a few ulps for the rounding of (1+eps)^2).
template <class C>
void check_knn(const mirror<C>& m, const operation_log& log, const typename C::point_type& q, std::size_t k,
               typename C::scalar_type eps) {
    log.trace([&] { return value_text(q) + " k " + std::to_string(k) + " eps " + number_text(eps); });
    if (both_reject(log, [&] { (void)m.mine().find_nearest(q, k, eps); },
                    [&] { (void)m.oracle().find_nearest(q, k, eps); }))
        return;
    const auto got = eps == 0 ? m.mine().find_nearest(q, k) : m.mine().find_nearest(q, k, eps);
    const auto want = m.oracle().find_nearest(q, k);
    log.require(got.size() == want.size(), "kNN returned another number of objects");
    (void)oracle_slots_of(m, log, got);
    for (std::size_t i = 1; i < got.size(); ++i)
        log.require(spatial::object_squared_distance(*got[i - 1], q) <= spatial::object_squared_distance(*got[i], q),
                    "kNN answer not sorted by distance");
    const auto d_got = spatial_test::distances_from(q, got), d_want = spatial_test::distances_from(q, want);
    if (eps == 0) {
        log.require(d_got == d_want, "kNN distances differ from the oracle's");
        return;
    }
    const double factor = (1 + static_cast<double>(eps)) * (1 + static_cast<double>(eps)) * (1 + 1e-12);
    for (std::size_t i = 0; i < d_got.size(); ++i)
        log.require(d_got[i] <= d_want[i] * factor, "approximate kNN: a distance beyond (1 + eps) times the true one");
}

// A range query (`query(container)`: ball or box): exactly the oracle's objects, by identity.
// On a difference a traced replay (SPATIAL_FUZZ_TRACE=1) prints the objects only one side
// returned, with their squared distance to `anchor` (the ball's centre; the box's lo corner).
template <class C, class Query>
void check_same_objects(const mirror<C>& m, const operation_log& log, Query&& query, const char* what,
                        const typename C::point_type& anchor) {
    if (both_reject(log, [&] { (void)query(m.mine()); }, [&] { (void)query(m.oracle()); })) return;
    const auto got = query(m.mine());
    const auto want = query(m.oracle());
    const auto got_slots = oracle_slots_of(m, log, got), want_slots = sorted_slots(want);
    if (got_slots == want_slots) return;
    log.trace([&] {
        std::string text = "answers differ:";
        const auto map = m.oracle_slots();
        auto describe = [&](const char* side, const auto& it) {
            text += std::string("\n  ") + side + " " + value_text(*it) + ", squared distance " +
                    number_text(spatial::object_squared_distance(*it, anchor));
        };
        for (const auto& it : got)
            if (!std::binary_search(want_slots.begin(), want_slots.end(), m.oracle_slot(map, it))) describe("extra", it);
        for (const auto& it : want)
            if (!std::binary_search(got_slots.begin(), got_slots.end(), it.slot())) describe("missed", it);
        return text;
    });
    log.fail(what);
}
template <class C>
void check_ball(const mirror<C>& m, const operation_log& log, const typename C::point_type& c,
                typename C::scalar_type r) {
    log.trace([&] { return value_text(c) + " radius " + number_text(r); });
    check_same_objects(m, log, [&](const auto& container) { return container.find_in_ball(c, r); },
                       "ball query: other objects than the oracle's", c);
    if constexpr (spatial::candidate_ball<C>) {
        // The visitor form: rejects what find_in_ball rejects, else the same elements, each
        // with the squared distance its object has.
        std::vector<spatial::neighbor_candidate<typename C::scalar_type>> found;
        const bool ball_rejects = rejects([&] { (void)m.mine().find_in_ball(c, r); });
        const bool candidates_reject = rejects([&] { m.mine().find_in_ball_candidates(c, r, found); });
        log.require(ball_rejects == candidates_reject, "ball query: find_in_ball_candidates and find_in_ball differ on rejecting it");
        if (ball_rejects) return;
        const auto [as_candidates, as_iterators] = spatial_test::ball_both_ways(m.mine(), c, r);
        log.require(as_candidates == as_iterators, "ball query: find_in_ball_candidates differs from find_in_ball");
    }
}
template <class C>
void check_box(const mirror<C>& m, const operation_log& log, const typename C::point_type& lo,
               const typename C::point_type& hi) {
    log.trace([&] { return value_text(lo) + " - " + value_text(hi); });
    check_same_objects(m, log, [&](const auto& container) { return container.find_in_box(lo, hi); },
                       "box query: other objects than the oracle's", lo);
}

// A ray cast: the same hit or miss, the same hit time and hit location bit for bit (every
// structure calls the object's own intersect, compiled with -ffp-contract=off), and the
// reported object is stored and really hit at that time. `limit`: hit_time on entry.
template <class C>
void check_ray(const mirror<C>& m, const operation_log& log, const typename C::point_type& o,
               const typename C::point_type& d, typename C::scalar_type thickness, typename C::scalar_type limit) {
    log.trace([&] {
        return "origin " + value_text(o) + " direction " + value_text(d) + " thickness " + number_text(thickness) +
               " hit_time " + number_text(limit);
    });
    using info = spatial::intersect_info<typename C::point_type>;
    info a, b;
    a.hit_time = b.hit_time = limit;
    if (both_reject(log, [&] { info x = a; (void)m.mine().intersect_object(o, d, thickness, x); },
                    [&] { info x = b; (void)m.oracle().intersect_object(o, d, thickness, x); }))
        return;
    const auto hit = m.mine().intersect_object(o, d, thickness, a);
    const bool oracle_hit = m.oracle().intersect_object(o, d, thickness, b) != m.oracle().end();
    log.require((hit != m.mine().end()) == oracle_hit, "ray: hit and miss disagree with the oracle");
    log.require(a.hit_time == b.hit_time, "ray: hit time differs from the oracle's");
    for (std::size_t i = 0; i < C::dimension; ++i)
        log.require(a.hit_location[i] == b.hit_location[i], "ray: hit location differs from the oracle's");
    if (!oracle_hit) return;
    (void)oracle_slots_of(m, log, std::vector{hit});
    info again;
    again.hit_time = limit;
    log.require(hit->intersect(o, d, thickness, again) && again.hit_time == a.hit_time,
                "ray: the reported object is not hit at the reported time");
}

}  // namespace spatial_fuzz
