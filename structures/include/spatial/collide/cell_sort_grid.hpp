#pragma once
// spatial::collide::cell_sort_grid<T, D> — the fast broad phase for a set of boxes that is
// rebuilt from scratch at every query: a uniform grid filled by COUNTING SORT into flat
// arrays (Teschner et al. 2003, "Optimized spatial hashing for collision detection of
// deformable objects"; the sorted-cell layout of Green 2008, "Particle simulation using
// CUDA"), joined cell by cell.
//
// Why rebuild rather than maintain: after every object moved, keeping a dynamic index up to
// date costs per-object updates of pointer-linked storage; a counting sort of n boxes is two
// linear passes over contiguous arrays, so "rebuild each step" is cheaper than any
// incremental repair once a sizeable fraction of the objects moved (the scenes' case).
//
// Algorithm (one query over boxes b_0 .. b_{n-1}, closed):
//  1. Cell size h = cell_size_factor * (mean box edge), enlarged until the grid has at most
//     max_cells_per_box * n cells (so memory is O(n) whatever the data); the grid spans the
//     boxes' bounds.
//  2. Each box is entered in every cell its box overlaps: a count pass, a prefix sum, a fill
//     pass (O(n + e), e entries).
//  3. Within each cell every pair of entries is tested for closed box overlap. A pair of
//     overlapping boxes shares every cell that contains the LOWER CORNER of their
//     intersection box, max(lo_a, lo_b) per axis; it is reported only in that cell, so once,
//     without a seen-set. The cell of a coordinate is floor((x - origin) / h) clamped to
//     the grid, a monotone function of x even in floating point, so that corner's cell lies
//     in both boxes' cell ranges and the rule never drops a pair.
//     The rule costs one OR per pair: each entry carries D bits, bit i set when the cell is
//     the box's FIRST cell along axis i. Both boxes contain the cell, so max(first_a, first_b)
//     equals the cell's coordinate on axis i exactly when one of them has bit i set: the pair
//     belongs to this cell iff (bits_a | bits_b) has all D bits.
//  4. A cell of at most `block_size` entries (nearly all of them) is copied into a small
//     structure-of-arrays block and joined 4 candidates at a time with SIMD compares (AVX
//     for double, SSE for float; a scalar loop elsewhere); the per-pair work is then a few
//     compares on data in L1, and hits are recorded without a branch.
// Cost: O(n + e + sum over cells of m_c^2) with m_c entries in cell c; for boxes of similar
// size O(n + k) with k overlapping pairs. Boxes much larger than h occupy many cells (a
// heavy-tailed size distribution costs their volume in cells, bounded by the cell cap).
// Memory: O(n + cells + e) 32-bit words (64-bit entries for D > 4) plus one copy of the
// boxes, all reused across queries (buffers keep their capacity).
// Exactness: every overlap decision is the closed box test in T; the grid only decides which
// pairs are looked at, and no overlapping pair can be skipped (step 3).
//
// Several threads (self_pairs_in_slabs): the grid is cut along its LAST axis into slabs of
// whole cell layers, one per thread (boundaries at quantiles of a sample of the boxes'
// first layers, so each slab gets about as many boxes). Each slab runs steps 2-4 alone, in
// its own buffers, on the boxes that reach into it, clipped to its layers; a box cut at the
// slab's lower end keeps its first-cell bit on that axis unset there, because its real first
// layer lies below. Step 3's rule puts every pair in exactly one cell, and every cell in
// exactly one slab, so the slabs' answers are disjoint and their union is the sequential
// answer, whatever the number of slabs. Each slab's boxes are listed once for all slabs, on
// every core, each with its first cell in the slab (list_slab_members), so a slab's counting
// sort reads its list, not its boxes; extra work: boxes crossing a slab boundary are entered
// twice.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "spatial/collide/box_bounds.hpp"
#include "spatial/core/parallel.hpp"

namespace spatial::collide {

struct cell_sort_grid_config {
    // h = factor * mean box edge: 2 measured fastest on cubes of equal size (each box spans
    // about (1 + 1/2)^D cells, cells hold few entries); see docs/collisions.md, collision_grid.
    double cell_size_factor = 2.0;
    // At most this many cells per box (memory stays O(n) for sparse or spread-out data).
    double max_cells_per_box = 4.0;
};

template <class T, std::size_t D>
class cell_sort_grid {
public:
    using bounds = box_bounds<T, D>;
    struct query_stats {
        std::size_t cells = 0;            // cells of the grid
        std::size_t entries = 0;          // (cell, box) entries: sum of cells spanned by boxes
        std::size_t candidate_tests = 0;  // pairs of entries looked at inside cells
        double cell_size = 0;
    };

    explicit cell_sort_grid(cell_sort_grid_config config = {}) : config_(config) {}

    // Calls emit(i, j) (i != j, box indices, in no particular but deterministic order) once
    // for every pair of overlapping boxes.
    template <class Emit>
    void self_pairs(const std::vector<bounds>& boxes, Emit&& emit) {
        run(boxes, boxes.size(), [&](std::uint32_t a, std::uint32_t b) { emit(a, b); });
    }
    // Calls emit(i, j) once for every overlapping pair of a[i] and b[j]: one grid over both
    // sets, where only pairs from different sets are reported.
    template <class Emit>
    void bipartite_pairs(const std::vector<bounds>& a, const std::vector<bounds>& b, Emit&& emit) {
        // With one set empty, run() would take the other for a self-pair query (split == n)
        // and emit indices into the empty set (found by fuzzing, docs/fuzzing.md).
        if (a.empty() || b.empty()) {
            stats_ = {};
            return;
        }
        combined_.assign(a.begin(), a.end());
        combined_.insert(combined_.end(), b.begin(), b.end());
        const auto na = static_cast<std::uint32_t>(a.size());
        run(combined_, a.size(), [&](std::uint32_t x, std::uint32_t y) {
            if (x < na) emit(x, y - na);
            else emit(y, x - na);
        });
    }

    // The self pairs found on up to `slabs` threads (see the header: the grid cut into slabs
    // of cell layers along the last axis). keep(i, j) is called concurrently from the slabs'
    // threads (it must be safe to call so: a read-only narrow phase is); then, on the calling
    // thread, emit(i, j) for every pair kept, i != j, each once, slab by slab in an order
    // fixed by the slab count. The same set as self_pairs for any count.
    // The first slab runs on the calling thread, which emits its pairs as soon as it is done,
    // while the other slabs may still run (the slabs' work is never quite even).
    template <class Keep, class Emit>
    void self_pairs_in_slabs(const std::vector<bounds>& boxes, std::size_t slabs, Keep&& keep, Emit&& emit) {
        for (slab& sl : slabs_) sl.pairs.clear();
        auto emit_slab = [&](const slab& sl) {
            for (const auto& [i, j] : sl.pairs) emit(i, j);
        };
        const std::size_t count = run_slabs(
            boxes, slabs,
            [&](std::size_t k, std::uint32_t i, std::uint32_t j) {
                if (keep(i, j)) slabs_[k].pairs.emplace_back(i, j);
            },
            [&] { emit_slab(slabs_[0]); });
        for (std::size_t k = 1; k < count; ++k) emit_slab(slabs_[k]);
    }
    // The same pairs, each given to emit(k, i, j) (i != j) in the thread of the slab k that
    // found it, k < max(slabs, 1): calls of different slabs run concurrently, calls of one
    // slab one after the other, so a caller collects per slab without locks (as Embree's
    // rtcCollide calls its callback from its worker threads). No pair is buffered here.
    template <class Emit>
    void self_pairs_in_slabs_concurrently(const std::vector<bounds>& boxes, std::size_t slabs, Emit&& emit) {
        run_slabs(boxes, slabs, emit, [] {});
    }

    const query_stats& last_query_stats() const { return stats_; }
    std::size_t memory_bytes() const {
        std::size_t b = sizeof(*this) + combined_.capacity() * sizeof(bounds) +
                        member_lists_.capacity() * sizeof(std::vector<member>) + member_cells_.capacity() * sizeof(std::size_t);
        for (const auto& list : member_lists_) b += list.capacity() * sizeof(member);
        for (const slab& sl : slabs_) b += sl.memory_bytes();
        return b;
    }

private:
    // The slabs of a parallel self-pair query: emit(k, i, j) from slab k's thread, the first
    // slab on the calling thread, which then calls first_done() while the others may still
    // run. Returns the number of slabs (0 for fewer than two boxes).
    template <class Emit, class FirstDone>
    std::size_t run_slabs(const std::vector<bounds>& boxes, std::size_t slabs, Emit&& emit, FirstDone&& first_done) {
        stats_ = {};
        const std::size_t n = boxes.size();
        if (n < 2) return 0;
        check_size(n);
        layout(boxes, true);
        const std::vector<std::uint32_t> bounds_at = slab_boundaries(boxes, std::max<std::size_t>(slabs, 1));
        const std::size_t count = bounds_at.size() - 1;
        if (slabs_.size() < count) slabs_.resize(count);
        for (std::size_t k = 0; k < count; ++k) {
            slabs_[k].layer_begin = bounds_at[k];
            slabs_[k].layer_end = bounds_at[k + 1];
        }
        list_slab_members(boxes, bounds_at);
        spatial::detail::parallel_for_then(
            count,
            [&](std::size_t k) {
                slab& sl = slabs_[k];
                sort_by_corner_cell<true>(sl, boxes, k);
                fill(sl);
                join_cells<false>(sl, static_cast<std::uint32_t>(n), [&](std::uint32_t i, std::uint32_t j) { emit(k, i, j); });
            },
            first_done);
        for (std::size_t k = 0; k < count; ++k) {
            stats_.entries += slabs_[k].entry_count;
            stats_.candidate_tests += slabs_[k].candidates;
        }
        return count;
    }

    // Entry = (sorted box index << D) | first-cell bits (step 3). 32 bits while that fits.
    using entry_type = std::conditional_t<(D <= 4), std::uint32_t, std::uint64_t>;
    static constexpr entry_type axis_bits = (entry_type(1) << D) - 1;
    // Cells with at most this many entries are joined in a local block (step 4); 32 covers
    // every cell of the benchmarks' workloads, larger cells take the plain double loop.
    static constexpr std::uint32_t block_size = 32;
    static constexpr std::uint32_t lanes = 4;
    // Boxes entering at most 2 cells per axis take a table-driven path in fill(); the tables
    // have 2^D x 2^D entries, so only for small D.
    static constexpr bool small_span_tables = D <= 4;

    // boxes [0, split) and [split, n) are two sets; pairs within the second set are not
    // reported (split == n: one set, every pair).
    template <class Emit>
    void run(const std::vector<bounds>& boxes, std::size_t split, Emit&& emit) {
        stats_ = {};
        const std::size_t n = boxes.size();
        if (n < 2) return;
        check_size(n);
        layout(boxes);
        if (slabs_.empty()) slabs_.resize(1);
        slab& sl = slabs_[0];
        sl.layer_begin = 0;
        sl.layer_end = dims_[D - 1];
        sort_by_corner_cell<false>(sl, boxes);
        fill(sl);
        if (split == n) join_cells<false>(sl, static_cast<std::uint32_t>(split), emit);
        else join_cells<true>(sl, static_cast<std::uint32_t>(split), emit);
        stats_.entries = sl.entry_count;
        stats_.candidate_tests = sl.candidates;
    }
    // A pass over the boxes in input order that does tens of instructions per box (the
    // sequential count, the slab listing) waited on memory for about half its time on the
    // 2-core VMs: the hardware prefetcher did not run far enough ahead of a loop that slow.
    // So such a pass asks for the box this many bytes ahead (both ends: a box may straddle
    // two lines); results/checks/stream_prefetch has the measurements.
    static constexpr std::size_t stream_ahead_bytes = 1536;
    static void prefetch_ahead(const std::vector<bounds>& boxes, std::size_t at) {
        constexpr std::size_t ahead = stream_ahead_bytes / sizeof(bounds) + 1;
        if (at + ahead < boxes.size()) {
            const char* next = reinterpret_cast<const char*>(&boxes[at + ahead]);
            __builtin_prefetch(next);
            __builtin_prefetch(next + sizeof(bounds) - 1);
        }
    }
    static void check_size(std::size_t n) {
        if (n > std::numeric_limits<std::uint32_t>::max() || n > (std::numeric_limits<entry_type>::max() >> D))
            throw std::length_error("cell_sort_grid: too many boxes for 32-bit box indices");
    }

    // The local copy of one cell (step 4): coordinates per axis in lanes, the first-cell bits
    // (plus, for bipartite joins, bit D = "from the second set"), the caller's indices.
    // Padded by `lanes` entries that overlap nothing (lo = +inf, hi = -inf).
    struct cell_block {
        alignas(32) std::array<std::array<T, block_size + lanes>, D> lo, hi;
        alignas(16) std::array<std::uint32_t, block_size + lanes> bits;
        std::array<std::uint32_t, block_size + lanes> id;
    };
    // Set in a box's last-axis span when the box was cut at its slab's lower end: its first
    // layer lies below the slab, so no cell of the slab is its first on that axis.
    static constexpr std::uint32_t cut_below = std::uint32_t(1) << 31;
    // A box listed for a slab of a parallel query: its index and its first cell in the slab.
    struct member {
        std::uint32_t box, corner;
    };

    // The buffers of one slab of cell layers [layer_begin, layer_end) along the last axis:
    // the whole grid in a sequential query, one thread's share in a parallel one. Cells are
    // numbered from the slab's first layer. All buffers keep their capacity across queries.
    struct slab {
        std::uint32_t layer_begin = 0, layer_end = 0;
        std::size_t cells = 0, entry_count = 0, candidates = 0;
        std::vector<std::uint32_t> starts, cursors, corner, ids, sorted_corner;
        std::vector<entry_type> entries;
        std::vector<bounds> sorted;
        std::vector<std::array<std::uint32_t, D>> sorted_span;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // a parallel query's answer
        cell_block block{};  // value-initialised: padding lanes read their other axes
        // One block's hits as block positions: at most m (m - 1) / 2 pairs, plus the lanes a
        // last group writes past them.
        std::array<std::pair<std::uint32_t, std::uint32_t>, block_size * (block_size - 1) / 2 + lanes> block_hits{};

        std::size_t memory_bytes() const {
            return sizeof(*this) +
                   (starts.capacity() + cursors.capacity() + corner.capacity() + ids.capacity() +
                    sorted_corner.capacity()) *
                       sizeof(std::uint32_t) +
                   entries.capacity() * sizeof(entry_type) + sorted.capacity() * sizeof(bounds) +
                   sorted_span.capacity() * sizeof(std::array<std::uint32_t, D>) +
                   pairs.capacity() * sizeof(std::pair<std::uint32_t, std::uint32_t>);
        }
    };

    // Bit j set when candidate (x, x_next + j) passes the closed box test and belongs to this
    // cell (and, bipartite, joins the two sets).
    template <bool Bipartite>
    static unsigned candidate_lanes(const cell_block& k, std::uint32_t x, std::uint32_t y) {
        constexpr std::uint32_t need = static_cast<std::uint32_t>(axis_bits) | (Bipartite ? (1u << D) : 0u);
#if defined(__AVX__)
        if constexpr (std::is_same_v<T, double> || std::is_same_v<T, float>) {
            __m128i both;
            if constexpr (Bipartite) {
                const __m128i a = _mm_set1_epi32(static_cast<int>(k.bits[x]));
                const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&k.bits[y]));
                // axis bits OR-ed, the set bit XOR-ed: all of `need` set.
                both = _mm_or_si128(_mm_and_si128(_mm_or_si128(a, b), _mm_set1_epi32(static_cast<int>(axis_bits))),
                                    _mm_andnot_si128(_mm_set1_epi32(static_cast<int>(axis_bits)), _mm_xor_si128(a, b)));
            } else {
                both = _mm_or_si128(_mm_set1_epi32(static_cast<int>(k.bits[x])),
                                    _mm_loadu_si128(reinterpret_cast<const __m128i*>(&k.bits[y])));
            }
            const __m128i here = _mm_cmpeq_epi32(both, _mm_set1_epi32(static_cast<int>(need)));
            unsigned ok = static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(here)));
            if constexpr (std::is_same_v<T, double>) {
                __m256d m = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));  // all lanes true
                for (std::size_t i = 0; i < D; ++i) {
                    const __m256d lo_y = _mm256_loadu_pd(&k.lo[i][y]), hi_y = _mm256_loadu_pd(&k.hi[i][y]);
                    m = _mm256_and_pd(m, _mm256_cmp_pd(_mm256_set1_pd(k.hi[i][x]), lo_y, _CMP_GE_OQ));
                    m = _mm256_and_pd(m, _mm256_cmp_pd(hi_y, _mm256_set1_pd(k.lo[i][x]), _CMP_GE_OQ));
                }
                ok &= static_cast<unsigned>(_mm256_movemask_pd(m));
            } else {
                __m128 m = _mm_castsi128_ps(_mm_set1_epi32(-1));
                for (std::size_t i = 0; i < D; ++i) {
                    const __m128 lo_y = _mm_loadu_ps(&k.lo[i][y]), hi_y = _mm_loadu_ps(&k.hi[i][y]);
                    m = _mm_and_ps(m, _mm_cmp_ps(_mm_set1_ps(k.hi[i][x]), lo_y, _CMP_GE_OQ));
                    m = _mm_and_ps(m, _mm_cmp_ps(hi_y, _mm_set1_ps(k.lo[i][x]), _CMP_GE_OQ));
                }
                ok &= static_cast<unsigned>(_mm_movemask_ps(m));
            }
            return ok;
        } else
#endif
        {
            unsigned ok = 0;
            for (std::uint32_t j = 0; j < lanes; ++j) {
                const std::uint32_t b = y + j;
                bool overlap = true;
                for (std::size_t i = 0; i < D; ++i) {  // no branch: both tests always run
                    overlap &= k.lo[i][b] <= k.hi[i][x];
                    overlap &= k.lo[i][x] <= k.hi[i][b];
                }
                std::uint32_t both = (k.bits[x] | k.bits[b]) & static_cast<std::uint32_t>(axis_bits);
                if constexpr (Bipartite) both |= (k.bits[x] ^ k.bits[b]) & (1u << D);
                ok |= static_cast<unsigned>(overlap & (both == need)) << j;
            }
            return ok;
        }
    }

    // Steps 3 and 4, cell by cell. Every box test is the closed test in T (NaN cannot occur:
    // callers store finite boxes).
    template <bool Bipartite, class Emit>
    void join_cells(slab& sl, std::uint32_t split, Emit&& emit) {
        std::size_t candidates = 0;
        for (std::size_t c = 0; c < sl.cells; ++c) {
            const std::uint32_t first = sl.starts[c], last = sl.starts[c + 1];
            const std::uint32_t m = last - first;
            if (m < 2) continue;
            candidates += static_cast<std::size_t>(m) * (m - 1) / 2;
            if (m <= block_size) join_block<Bipartite>(sl, first, m, split, emit);
            else join_large<Bipartite>(sl, first, last, split, emit);
        }
        sl.candidates = candidates;
    }
    template <bool Bipartite, class Emit>
    static void join_block(slab& sl, std::uint32_t first, std::uint32_t m, std::uint32_t split, Emit& emit) {
        cell_block& k = sl.block;
        for (std::uint32_t j = 0; j < m; ++j) {
            const entry_type e = sl.entries[first + j];
            const bounds& b = sl.sorted[static_cast<std::size_t>(e >> D)];
            for (std::size_t i = 0; i < D; ++i) k.lo[i][j] = b.lo[i], k.hi[i][j] = b.hi[i];
            k.id[j] = sl.ids[static_cast<std::size_t>(e >> D)];
            k.bits[j] = static_cast<std::uint32_t>(e & axis_bits);
            if constexpr (Bipartite) k.bits[j] |= static_cast<std::uint32_t>(k.id[j] >= split) << D;
        }
        // Padding: a lower bound of +inf on one axis overlaps no finite box.
        for (std::uint32_t j = m; j < m + lanes; ++j) k.lo[0][j] = std::numeric_limits<T>::infinity();
        // Hits are recorded without a branch (a store per lane; the count advances by the
        // lane's bit), then emitted: whether 4 candidates hold a pair is unpredictable, and
        // a branch on it mispredicted about once per pair.
        std::uint32_t found = 0;
        for (std::uint32_t x = 0; x + 1 < m; ++x)
            for (std::uint32_t y = x + 1; y < m; y += lanes) {
                const unsigned hits = candidate_lanes<Bipartite>(k, x, y);
                for (std::uint32_t j = 0; j < lanes; ++j) {
                    sl.block_hits[found] = {x, y + j};
                    found += (hits >> j) & 1u;
                }
            }
        for (std::uint32_t h = 0; h < found; ++h) emit(k.id[sl.block_hits[h].first], k.id[sl.block_hits[h].second]);
    }
    template <bool Bipartite, class Emit>
    static void join_large(const slab& sl, std::uint32_t first, std::uint32_t last, std::uint32_t split, Emit& emit) {
        for (std::uint32_t x = first; x + 1 < last; ++x) {
            const entry_type ea = sl.entries[x];
            const bounds& ba = sl.sorted[static_cast<std::size_t>(ea >> D)];
            const std::uint32_t ia = sl.ids[static_cast<std::size_t>(ea >> D)];
            for (std::uint32_t y = x + 1; y < last; ++y) {
                const entry_type eb = sl.entries[y];
                const bounds& bb = sl.sorted[static_cast<std::size_t>(eb >> D)];
                const std::uint32_t ib = sl.ids[static_cast<std::size_t>(eb >> D)];
                bool here = ((ea | eb) & axis_bits) == axis_bits, apart = false;
                for (std::size_t i = 0; i < D; ++i) {  // no branch: both tests always run
                    apart |= ba.hi[i] < bb.lo[i];
                    apart |= bb.hi[i] < ba.lo[i];
                }
                if constexpr (Bipartite) here &= (ia < split) != (ib < split);
                if (here & !apart) emit(ia, ib);
            }
        }
    }
    // The boxes' common bounds and the sum of their edges over [first, last).
    struct extent {
        bounds all;
        double edge_sum = 0;
    };
    static extent measure(const std::vector<bounds>& boxes, std::size_t first, std::size_t last) {
        extent e{boxes[first], 0.0};
        for (std::size_t k = first; k < last; ++k) {
            const bounds& b = boxes[k];
            for (std::size_t i = 0; i < D; ++i) {
                e.all.lo[i] = std::min(e.all.lo[i], b.lo[i]);
                e.all.hi[i] = std::max(e.all.hi[i], b.hi[i]);
                e.edge_sum += static_cast<double>(b.hi[i]) - static_cast<double>(b.lo[i]);
            }
        }
        return e;
    }
    // A parallel query measures the boxes in this many fixed chunks (concurrently), so its
    // grid does not depend on the thread count.
    static constexpr std::size_t layout_chunks = 64;

    // Grid geometry from the boxes: origin, cell size, cells per axis. Parallel: the boxes
    // are measured in layout_chunks chunks, combined in chunk order.
    void layout(const std::vector<bounds>& boxes, bool parallel = false) {
        extent whole;
        if (parallel && boxes.size() >= 2 * layout_chunks) {
            std::array<extent, layout_chunks> part;
            const std::size_t count = boxes.size();
            spatial::detail::parallel_chunks(layout_chunks, 1, [&](std::size_t first, std::size_t last) {
                for (std::size_t k = first; k < last; ++k) part[k] = measure(boxes, k * count / layout_chunks, (k + 1) * count / layout_chunks);
            });
            whole = part[0];
            for (std::size_t k = 1; k < layout_chunks; ++k) {
                for (std::size_t i = 0; i < D; ++i) {
                    whole.all.lo[i] = std::min(whole.all.lo[i], part[k].all.lo[i]);
                    whole.all.hi[i] = std::max(whole.all.hi[i], part[k].all.hi[i]);
                }
                whole.edge_sum += part[k].edge_sum;
            }
        } else {
            whole = measure(boxes, 0, boxes.size());
        }
        const bounds& all = whole.all;
        const double edge_sum = whole.edge_sum;
        const double n = static_cast<double>(boxes.size());
        std::array<double, D> span{};
        double span_max = 0;
        for (std::size_t i = 0; i < D; ++i) {
            span[i] = static_cast<double>(all.hi[i]) - static_cast<double>(all.lo[i]);
            span_max = std::max(span_max, span[i]);
        }
        if (!std::isfinite(span_max)) throw std::overflow_error("cell_sort_grid: the boxes' bounds overflow");
        double h = config_.cell_size_factor * edge_sum / (n * static_cast<double>(D));
        const double max_cells = std::max(1.0, config_.max_cells_per_box * n);
        // A degenerate set (all points, or all boxes flat) has mean edge 0: start from the
        // cap's cell size instead.
        if (!(h > 0)) h = span_max > 0 ? span_max / std::pow(max_cells, 1.0 / static_cast<double>(D)) : 1.0;
        // Spans and edges of a few denormals give a cell size that underflows to 0 (the loop
        // below then turned it into NaN and never ended) or whose reciprocal overflows (a cell
        // index became 0 * inf = NaN): found by fuzzing, docs/fuzzing.md. The smallest normal
        // number has a finite reciprocal and still puts such a span in one cell.
        h = std::max(h, static_cast<double>(std::numeric_limits<double>::min()));
        for (;;) {
            double cells = 1;
            for (std::size_t i = 0; i < D; ++i) cells *= std::floor(span[i] / h) + 1;
            if (cells <= max_cells) break;
            h *= std::pow(cells / max_cells, 1.0 / static_cast<double>(D)) * 1.0001;
        }
        std::size_t stride = 1;
        for (std::size_t i = 0; i < D; ++i) {
            origin_[i] = all.lo[i];
            dims_[i] = static_cast<std::uint32_t>(std::floor(span[i] / h)) + 1;
            stride_[i] = stride;
            stride *= dims_[i];
        }
        inv_h_ = 1.0 / h;
        stats_.cell_size = h;
        stats_.cells = stride;
        if constexpr (small_span_tables) build_small_span_tables();
    }
    // floor((x - origin) / h) clamped to [0, dims - 1]: monotone in x. Every x is >= origin
    // (the least lower bound), so the product is >= 0 and truncation is the floor.
    std::uint32_t cell_coordinate(T x, std::size_t axis) const {
        const double c = (static_cast<double>(x) - static_cast<double>(origin_[axis])) * inv_h_;
        return static_cast<std::uint32_t>(std::min(c, static_cast<double>(dims_[axis] - 1)));
    }
    // Slab boundaries for a parallel query: layer indices 0 = b_0 < b_1 < ... < b_S = dims
    // along the last axis, S <= slabs, at quantiles of the first layers of a sample of the
    // boxes (about 4096, evenly spaced in the input), so slabs get similar box counts on
    // clustered data too. Deterministic for given boxes and slab count. O(sample log sample).
    std::vector<std::uint32_t> slab_boundaries(const std::vector<bounds>& boxes, std::size_t slabs) const {
        const std::uint32_t layers = dims_[D - 1];
        std::vector<std::uint32_t> out{0};
        if (slabs > 1 && layers > 1) {
            const std::size_t n = boxes.size(), step = std::max<std::size_t>(1, n / 4096);
            std::vector<std::uint32_t> sample;
            sample.reserve(n / step + 1);
            for (std::size_t b = 0; b < n; b += step) sample.push_back(cell_coordinate(boxes[b].lo[D - 1], D - 1));
            std::sort(sample.begin(), sample.end());
            for (std::size_t k = 1; k < slabs; ++k) {
                const std::uint32_t at = sample[k * sample.size() / slabs];
                if (at > out.back() && at < layers) out.push_back(at);
            }
        }
        out.push_back(layers);
        return out;
    }

    // Box b's cells in the slab: its first cell (linear index within the slab) and how many
    // further cells it spans per axis (the last axis clipped to the slab, cut_below set when
    // its first layer is below). Returns the number of cells, 0 when b misses the slab.
    template <bool Sliced>
    std::size_t cell_range(const slab& sl, const bounds& b, std::size_t& corner, std::array<std::uint32_t, D>& extra) const {
        corner = 0;
        std::size_t spanned = 1;
        constexpr std::size_t free_axes = Sliced ? D - 1 : D;  // the last axis first when sliced
        if constexpr (Sliced) {
            std::uint32_t first = cell_coordinate(b.lo[D - 1], D - 1), last = cell_coordinate(b.hi[D - 1], D - 1);
            if (last < sl.layer_begin || first >= sl.layer_end) return 0;
            const std::uint32_t cut = first < sl.layer_begin ? cut_below : 0;
            first = std::max(first, sl.layer_begin) - sl.layer_begin;
            last = std::min(last, sl.layer_end - 1) - sl.layer_begin;
            extra[D - 1] = (last - first) | cut;
            corner = first * stride_[D - 1];
            spanned = static_cast<std::size_t>(last - first) + 1;
        }
        for (std::size_t i = 0; i < free_axes; ++i) {
            const std::uint32_t first = cell_coordinate(b.lo[i], i), last = cell_coordinate(b.hi[i], i);
            extra[i] = last - first;
            corner += first * stride_[i];
            spanned *= static_cast<std::size_t>(extra[i]) + 1;
        }
        return spanned;
    }

    // Locality: a copy of the slab's boxes ordered by the cell of their lower corner (a
    // counting sort, O(n + cells)), so the boxes met in one cell, and in consecutive cells,
    // sit close together in memory. In the caller's (random) order every candidate test was
    // a cache miss; this halves the query time at 1e6 boxes. Sliced: only the slab's members
    // (list_slab_members: the boxes reaching into its layers, in input order), clipped to its
    // layers.
    template <bool Sliced>
    void sort_by_corner_cell(slab& sl, const std::vector<bounds>& boxes, std::size_t slab_index = 0) const {
        sl.cells = stride_[D - 1] * (sl.layer_end - sl.layer_begin);
        sl.starts.assign(sl.cells + 1, 0);
        std::size_t m = 0, total = 0;
        if constexpr (Sliced) {
            // The listing found each member's first cell: the count reads the lists only.
            for_each_member_list(slab_index, [&](const std::vector<member>& list, std::size_t cells) {
                for (const member& e : list) ++sl.starts[e.corner + 1];
                m += list.size();
                total += cells;
            });
        } else {
            m = boxes.size();
            sl.corner.resize(m);  // by position in the input
            std::array<std::uint32_t, D> extra;
            for (std::size_t k = 0; k < m; ++k) {
                std::size_t corner;
                prefetch_ahead(boxes, k);
                total += cell_range<false>(sl, boxes[k], corner, extra);
                sl.corner[k] = static_cast<std::uint32_t>(corner);
                ++sl.starts[corner + 1];
            }
        }
        if (total > std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("cell_sort_grid: more than 2^32 - 1 (cell, box) entries");
        sl.entry_count = total;
        for (std::size_t c = 0; c < sl.cells; ++c) sl.starts[c + 1] += sl.starts[c];
        sl.sorted.resize(m);
        sl.ids.resize(m);
        sl.sorted_corner.resize(m);
        sl.sorted_span.resize(m);
        // Only the box numbers are scattered (4 bytes, one random write per box); the boxes are
        // then copied in their new order: sequential writes and independent random reads,
        // which the processor overlaps (prefetched a few boxes ahead). Scattering whole boxes
        // missed the cache on every write of 1e6 boxes. Each box's cell range is computed
        // again from the box just read rather than read back: a few multiplications instead
        // of two more random reads per box. ids holds the caller's indices.
        if constexpr (Sliced) {
            for_each_member_list(slab_index, [&](const std::vector<member>& list, std::size_t) {
                for (const member& e : list) sl.ids[sl.starts[e.corner]++] = e.box;
            });
        } else {
            for (std::size_t k = 0; k < m; ++k) sl.ids[sl.starts[sl.corner[k]]++] = static_cast<std::uint32_t>(k);
        }
        constexpr std::size_t ahead = 8;
        for (std::size_t at = 0; at < m; ++at) {
            if (at + ahead < m) __builtin_prefetch(&boxes[sl.ids[at + ahead]]);
            const bounds& box = boxes[sl.ids[at]];
            sl.sorted[at] = box;
            std::size_t corner;
            cell_range<Sliced>(sl, box, corner, sl.sorted_span[at]);
            sl.sorted_corner[at] = static_cast<std::uint32_t>(corner);
        }
    }
    // Each slab's members: the boxes whose last-axis layers meet the slab's, in input order,
    // each with its first cell in the slab, listed on every core in one pass over the boxes:
    // per fixed chunk of boxes one list per slab (member_lists_, capacities kept across
    // queries) and the lists' cell counts. A slab then counts its cells from its lists alone.
    // (Each slab used to test every box itself: on 1e6 boxes in 2 slabs, 16 ms of each slab's
    // 28 ms sort went to the boxes of the other slab. A count pass and a write pass over the
    // boxes came next, and the slab's sort read its boxes once more for their first cells:
    // slabs reading their boxes at once, on cores that share one cache, lose to each other's
    // misses; results/checks/slab_member_corners.) O(n S_b) for boxes meeting S_b slabs;
    // span O(n / threads + chunks x slabs).
    void list_slab_members(const std::vector<bounds>& boxes, const std::vector<std::uint32_t>& bounds_at) {
        const std::size_t n = boxes.size(), count = bounds_at.size() - 1;
        constexpr std::size_t chunk = std::size_t{1} << 14;
        const std::size_t chunks = (n + chunk - 1) / chunk;
        // The slab holding a layer (layers < bounds_at.back()): without branches for the few
        // slabs of a machine's cores (a search's branches went the random way half the time).
        auto slab_of = [&](std::uint32_t layer) {
            if (count > 16)
                return static_cast<std::uint32_t>(std::upper_bound(bounds_at.begin(), bounds_at.end(), layer) - bounds_at.begin() - 1);
            std::uint32_t s = 0;
            for (std::size_t j = 1; j < count; ++j) s += layer >= bounds_at[j];
            return s;
        };
        if (member_lists_.size() < chunks * count) member_lists_.resize(chunks * count);
        member_cells_.assign(chunks * count, 0);
        member_chunks_ = chunks;
        member_slabs_ = count;
        spatial::detail::parallel_chunks(chunks, 1, [&](std::size_t first, std::size_t last) {
            std::array<std::uint32_t, D> extra;
            for (std::size_t k = first; k < last; ++k) {
                std::vector<member>* lists = member_lists_.data() + k * count;
                std::size_t* cells = member_cells_.data() + k * count;
                for (std::size_t s = 0; s < count; ++s) lists[s].clear();
                for (std::size_t b = k * chunk; b < std::min(n, (k + 1) * chunk); ++b) {
                    prefetch_ahead(boxes, b);
                    const std::uint32_t lo = slab_of(cell_coordinate(boxes[b].lo[D - 1], D - 1));
                    const std::uint32_t hi = slab_of(cell_coordinate(boxes[b].hi[D - 1], D - 1));
                    for (std::uint32_t s = lo; s <= hi; ++s) {
                        std::size_t corner;
                        cells[s] += cell_range<true>(slabs_[s], boxes[b], corner, extra);
                        lists[s].push_back({static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(corner)});
                    }
                }
            }
        });
    }
    // f(list, cells) for each chunk's list of slab s's members, in input order.
    template <class F>
    void for_each_member_list(std::size_t s, F&& f) const {
        for (std::size_t k = 0; k < member_chunks_; ++k) f(member_lists_[k * member_slabs_ + s], member_cells_[k * member_slabs_ + s]);
    }
    // Counting sort of the slab's (cell, box) entries into its entries, grouped by cell, each
    // tagged with its first-cell bits (step 3).
    void fill(slab& sl) const {
        sl.starts.assign(sl.cells + 1, 0);
        const std::size_t n = sl.sorted.size();
        for (std::size_t b = 0; b < n; ++b) for_each_cell(sl, b, [&](std::size_t c, entry_type) { ++sl.starts[c + 1]; });
        for (std::size_t c = 0; c < sl.cells; ++c) sl.starts[c + 1] += sl.starts[c];
        sl.entries.resize(sl.entry_count);
        // Each cell is filled from its end down (cursor = the next cell's start), boxes in
        // decreasing order, so every cell lists its boxes in increasing order.
        sl.cursors.assign(sl.starts.begin() + 1, sl.starts.end());
        for (std::size_t b = n; b-- > 0;)
            for_each_cell(sl, b, [&](std::size_t c, entry_type first_bits) {
                sl.entries[--sl.cursors[c]] = static_cast<entry_type>(b) << D | first_bits;
            });
    }
    // Boxes spanning at most 2 cells on every axis (nearly all: h is twice the mean edge) are
    // entered from a table indexed by which axes they span 2 cells on: cell offsets from the
    // first cell and their first-cell bits. One loop of 1, 2, 4 or 8 trips instead of D
    // nested loops whose trip counts the branch predictor cannot guess.
    void build_small_span_tables() {
        for (std::uint32_t code = 0; code <= axis_bits; ++code) {
            std::uint32_t k = 0;
            for (std::uint32_t o = 0; o <= axis_bits; ++o) {
                if ((o & ~code) != 0) continue;
                std::size_t offset = 0;
                for (std::size_t i = 0; i < D; ++i)
                    if ((o >> i) & 1u) offset += stride_[i];
                small_offset_[code][k] = offset;
                small_bits_[code][k] = static_cast<entry_type>(~o & axis_bits);
                ++k;
            }
            small_count_[code] = k;
        }
    }
    // f(cell, first-cell bits) for every cell of the slab that box b (sorted order) overlaps.
    // A box cut below the slab (cut_below) never takes the table path (its span exceeds 1)
    // and has no first cell on the last axis here.
    template <class F>
    void for_each_cell(const slab& sl, std::size_t b, F&& f) const {
        const auto& extra = sl.sorted_span[b];
        const std::size_t base = sl.sorted_corner[b];
        if constexpr (small_span_tables) {
            std::uint32_t code = 0;
            bool small = true;
            for (std::size_t i = 0; i < D; ++i) {
                code |= static_cast<std::uint32_t>(extra[i] != 0) << i;
                small &= extra[i] <= 1;
            }
            if (small) {
                for (std::uint32_t k = 0; k < small_count_[code]; ++k) f(base + small_offset_[code][k], small_bits_[code][k]);
                return;
            }
        }
        std::array<std::uint32_t, D> ends = extra;
        ends[D - 1] &= ~cut_below;
        const entry_type first_mask = (extra[D - 1] & cut_below) ? axis_bits >> 1 : axis_bits;
        std::array<std::uint32_t, D> at{};  // offsets from the first cell, per axis
        for (;;) {
            std::size_t offset = 0;
            entry_type first_bits = 0;
            for (std::size_t i = 0; i < D; ++i) {
                offset += at[i] * stride_[i];
                first_bits |= static_cast<entry_type>(at[i] == 0) << i;
            }
            f(base + offset, first_bits & first_mask);
            std::size_t i = 0;
            for (; i < D; ++i) {
                if (at[i] < ends[i]) {
                    ++at[i];
                    break;
                }
                at[i] = 0;
            }
            if (i == D) break;
        }
    }

    static constexpr std::size_t table_size = small_span_tables ? (std::size_t(1) << D) : 1;
    cell_sort_grid_config config_;
    std::array<T, D> origin_{};
    std::array<std::uint32_t, D> dims_{};
    std::array<std::size_t, D> stride_{};
    double inv_h_ = 1;
    std::vector<slab> slabs_;  // [0] serves the sequential queries
    std::vector<bounds> combined_;
    // A parallel query's slab members (list_slab_members): per chunk of boxes and slab,
    // chunk-major, the members the chunk gives the slab in input order, and their cell count.
    std::vector<std::vector<member>> member_lists_;
    std::vector<std::size_t> member_cells_;
    std::size_t member_chunks_ = 0, member_slabs_ = 0;
    std::array<std::array<std::size_t, table_size>, table_size> small_offset_{};
    std::array<std::array<entry_type, table_size>, table_size> small_bits_{};
    std::array<std::uint32_t, table_size> small_count_{};
    query_stats stats_;
};

}  // namespace spatial::collide
