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
// The margins are measured, not configured. Each box's margin on an axis is q times the
// change of its own bounds on that axis, the larger of the last two queries' changes (a box
// mirrored back from a wall at the last query has barely moved over it, but moves as fast as
// before; without the query before, the list has a single margin, below), at least a floor
// (a fraction of the largest change's margin) and at most a cap (half the boxes' mean edge):
// a slow box gets a thin skin and a fast one a thick one, so the candidates follow the motion
// each box has (Box2D likewise sizes each proxy's fat box from its own displacement). q is
// up to max_queries_per_list, less where the typical margin would exceed a quarter of the
// mean edge (up to 3 with a single margin), and no list is built below min_queries_per_list:
// the boxes move too far for their size (a list's candidates grow as the cube of the fat
// boxes' width). When some box outruns its own margin within a few queries (motion that
// turns: a random walk), the next global_lists lists give every box the largest change's
// margin instead (a single margin for all boxes, as in the first version); then own margins
// are tried again. A list that served only the query that built it, or a refused one, makes
// the next backoff_queries moving queries full queries.
//
// Exactness does not depend on the margin's rounding: containment is checked with
// comparisons, and the candidates are the exact closed overlaps of the fat boxes.
// Cost of a query answered from the list: O(n + c) for n boxes and c candidates (at most a
// constant factor more than the pairs, for boxes of similar size); a rebuild costs one full
// query on the fat boxes plus sorting its c pairs (O(n + c), a counting sort).
// Memory: one fat box per box, two 32-bit indices per candidate, and the build's scratch
// (as many again for the unsorted candidates, two 32-bit words per box for their sort, D
// scalars per box for its changes), kept for the next build as every buffer here is.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "spatial/collide/box_bounds.hpp"

namespace spatial::collide {

template <class T, std::size_t D>
class fat_box_pairs {
public:
    using bounds = box_bounds<T, D>;
    struct statistics {
        std::size_t built = 0;        // lists built (full queries on fat boxes)
        std::size_t reused = 0;       // queries answered from a list built by an earlier one
        std::size_t candidates = 0;   // candidates of the current list
        std::array<double, D> margin{};  // the current list's smallest margin per axis (its floor)
        bool own_margins = false;        // whether its boxes' margins follow their own motion
    };

    // A box's margin is q times its last change, q chosen per list: as large as this, so
    // that a list serves about q queries after the one that builds it while the boxes keep
    // their velocity, unless the typical margin (q times the mean change; the largest with a
    // single margin) would then exceed typical_margin_per_edge times the boxes' mean edge on
    // some axis: q shrinks to fit. Below min_queries_per_list no list is built: the boxes move
    // too far for their size. 5 against 3, 4 and 6 on the boxes of the boxes_100k scene at its
    // speed, a quarter and twice it (results/checks/fat_box_pairs).
    static constexpr double max_queries_per_list = 5;
    // With a single margin, up to 3 (against 1.5, 2, 4 and 6 in the first version's sweep):
    // every box then carries the fastest one's margin.
    static constexpr double max_queries_per_single_margin_list = 3;
    // A list's build costs about two full queries: below this it does not pay.
    static constexpr double min_queries_per_list = 3;
    // The typical margin's limit, and each box's: a fast box's margin stops at twice it.
    // With typical fat boxes at most 1.5 times as wide, the candidates stay within about
    // 1.5^D times the pairs (for boxes of similar size).
    static constexpr double typical_margin_per_edge = 0.25;
    static constexpr double largest_margin_per_edge = 0.5;
    // Margins are that much larger still, relatively: boxes moving at a constant velocity
    // are exactly q changes from their fat boxes' faces after q queries, and rounding put
    // about half of those outside, ending lists a query early.
    static constexpr double rounding_allowance = 1e-3;
    // Own margins are at least this fraction of the margin the largest change gives (and at
    // most the typical margin): a box that barely moved in the last step still has some skin.
    // 0.25 against 0.5 and 1 (a single margin) in results/checks/fat_box_pairs.
    static constexpr double own_margin_floor = 0.25;
    // A list of own margins that served fewer queries than this (some box outran its margin)
    // makes the next global_lists lists use the largest change's margin for every box. 32
    // rather than 8: each retry of own margins under motion that keeps turning costs a build.
    static constexpr std::size_t own_margins_serve_at_least = 3;
    static constexpr std::size_t global_lists = 32;
    // After a list that served a single query, or a refused one, this many moving queries go
    // without one.
    static constexpr std::size_t backoff_queries = 16;

    // The boxes were renumbered (inserted, erased): no list applies any more.
    void forget() {
        live_ = false;
        backoff_ = 0;
        pairs_.clear();
        fat_.clear();
    }

    // Whether a list is live (its fat boxes are those of the boxes in the current numbering).
    bool live() const { return live_; }
    // Whether box k (a box of the current query) lies inside its fat box; for a live list, as
    // the caller gathers the boxes (one pass instead of a gather and a check). Branchless.
    bool contains(std::size_t k, const bounds& b) const {
        bool inside = true;
        for (std::size_t a = 0; a < D; ++a) {
            inside &= fat_[k].lo[a] <= b.lo[a];
            inside &= b.hi[a] <= fat_[k].hi[a];
        }
        return inside;
    }

    // Whether the coming moving queries may build a list, so that the caller keeps the
    // previous two queries' boxes for it (answer's `previous` and `before`); otherwise it
    // need not (no list is live and the backoff runs: keeping more boxes alive costs a few
    // percent there).
    bool wants_previous() const { return live_ || backoff_ <= 1; }

    // Answers a self-pair query over `boxes` from the candidate list, emit(i, j) with i < j
    // for every overlapping pair, in increasing (i, j): from the current list if `covered`
    // (every box is inside its fat box: contains() over the gather; meaningful for a live
    // list of as many boxes); otherwise, when the boxes `moved` since the previous query and
    // `previous` holds that query's boxes in the same numbering (as wants_previous() asked;
    // `before`, if not null, the boxes of the query before it), from a new list that
    // `full_query(fat_boxes, collect)` builds. Returns false, having emitted nothing, when
    // neither applies (the caller then runs its full query on `boxes`).
    // Out of line: inlined, it made the caller's full query a few percent slower even when
    // no list was live.
    template <class FullQuery, class Emit>
    [[gnu::noinline]] bool answer(const std::vector<bounds>& boxes, bool moved, const std::vector<bounds>* previous,
                                  const std::vector<bounds>* before, bool covered, FullQuery&& full_query, Emit&& emit) {
        if (live_) {
            if (covered && boxes.size() == fat_.size()) {
                ++served_;
                ++stats_.reused;
                scan(boxes, emit);
                return true;
            }
            live_ = false;
            if (list_own_ && served_ < own_margins_serve_at_least)
                global_lists_ = global_lists;  // some box outran its own margin: the largest for all
            else if (served_ <= 1)
                backoff_ = backoff_queries;
        }
        if (!moved) return false;
        if (backoff_ > 0) {
            --backoff_;
            return false;
        }
        if (!previous || previous->size() != boxes.size()) return false;
        if (before && before->size() != boxes.size()) before = nullptr;
        if (!build(boxes, *previous, before, full_query)) {
            backoff_ = backoff_queries;
            return false;
        }
        if (!list_own_ && global_lists_ > 0) --global_lists_;
        scan(boxes, emit);
        return true;
    }

    const statistics& stats() const { return stats_; }
    std::size_t memory_bytes() const {
        return fat_.capacity() * sizeof(bounds) +
               (pairs_.capacity() + unsorted_.capacity()) * sizeof(std::pair<std::uint32_t, std::uint32_t>) +
               (starts_.capacity() + cursor_.capacity()) * sizeof(std::uint32_t) + changes_.capacity() * sizeof(std::array<T, D>);
    }

private:
    // A new list from the boxes' change since the previous query; false (no list) when the
    // boxes move too far for their size, did not move, or the fat boxes would overflow.
    template <class FullQuery>
    bool build(const std::vector<bounds>& boxes, const std::vector<bounds>& previous, const std::vector<bounds>* before,
               FullQuery& full_query) {
        const std::size_t n = boxes.size();
        if (n < 2) return false;
        // Own margins need the last two queries' changes: from one, a box that bounced in it
        // would look slow (the first list of a run, or after a backoff, has a single margin).
        const bool own = global_lists_ == 0 && before;
        // A box's change on an axis: the largest change of its bounds over the last query, and
        // for own margins over the one before too (a box that bounced off a wall at the last
        // query has barely moved over it, but still moves as fast). A single margin takes the
        // largest over all boxes, which one query gives.
        auto change = [&](std::size_t k, std::size_t a) {
            const T last = std::max(std::abs(boxes[k].lo[a] - previous[k].lo[a]), std::abs(boxes[k].hi[a] - previous[k].hi[a]));
            if (!own) return last;
            return std::max({last, std::abs(previous[k].lo[a] - (*before)[k].lo[a]), std::abs(previous[k].hi[a] - (*before)[k].hi[a])});
        };
        // Per axis: the boxes' mean edge, and the largest and the mean change of a box. Own
        // margins keep each box's change for the fat boxes' pass, which then reads one array
        // instead of the three sets of boxes again. (Fat boxes reaching ahead of each box's
        // motion only, not behind it, as Box2D's dynamic tree predicts a proxy's displacement,
        // ended nearly every list at once on boxes_100k: boxes turning back at a wall leave
        // them; results/checks/scene_step.)
        std::array<double, D> edge{}, largest{}, mean{};
        if (own) changes_.resize(n);
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t a = 0; a < D; ++a) {
                edge[a] += static_cast<double>(boxes[k].hi[a]) - static_cast<double>(boxes[k].lo[a]);
                const T ck = change(k, a);
                if (own) changes_[k][a] = ck;
                const double c = static_cast<double>(ck);
                largest[a] = std::max(largest[a], c);
                mean[a] += c;
            }
        // q: the most queries a list can serve with typical margins within their limit.
        double q = own ? max_queries_per_list : max_queries_per_single_margin_list;
        bool any = false;
        for (std::size_t a = 0; a < D; ++a) {
            const double typical = own ? mean[a] / static_cast<double>(n) : largest[a];
            if (typical > 0) q = std::min(q, typical_margin_per_edge * edge[a] / static_cast<double>(n) / typical);
            any |= largest[a] > 0;
        }
        if (!(q >= min_queries_per_list)) return false;  // too fast for the boxes' size (or NaN)
        q *= 1 + rounding_allowance;
        std::array<T, D> floor{}, cap{};
        for (std::size_t a = 0; a < D; ++a) {
            const double typical = q * (own ? mean[a] / static_cast<double>(n) : largest[a]);
            floor[a] = static_cast<T>(own ? std::min(own_margin_floor * q * largest[a], typical) : typical);
            cap[a] = static_cast<T>(std::max(largest_margin_per_edge * edge[a] / static_cast<double>(n), static_cast<double>(floor[a])));
        }
        if (!any) return false;  // nothing moved: a list would die at the first motion
        fat_.resize(n);
        // Boxes are finite (checked when stored), so a fat bound can only overflow to an
        // infinity, never become a NaN: a comparison with the largest finite value sees it.
        constexpr T top = std::numeric_limits<T>::max();
        const T factor = static_cast<T>(q);
        bool finite = true;
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t a = 0; a < D; ++a) {
                // A single margin: the floor for all (no second look at the changes).
                const T m = own ? std::max(std::min(factor * changes_[k][a], cap[a]), floor[a]) : floor[a];
                fat_[k].lo[a] = boxes[k].lo[a] - m;
                fat_[k].hi[a] = boxes[k].hi[a] + m;
                finite &= -top <= fat_[k].lo[a];
                finite &= fat_[k].hi[a] <= top;
            }
        if (!finite) {  // near the top of T's range: the full query takes the boxes as they are
            fat_.clear();
            return false;
        }
        unsorted_.clear();
        starts_.assign(n + 1, 0);  // the counting sort's counts, taken as the pairs come
        full_query(fat_, [&](std::uint32_t i, std::uint32_t j) {
            const std::uint32_t lower = std::min(i, j);
            unsorted_.emplace_back(lower, std::max(i, j));
            ++starts_[lower + 1];
        });
        sort_by_lower_index(n);
        live_ = true;
        list_own_ = own;
        served_ = 1;
        ++stats_.built;
        stats_.candidates = pairs_.size();
        stats_.own_margins = own;
        for (std::size_t a = 0; a < D; ++a) stats_.margin[a] = static_cast<double>(floor[a]);
        return true;
    }
    // unsorted_ (each pair once, as the full query reports it; starts_[i + 1] counts the
    // pairs of lower index i) into pairs_ in increasing (i, j): a counting sort by i, then
    // each i's few partners by insertion sort (about 1.5^D times the overlaps per box). Two
    // passes over the candidates where the radix sort of 64-bit keys (pair_sort.hpp) made six,
    // plus its key building and unpacking. (Scattering in two steps, by blocks of 256 lower
    // indices first, was 1.1-1.2 times slower on the candidates of boxes_100k: the list's
    // 2 MB fit the L2 cache; results/checks/scene_step.)
    void sort_by_lower_index(std::size_t n) {
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
                for (std::size_t a = 0; a < D; ++a) {
                    overlap &= !(x.hi[a] < y.lo[a]);
                    overlap &= !(y.hi[a] < x.lo[a]);
                }
                hit[found] = static_cast<std::uint32_t>(k);
                found += overlap;
            }
            for (std::size_t h = 0; h < found; ++h) emit(pairs_[hit[h]].first, pairs_[hit[h]].second);
        }
    }

    std::vector<bounds> fat_;
    std::vector<std::array<T, D>> changes_;  // a build's change of each box per axis (own margins)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_;  // sorted, i < j
    std::vector<std::pair<std::uint32_t, std::uint32_t>> unsorted_;  // a build's full query
    std::vector<std::uint32_t> starts_, cursor_;                     // its counting sort
    bool live_ = false, list_own_ = false;  // a list is live; it has own margins
    std::size_t served_ = 0, backoff_ = 0;
    std::size_t global_lists_ = 0;  // lists still to build with a single margin
    statistics stats_;
};

}  // namespace spatial::collide
