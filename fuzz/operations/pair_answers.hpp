#pragma once
// The operations fuzzer's pair checks (collide/pairs.hpp): each pair once, sorted by slots,
// self pairs as (lower slot, higher slot); with the exact filter the pair set is the oracle's
// exactly, by identity (mapped through the handle tables); candidates must contain it (how
// many more depends on the structure's volumes, which is what the collide suite measures).

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "answer_comparison.hpp"
#include "mirror.hpp"
#include "spatial/collide/pairs.hpp"

namespace spatial_fuzz {

using slot_pairs = std::vector<spatial_test::slot_pair>;

inline std::string filter_text(spatial::pair_filter filter) {
    return filter == spatial::pair_filter::exact ? "exact" : "candidates";
}
inline void require_pair_set(const operation_log& log, const slot_pairs& got, const slot_pairs& want,
                             spatial::pair_filter filter) {
    if (filter == spatial::pair_filter::exact) {
        log.require(got == want, "exact pairs differ from the oracle's");
    } else {
        log.require(std::includes(got.begin(), got.end(), want.begin(), want.end()),
                    "candidate pairs miss an intersecting pair");
    }
}
inline void require_sorted_once(const operation_log& log, const slot_pairs& pairs) {
    log.require(std::adjacent_find(pairs.begin(), pairs.end(), std::greater_equal<>()) == pairs.end(),
                "pairs not sorted by slots, or a pair reported twice");
}

template <class C>
void check_self_pairs(const mirror<C>& m, const operation_log& log, spatial::pair_filter filter) {
    log.trace([&] { return filter_text(filter); });
    const auto pairs = m.mine().self_pairs(filter);
    const slot_pairs slots = spatial_test::slots_of(pairs);
    require_sorted_once(log, slots);
    const auto map = m.oracle_slots();
    slot_pairs got;
    for (const auto& [a, b] : slots) log.require(a < b, "a self pair not as (lower slot, higher slot)");
    for (const auto& [a, b] : pairs) {
        const spatial::slot_index x = m.oracle_slot(map, a), y = m.oracle_slot(map, b);
        got.emplace_back(std::min(x, y), std::max(x, y));
    }
    std::sort(got.begin(), got.end());
    require_pair_set(log, got, spatial_test::slots_of(m.oracle().self_pairs(spatial::pair_filter::exact)), filter);
}

// Pairs between two structures of the same type (each descends against the other where it
// can), and between a structure and the other's oracle (the generic path of pairs_between).
template <class C>
void check_pairs_with(const mirror<C>& m, const mirror<C>& other, const operation_log& log,
                      spatial::pair_filter filter) {
    log.trace([&] { return filter_text(filter); });
    const auto want = spatial_test::slots_of(m.oracle().pairs_with(other.oracle(), spatial::pair_filter::exact));
    const auto map = m.oracle_slots(), other_map = other.oracle_slots();
    const auto pairs = m.mine().pairs_with(other.mine(), filter);
    require_sorted_once(log, spatial_test::slots_of(pairs));
    slot_pairs got;
    for (const auto& [a, b] : pairs) got.emplace_back(m.oracle_slot(map, a), other.oracle_slot(other_map, b));
    std::sort(got.begin(), got.end());
    require_pair_set(log, got, want, filter);

    const auto generic = m.mine().pairs_with(other.oracle(), filter);
    require_sorted_once(log, spatial_test::slots_of(generic));
    got.clear();
    for (const auto& [a, b] : generic) got.emplace_back(m.oracle_slot(map, a), b.slot());
    std::sort(got.begin(), got.end());
    require_pair_set(log, got, want, filter);
}

}  // namespace spatial_fuzz
