#pragma once
// harness::collide_index — the interface subset every collision peer is put behind, so the
// `collide` suite and the scene runner time and validate peers and our structures alike.
//
// The index holds a set of boxes identified by their position 0..n-1 in the array given
// to build(). Boxes are CLOSED: two boxes touching on a face, edge or corner overlap. This
// is the broad phase only; the exact narrow phase of non-box objects is the caller's
// (spatial::collide::narrow_phase on the objects whose boxes these are), except where a
// peer runs a caller-given exact test itself (see exact_test below).
//
// Pairs come back as (i, j) with i < j for self pairs and (i in the built set, j in the
// other set) for bipartite pairs, sorted lexicographically, each once: sets that compare
// equal with operator== when the answers agree.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "harness/configured.hpp"
#include "spatial/collide/pair_sort.hpp"

namespace harness {

struct collide_box {
    std::array<double, 3> lo{}, hi{};
};

using index_pair = std::pair<std::uint32_t, std::uint32_t>;

class collide_index : public configured {  // configuration(): harness/configured.hpp
public:
    virtual ~collide_index() = default;
    virtual std::string name() const = 0;

    // An optional exact test on (index in the built set, index in the other set or in the
    // built set): pairs whose boxes overlap are reported only if it returns true. Peers
    // that can run a callback during their traversal (Embree's rtcCollide) call it there;
    // the others call it on each candidate they found. Empty: boxes only.
    using exact_test = std::function<bool(std::uint32_t, std::uint32_t)>;

    // Builds the index over `boxes` (copied or referenced: the caller keeps `boxes` alive
    // and unchanged until the next build() or update()).
    virtual void build(std::span<const collide_box> boxes) = 0;
    // The same boxes (same count, same ids) moved: the peer's own incremental update
    // (FCL's manager update(), Embree's rtcCommitScene on changed bounds; CGAL has none and
    // simply keeps the new array, its query being a full sort-and-sweep anyway).
    virtual void update(std::span<const collide_box> boxes) = 0;
    // All pairs of distinct built boxes that overlap (and pass `exact` if given).
    virtual std::vector<index_pair> self_pairs(const exact_test& exact = {}) = 0;
    // All (i, j) with built box i overlapping others[j] (and passing `exact` if given).
    virtual std::vector<index_pair> pairs_with(std::span<const collide_box> others, const exact_test& exact = {}) = 0;
    // Bytes held by the index (what the peer allocated, when it can be counted).
    virtual std::size_t memory_bytes() const = 0;
};

// The closed-box overlap every collide_index reproduces exactly: boxes touching on a face,
// edge or corner overlap, a zero-extent box overlaps whatever contains it. O(1).
inline bool closed_boxes_overlap(const collide_box& a, const collide_box& b) {
    for (std::size_t k = 0; k < 3; ++k)
        if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
    return true;
}

// Puts pairs in the interface's answer form: sorted lexicographically, each once (peers that
// may report a pair twice rely on the unique step). Every participant (ours and the peers)
// goes through this same function, so it costs all alike (the library's, a radix sort for
// indices: spatial/collide/pair_sort.hpp).
inline void sort_unique_pairs(std::vector<index_pair>& pairs) { spatial::collide::sort_unique_pairs(pairs); }

}  // namespace harness
