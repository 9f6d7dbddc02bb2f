#pragma once
// spatial::motion_strategy — how a structure restores itself after many objects moved
// (bvh::update(first, last, strategy); the scene runner picks one per scene).
//
//   refit     keep the topology, recompute every volume bottom-up: O(n), cheapest per step,
//             but the tree was built for the old positions, so node overlap (and query time)
//             grows as objects drift apart from their original neighbours.
//   rebuild   build the whole structure again for the new positions: O(n log n), best
//             quality.
//   reinsert  take each moved object out and insert it again (Goldsmith & Salmon greedy
//             descent in a BVH): O(m depth) for m moved objects, quality kept locally; the
//             right choice when few objects move.
//   automatic each structure's stated rule (bvh: docs/collisions.md, motion).

#include <string_view>

namespace spatial {

enum class motion_strategy { refit, rebuild, reinsert, automatic };

constexpr std::string_view to_string(motion_strategy s) noexcept {
    switch (s) {
        case motion_strategy::refit: return "refit";
        case motion_strategy::rebuild: return "rebuild";
        case motion_strategy::reinsert: return "reinsert";
        case motion_strategy::automatic: return "automatic";
    }
    return "?";
}

}  // namespace spatial
