#pragma once
// harness::best_peer — issue 18's reference figure for a suite that sweeps its peers' settings
// (harness/tuning_sweep.hpp): our structure's figure divided by the FASTEST VALIDATED
// configuration of any peer measured in the same run, for the same figure. The suite writes
// it as a `best_peer_ratio` row (check `derived`) whose structure is that peer and whose params
// are the operation's followed by the peer configuration's every setting, so the row says
// what ours was compared with. The knn, raycast and collide suites all call it.

#include <optional>
#include <string>
#include <vector>

#include "harness/peer_registry.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {

// One structure's value of one figure (a time: smaller is better).
struct configured_figure {
    std::string structure;      // the CSV structure column
    std::string configuration;  // "" for its registry configuration, else what the sweep changed
    double value = 0;
    bool validated = false;  // its rows' check is not check::none
};

struct best_peer_figure {
    std::string structure;      // the winning peer
    std::string configuration;  // its every setting ("build_quality=high;flags=robust")
    double ratio = 0;           // ours / the peer's
};

// Among `figures`, the registry peers' (find_peer, kind "peer") validated ones with a positive value: the
// fastest, and `ours` divided by it. nullopt when `ours` is not validated or no peer qualifies.
inline std::optional<best_peer_figure> best_peer(const configured_figure& ours,
                                                 const std::vector<configured_figure>& figures) {
    if (!ours.validated) return std::nullopt;
    const configured_figure* best = nullptr;
    for (const auto& f : figures) {
        const structure_info* peer = find_peer(f.structure);
        if (!peer || peer->kind != "peer" || !f.validated || !(f.value > 0)) continue;
        if (!best || f.value < best->value) best = &f;
    }
    if (!best) return std::nullopt;
    return best_peer_figure{best->structure,
                            full_configuration(find_peer(best->structure)->settings, best->configuration),
                            ours.value / best->value};
}

}  // namespace harness
