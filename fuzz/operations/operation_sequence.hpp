#pragma once
// The operations fuzzer's interpreter: the input is read as a sequence of container
// operations (structure-aware fuzzing, libFuzzer docs: a mutated byte changes one operation or
// one argument) applied to a structure and the brute-force oracle (mirror.hpp), every answer
// compared (answers.hpp, pair_answers.hpp), rejected inputs checked (invalid_inputs.hpp).
//
// Two mirrors: `a_`, which every query asks, and `b_`, the other container of pairs_with; a
// mutation goes to b_ one time in four. Operations a structure does not have (a pair-search
// structure has no kNN; only some have motion) are skipped. After every mutation the sizes and
// the structure's invariant check; every 16 steps and at the end the full contents. How long a
// sequence runs and how large the containers grow: sequence_limits.hpp.

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "answers.hpp"
#include "fuzz_input.hpp"
#include "hard_values.hpp"
#include "invalid_inputs.hpp"
#include "mirror.hpp"
#include "operation_log.hpp"
#include "pair_answers.hpp"
#include "sequence_limits.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/object_geometry.hpp"

namespace spatial_fuzz {

template <class C>
class operation_sequence {
public:
    using O = typename C::value_type;
    using T = typename C::scalar_type;

    operation_sequence(fuzz_input& in, std::string_view structure, const sequence_limits& limits)
        : in_(in), limits_(limits), log_(structure), a_(log_, "a"), b_(log_, "b"), values_(in) {}

    // The mutated container is checked after each mutation (queries change nothing, and a
    // structure's own check can be as slow as a rebuild); both fully every 16 steps. Skipped
    // steps (an operation the structure does not have, an insertion into a full container, a
    // clear or range erase the limits held back) are not counted as operations. With
    // limits.validate_one_in > 1 (a long soak) those checks and the query comparisons happen at
    // one step in that many (sequence_limits.hpp); the sizes are compared after every mutation,
    // and the final check always runs.
    sequence_summary run() {
        sequence_summary done;
        const std::size_t every = limits_.validate_one_in == 0 ? 1 : limits_.validate_one_in;
        for (std::size_t step = 0; step < limits_.max_steps && !in_.exhausted(); ++step) {
            const bool validated = step % every == 0;
            const std::size_t op = in_.below(operation_names.size());
            log_.begin(step, operation_names[op]);
            if (op < first_query) {
                mirror<C>& target = in_.below(4) == 0 ? b_ : a_;
                if (mutate(op, target)) ++done.operations;
                if (validated) target.check(false);
                else target.check_sizes();
                done.largest = std::max(done.largest, target.size());
            } else if (query(op, validated)) {
                ++done.operations;
            }
            if (step % (16 * every) == 16 * every - 1) {
                a_.check(true);
                b_.check(true);
            }
        }
        log_.begin(limits_.max_steps, "final check");
        a_.check(true);
        b_.check(true);
        return done;
    }

private:
    static constexpr std::size_t first_query = 9;
    static constexpr std::array<std::string_view, 19> operation_names{
        "insert",     "hinted insert", "bulk insert", "erase(pos)", "erase(value)",   "erase(first, last)",
        "update",     "update batch",  "clear",       "find/count", "kNN",            "eps-kNN",
        "ball",       "box",           "thin ray",    "thick ray",  "self pairs",     "pairs with",
        "rejected input"};

    // Whether the operation was applied.
    bool mutate(std::size_t op, mirror<C>& m) {
        const bool room = m.size() < limits_.max_size;
        switch (op) {
            case 0:
                if (!room) return false;
                m.insert(values_.object(m.anchors()));
                return true;
            case 1:
                if constexpr (spatial::spatial_container<C>) {
                    if (!room) return false;
                    const std::size_t hint = in_.below(limits_.max_size);
                    m.insert_hinted(hint, values_.object(m.anchors()));
                    return true;
                }
                return false;
            case 2:
                if (!room) return false;
                m.insert_bulk(batch(m, 1 + in_.below(in_.flag() ? 64 : 8)));
                return true;
            case 3:
                if (m.size() == 0) return false;
                m.erase_at(in_.below(m.size()));
                return true;
            case 4:
                if constexpr (spatial::spatial_container<C>) {
                    m.erase_value(existing_or_new(m));
                    return true;
                }
                return false;
            case 5:
                if constexpr (spatial::spatial_container<C>) {
                    if (held_back()) return false;
                    const std::size_t first = in_.below(m.size() + 1);
                    m.erase_range(first, in_.below(m.size() + 2));
                    return true;
                }
                return false;
            case 6:
                if constexpr (spatial::single_motion<C>) {
                    if (m.size() == 0) return false;
                    const std::size_t i = in_.below(m.size());
                    const O to = values_.object(m.anchors());
                    m.update_at(i, to, in_.flag());
                    return true;
                }
                return false;
            case 7: return update_batch(m);
            default:
                if (held_back()) return false;
                m.clear();
                return true;
        }
    }
    // A clear or range erase the limits hold back this time (reads no byte when they never do).
    bool held_back() { return in_.below(limits_.wholesale_removal_one_in) != 0; }

    // Arguments drawn from the input are drawn in order (named first), not as function
    // arguments, whose evaluation order is unspecified: an input means the same to every compiler.
    // Whether the structure has the query (a pair-search structure has no kNN, ball or rays).
    // Unvalidated (`validated` false), the structure alone answers (ask_structure).
    bool query(std::size_t op, bool validated) {
        const auto q = values_.point(a_.anchors());
        if constexpr (spatial::spatial_container<C>) {
            switch (op) {
                case 9: {
                    const O v = existing_or_new(a_);
                    if (validated) check_find_count(a_, log_, v);
                    else ask_structure([&] { return a_.mine().count(v) + (a_.mine().find(v) != a_.mine().end()); });
                    return true;
                }
                case 10: knn(q, in_.below(a_.size() + 3), T(0), validated); return true;
                case 11: {
                    const std::size_t k = in_.below(a_.size() + 3);
                    knn(q, k, values_.eps(), validated);
                    return true;
                }
                case 12: {
                    const T r = values_.size();
                    if (validated) check_ball(a_, log_, q, r);
                    else ask_structure([&] { return a_.mine().find_in_ball(q, r).size(); });
                    return true;
                }
                case 14: ray(q, T(0), validated); return true;
                case 15: ray(q, values_.size(), validated); return true;
                default: break;
            }
        }
        switch (op) {
            case 13: {
                const auto hi = values_.point(a_.anchors());
                if (validated) check_box(a_, log_, q, hi);
                else ask_structure([&] { return a_.mine().find_in_box(q, hi).size(); });
                return true;
            }
            case 16: {
                const auto f = filter();
                if (validated) check_self_pairs(a_, log_, f);
                else ask_structure([&] { return a_.mine().self_pairs(f).size(); });
                return true;
            }
            case 17: {
                const auto f = filter();
                if (validated) check_pairs_with(a_, b_, log_, f);
                else ask_structure([&] { return a_.mine().pairs_with(b_.mine(), f).size(); });
                return true;
            }
            case 18: invalid_inputs<C>(a_, log_, in_, values_).run(); return true;
            default: return false;
        }
    }

    // An unvalidated query: the structure answers alone, a rejection (std::invalid_argument,
    // which the oracle would check) allowed; a crash, an assertion or another exception is
    // still a finding. The answer's size is kept so the call cannot be optimised away.
    template <class Ask>
    void ask_structure(Ask&& ask) {
        try {
            unvalidated_answers_ += static_cast<std::size_t>(ask());
        } catch (const std::invalid_argument&) {
        }
    }

    // kNN checked against the oracle, or unvalidated with the checks that need none: as many
    // answers as k allows, sorted by distance.
    void knn(const typename C::point_type& q, std::size_t k, T eps, bool validated) {
        if (validated) return check_knn(a_, log_, q, k, eps);
        ask_structure([&] {
            const auto got = eps == 0 ? a_.mine().find_nearest(q, k) : a_.mine().find_nearest(q, k, eps);
            log_.require(got.size() == std::min(k, a_.size()), "kNN returned another number of objects");
            for (std::size_t i = 1; i < got.size(); ++i)
                log_.require(spatial::object_squared_distance(*got[i - 1], q) <= spatial::object_squared_distance(*got[i], q),
                             "kNN answer not sorted by distance");
            return got.size();
        });
    }

    bool update_batch(mirror<C>& m) {
        if constexpr (spatial::batched_motion<C>) {
            std::vector<std::size_t> indices;
            std::vector<O> moved;
            for (std::size_t i = 0; i < m.size() && i < 32; ++i)
                if (in_.flag()) indices.push_back(i), moved.push_back(values_.object(m.anchors()));
            static constexpr std::array<spatial::motion_strategy, 4> strategies{
                spatial::motion_strategy::automatic, spatial::motion_strategy::refit, spatial::motion_strategy::rebuild,
                spatial::motion_strategy::reinsert};
            m.update_batch(indices, moved, in_.pick(strategies));
            return true;
        }
        return false;
    }

    std::vector<O> batch(const mirror<C>& m, std::size_t count) {
        const auto anchors = m.anchors();
        std::vector<O> out;
        for (std::size_t k = 0; k < count; ++k) out.push_back(values_.object(anchors));
        return out;
    }
    // A stored value (half the time, when there is one) or a new one.
    O existing_or_new(const mirror<C>& m) {
        if (m.size() > 0 && in_.flag()) return *m.live()[in_.below(m.size())].mine;
        return values_.object(m.anchors());
    }
    spatial::pair_filter filter() { return in_.flag() ? spatial::pair_filter::exact : spatial::pair_filter::candidates; }
    void ray(const typename C::point_type& origin, T thickness, bool validated) {
        const auto direction = values_.direction(origin, a_.anchors());
        const T limit = values_.hit_limit();
        if (validated) return check_ray(a_, log_, origin, direction, thickness, limit);
        ask_structure([&] {
            spatial::intersect_info<typename C::point_type> info;
            info.hit_time = limit;
            return a_.mine().intersect_object(origin, direction, thickness, info) != a_.mine().end();
        });
    }

    fuzz_input& in_;
    sequence_limits limits_;
    operation_log log_;
    mirror<C> a_, b_;
    value_source<O> values_;
    std::size_t unvalidated_answers_ = 0;
};

// The entry point of a run_*.cpp: the whole input as operations on a C.
template <class C>
sequence_summary run_operations(fuzz_input& in, std::string_view structure, const sequence_limits& limits) {
    return operation_sequence<C>(in, structure, limits).run();
}

}  // namespace spatial_fuzz
