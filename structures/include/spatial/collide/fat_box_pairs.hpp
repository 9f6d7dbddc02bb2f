#pragma once
// spatial::collide::fat_box_pairs<T, D> — the candidate pairs of a moving set of boxes, kept
// from query to query: every box is grown by a margin (its "fat" box), the pairs of fat boxes
// are found once, and the following queries only re-test those candidates with the exact
// closed box test, for as long as every box still lies inside its fat box. Then two boxes
// that overlap have overlapping fat boxes, so their pair is among the candidates: the answer
// is exactly the pair set a full query gives. This is the Verlet neighbour list of molecular
// dynamics (Verlet 1967, "Computer 'experiments' on classical fluids"; the "skin" of Allen &
// Tildesley, "Computer Simulation of Liquids", §5.3) and the fat AABB of game physics
// broad phases (Box2D's and Bullet's dynamic trees enlarge each stored box by a margin), here
// over a broad phase that is rebuilt from scratch (cell_sort_grid).
//
// Why: when every box moves a little at every step (a simulation), a full query re-sorts all
// boxes into a grid, fills its cells and joins them. A candidate list turns most steps into
// one pass that checks each box against its fat box and one pass over the candidates; the
// full query runs only when some box has left its fat box.
//
// The margin is measured, not configured: on axis a it is queries_per_list times the largest
// change of any box's bound on that axis since the previous query. Where that exceeds a
// quarter of the boxes' mean edge on some axis, the boxes move too far for their size and the
// query is a full one (a list's candidates grow as the cube of the fat boxes' width). A list
// that had to be rebuilt at once (some boxes jump) makes the next backoff_queries moving
// queries full queries.
//
// Exactness does not depend on the margin's rounding: containment is checked with
// comparisons, and the candidates are the exact closed overlaps of the fat boxes.
// Cost of a query answered from the list: O(n + c) for n boxes and c candidates (at most a
// constant factor more than the pairs, for boxes of similar size); a rebuild costs one full
// query on the fat boxes plus sorting its c pairs (O(n + c), a counting sort).
// Memory: one fat box per box, two 32-bit indices per candidate, and the build's scratch
// (as many again for the unsorted candidates, two 32-bit words per box for their sort), kept
// for the next build as every buffer here is.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "spatial/collide/box_bounds.hpp"

namespace spatial::collide {

template <class T, std::size_t D>
class fat_box_pairs {
public:
    using bounds = box_bounds<T, D>;
    // The largest change of any box's bounds per axis since the previous query.
    using displacement = std::array<double, D>;
    struct statistics {
        std::size_t built = 0;        // lists built (full queries on fat boxes)
        std::size_t reused = 0;       // queries answered from a list built by an earlier one
        std::size_t candidates = 0;   // candidates of the current list
        std::array<double, D> margin{};  // the current list's margin per axis
    };

    // The margin is this many times the last per-query displacement: a list serves about
    // this many queries after the one that builds it when the boxes keep their speed. 3
    // against 1.5, 2, 4 and 6 on the boxes of the boxes_100k scene at their speed and at a
    // quarter of it (results/checks/fat_box_pairs).
    static constexpr double queries_per_list = 3;
    // No list when that margin would exceed this fraction of the mean edge on some axis: the
    // boxes move too far for their size. Fat boxes are then at most 1.5 times as wide, so the
    // candidates stay within about 1.5^D times the pairs (for boxes of similar size).
    static constexpr double largest_margin_per_edge = 0.25;
    // After a list that served a single query, this many moving queries go without one.
    static constexpr std::size_t backoff_queries = 16;

    // The boxes were renumbered (inserted, erased): no list applies any more.
    void forget() {
        live_ = false;
        backoff_ = 0;
        pairs_.clear();
        fat_.clear();
    }

    // Answers a self-pair query over `boxes` from the candidate list, emit(i, j) with i < j
    // for every overlapping pair, in increasing (i, j): from the current list if every box
    // is still inside its fat box; otherwise, when the boxes moved (`moved`: the
    // displacement since the previous query over the same boxes), from a new list that
    // `full_query(fat_boxes, collect)` builds. Returns false, having emitted nothing, when
    // neither applies (the caller then runs its full query on `boxes`).
    template <class FullQuery, class Emit>
    bool answer(const std::vector<bounds>& boxes, const std::optional<displacement>& moved, FullQuery&& full_query, Emit&& emit) {
        if (live_) {
            if (covers(boxes)) {
                ++served_;
                ++stats_.reused;
                scan(boxes, emit);
                return true;
            }
            live_ = false;
            if (served_ <= 1) backoff_ = backoff_queries;
        }
        if (!moved) return false;
        if (backoff_ > 0) {
            --backoff_;
            return false;
        }
        if (!build(boxes, *moved, full_query)) return false;
        scan(boxes, emit);
        return true;
    }

    const statistics& stats() const { return stats_; }
    std::size_t memory_bytes() const {
        return fat_.capacity() * sizeof(bounds) +
               (pairs_.capacity() + unsorted_.capacity()) * sizeof(std::pair<std::uint32_t, std::uint32_t>) +
               (starts_.capacity() + cursor_.capacity()) * sizeof(std::uint32_t);
    }

private:
    bool covers(const std::vector<bounds>& boxes) const {
        if (boxes.size() != fat_.size()) return false;
        bool inside = true;
        for (std::size_t k = 0; k < boxes.size(); ++k)
            for (std::size_t a = 0; a < D; ++a) inside &= (fat_[k].lo[a] <= boxes[k].lo[a]) & (boxes[k].hi[a] <= fat_[k].hi[a]);
        return inside;
    }
    template <class FullQuery>
    bool build(const std::vector<bounds>& boxes, const displacement& moved, FullQuery& full_query) {
        const std::size_t n = boxes.size();
        if (n < 2) return false;
        std::array<double, D> edge{};
        for (const bounds& b : boxes)
            for (std::size_t a = 0; a < D; ++a) edge[a] += static_cast<double>(b.hi[a]) - static_cast<double>(b.lo[a]);
        std::array<T, D> margin{};
        bool any = false;
        for (std::size_t a = 0; a < D; ++a) {
            const double want = queries_per_list * moved[a];
            if (!(want <= largest_margin_per_edge * edge[a] / static_cast<double>(n))) return false;
            margin[a] = static_cast<T>(want);
            any |= margin[a] > 0;
        }
        if (!any) return false;  // nothing moved: a list would die at the first motion
        fat_.resize(n);
        bool finite = true;
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t a = 0; a < D; ++a) {
                fat_[k].lo[a] = boxes[k].lo[a] - margin[a];
                fat_[k].hi[a] = boxes[k].hi[a] + margin[a];
                finite &= std::isfinite(fat_[k].lo[a]) && std::isfinite(fat_[k].hi[a]);
            }
        if (!finite) {  // near the top of T's range: the full query takes the boxes as they are
            fat_.clear();
            return false;
        }
        unsorted_.clear();
        full_query(fat_, [&](std::uint32_t i, std::uint32_t j) { unsorted_.emplace_back(std::min(i, j), std::max(i, j)); });
        sort_by_lower_index(n);
        live_ = true;
        served_ = 1;
        ++stats_.built;
        stats_.candidates = pairs_.size();
        for (std::size_t a = 0; a < D; ++a) stats_.margin[a] = static_cast<double>(margin[a]);
        return true;
    }
    // unsorted_ (each pair once, as the full query reports it) into pairs_ in increasing
    // (i, j): a counting sort by i over the n boxes, then each i's few partners by insertion
    // sort (about 1.5^D times the overlaps per box). Two passes over the candidates where the
    // radix sort of 64-bit keys (pair_sort.hpp) made six, plus its key building and unpacking.
    void sort_by_lower_index(std::size_t n) {
        starts_.assign(n + 1, 0);
        for (const auto& [i, j] : unsorted_) ++starts_[i + 1];
        for (std::size_t k = 0; k < n; ++k) starts_[k + 1] += starts_[k];
        pairs_.resize(unsorted_.size());
        cursor_.assign(starts_.begin(), starts_.end() - 1);
        for (const auto& p : unsorted_) pairs_[cursor_[p.first]++] = p;
        for (std::size_t k = 0; k < n; ++k)
            for (std::uint32_t x = starts_[k] + 1; x < starts_[k + 1]; ++x)
                for (std::uint32_t y = x; y > starts_[k] && pairs_[y].second < pairs_[y - 1].second; --y) std::swap(pairs_[y], pairs_[y - 1]);
    }
    // The candidates still overlapping, in list order: the tests are written into a block of
    // hit flags first, so the loop has no branch on the (unpredictable) outcome.
    template <class Emit>
    void scan(const std::vector<bounds>& boxes, Emit& emit) const {
        constexpr std::size_t block = 64, ahead = 32;
        std::array<std::uint32_t, block> hit;
        const std::size_t c = pairs_.size();
        for (std::size_t first = 0; first < c; first += block) {
            const std::size_t last = std::min(c, first + block);
            std::size_t found = 0;
            for (std::size_t k = first; k < last; ++k) {
                if (k + ahead < c) {  // the partner is anywhere: both cache lines a box may straddle
                    const char* next = reinterpret_cast<const char*>(&boxes[pairs_[k + ahead].second]);
                    __builtin_prefetch(next);
                    __builtin_prefetch(next + sizeof(bounds) - 1);
                }
                const bounds &x = boxes[pairs_[k].first], &y = boxes[pairs_[k].second];
                bool overlap = true;
                for (std::size_t a = 0; a < D; ++a) overlap &= !(x.hi[a] < y.lo[a]) & !(y.hi[a] < x.lo[a]);
                hit[found] = static_cast<std::uint32_t>(k);
                found += overlap;
            }
            for (std::size_t h = 0; h < found; ++h) emit(pairs_[hit[h]].first, pairs_[hit[h]].second);
        }
    }

    std::vector<bounds> fat_;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_;  // sorted, i < j
    std::vector<std::pair<std::uint32_t, std::uint32_t>> unsorted_;  // a build's full query
    std::vector<std::uint32_t> starts_, cursor_;                     // its counting sort
    bool live_ = false;
    std::size_t served_ = 0, backoff_ = 0;
    statistics stats_;
};

}  // namespace spatial::collide
