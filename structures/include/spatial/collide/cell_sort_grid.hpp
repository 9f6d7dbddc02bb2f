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
// Cost: O(n + e + sum over cells of m_c^2) with m_c entries in cell c; for boxes of similar
// size O(n + k) with k overlapping pairs. Boxes much larger than h occupy many cells (a
// heavy-tailed size distribution costs their volume in cells, bounded by the cell cap).
// Memory: O(n + cells + e) 32-bit words plus one copy of the boxes, all reused across
// queries (buffers keep their capacity).
// Exactness: every overlap decision is the closed box test in T; the grid only decides which
// pairs are looked at, and no overlapping pair can be skipped (step 3).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace spatial::collide {

template <class T, std::size_t D>
struct box_bounds {
    std::array<T, D> lo{}, hi{};
};

template <class T, std::size_t D>
bool closed_boxes_overlap(const box_bounds<T, D>& a, const box_bounds<T, D>& b) {
    for (std::size_t i = 0; i < D; ++i)
        if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
    return true;
}

struct cell_sort_grid_config {
    // h = factor * mean box edge: 2 measured fastest on cubes of equal size (each box spans
    // about (1 + 1/2)^D cells, cells hold few entries); see docs/design.md §15.
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
        combined_.assign(a.begin(), a.end());
        combined_.insert(combined_.end(), b.begin(), b.end());
        const auto na = static_cast<std::uint32_t>(a.size());
        run(combined_, a.size(), [&](std::uint32_t x, std::uint32_t y) {
            if (x < na) emit(x, y - na);
            else emit(y, x - na);
        });
    }

    const query_stats& last_query_stats() const { return stats_; }
    std::size_t memory_bytes() const {
        return sizeof(*this) + (starts_.capacity() + cursors_.capacity() + entries_.capacity()) * sizeof(std::uint32_t) +
               (corner_.capacity() + ids_.capacity()) * sizeof(std::uint32_t) +
               (sorted_.capacity() + combined_.capacity()) * sizeof(bounds) +
               first_cell_.capacity() * sizeof(std::array<std::uint32_t, D>) +
               last_cell_.capacity() * sizeof(std::array<std::uint32_t, D>);
    }

private:
    // boxes [0, split) and [split, n) are two sets; pairs within the second set are not
    // reported (split == n: one set, every pair).
    template <class Emit>
    void run(const std::vector<bounds>& boxes, std::size_t split, Emit&& emit) {
        stats_ = {};
        const std::size_t n = boxes.size();
        if (n < 2) return;
        if (n > std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("cell_sort_grid: more than 2^32 - 1 boxes");
        layout(boxes);
        sort_by_corner_cell(boxes);
        fill();
        if (split == n) join_cells<false>(static_cast<std::uint32_t>(split), emit);
        else join_cells<true>(static_cast<std::uint32_t>(split), emit);
    }
    // Step 3, cell by cell in coordinate order. The reporting rule is checked first, on
    // integers: the intersection's lower corner lies in cell max(first_a, first_b) per axis
    // (first = the cell of a box's lower corner; cell_coordinate is monotone), so a pair is
    // looked at only in that cell and the box test runs once per pair sharing cells, not
    // once per shared cell. Both tests are computed without branches (their outcomes are
    // unpredictable) and combined into one rarely-taken branch.
    template <bool Bipartite, class Emit>
    void join_cells(std::uint32_t split, Emit& emit) {
        std::array<std::uint32_t, D> at{};
        const std::size_t cells = starts_.size() - 1;
        for (std::size_t c = 0; c < cells; ++c) {
            if (c != 0)
                for (std::size_t i = 0; i < D && ++at[i] == dims_[i]; ++i) at[i] = 0;  // next cell's coordinates
            const std::uint32_t first = starts_[c], last = starts_[c + 1];
            if (last - first < 2) continue;
            for (std::uint32_t x = first; x + 1 < last; ++x) {
                const std::uint32_t a = entries_[x];
                const bounds& ba = sorted_[a];
                const auto& fa = first_cell_[a];
                stats_.candidate_tests += last - x - 1;
                for (std::uint32_t y = x + 1; y < last; ++y) {
                    const std::uint32_t b = entries_[y];
                    const auto& fb = first_cell_[b];
                    const bounds& bb = sorted_[b];
                    bool here = true, apart = false;
                    for (std::size_t i = 0; i < D; ++i) {
                        here &= std::max(fa[i], fb[i]) == at[i];
                        apart |= (ba.hi[i] < bb.lo[i]) | (bb.hi[i] < ba.lo[i]);
                    }
                    if constexpr (Bipartite) here &= (ids_[a] < split) != (ids_[b] < split);
                    // One rarely-taken branch: the tests are computed branch-free.
                    if (here & !apart) emit(ids_[a], ids_[b]);
                }
            }
        }
    }
    // Grid geometry from the boxes: origin, cell size, cells per axis.
    void layout(const std::vector<bounds>& boxes) {
        bounds all = boxes[0];
        double edge_sum = 0;
        for (const bounds& b : boxes)
            for (std::size_t i = 0; i < D; ++i) {
                all.lo[i] = std::min(all.lo[i], b.lo[i]);
                all.hi[i] = std::max(all.hi[i], b.hi[i]);
                edge_sum += static_cast<double>(b.hi[i]) - static_cast<double>(b.lo[i]);
            }
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
        for (;;) {
            double cells = 1;
            for (std::size_t i = 0; i < D; ++i) cells *= std::floor(span[i] / h) + 1;
            if (cells <= max_cells) break;
            h *= std::pow(cells / max_cells, 1.0 / static_cast<double>(D)) * 1.0001;
        }
        for (std::size_t i = 0; i < D; ++i) {
            origin_[i] = all.lo[i];
            dims_[i] = static_cast<std::uint32_t>(std::floor(span[i] / h)) + 1;
        }
        inv_h_ = 1.0 / h;
        stats_.cell_size = h;
    }
    // floor((x - origin) / h) clamped to [0, dims - 1]: monotone in x.
    std::uint32_t cell_coordinate(T x, std::size_t axis) const {
        const double c = std::floor((static_cast<double>(x) - static_cast<double>(origin_[axis])) * inv_h_);
        if (!(c > 0)) return 0;
        const double top = static_cast<double>(dims_[axis] - 1);
        return static_cast<std::uint32_t>(std::min(c, top));
    }
    std::size_t linear_cell(const std::array<std::uint32_t, D>& c) const {
        std::size_t id = c[D - 1];
        for (std::size_t i = D - 1; i-- > 0;) id = id * dims_[i] + c[i];
        return id;
    }
    // Locality: a copy of the boxes ordered by the cell of their lower corner (a counting
    // sort, O(n + cells)), so the boxes met in one cell, and in consecutive cells, sit close
    // together in memory. In the caller's (random) order every candidate test was a cache
    // miss; this halves the query time at 1e6 boxes.
    void sort_by_corner_cell(const std::vector<bounds>& boxes) {
        std::size_t cells = 1;
        for (std::size_t i = 0; i < D; ++i) cells *= dims_[i];
        stats_.cells = cells;
        const std::size_t n = boxes.size();
        starts_.assign(cells + 1, 0);
        corner_.resize(n);
        for (std::size_t b = 0; b < n; ++b) {
            std::array<std::uint32_t, D> c;
            for (std::size_t i = 0; i < D; ++i) c[i] = cell_coordinate(boxes[b].lo[i], i);
            corner_[b] = static_cast<std::uint32_t>(linear_cell(c));
            ++starts_[corner_[b] + 1];
        }
        for (std::size_t c = 0; c < cells; ++c) starts_[c + 1] += starts_[c];
        sorted_.resize(n);
        ids_.resize(n);
        for (std::size_t b = 0; b < n; ++b) {
            const std::uint32_t at = starts_[corner_[b]]++;
            sorted_[at] = boxes[b];
            ids_[at] = static_cast<std::uint32_t>(b);
        }
    }
    // Counting sort of the (cell, box) entries into entries_, grouped by cell.
    void fill() {
        const std::vector<bounds>& boxes = sorted_;
        const std::size_t cells = stats_.cells;
        starts_.assign(cells + 1, 0);
        const std::size_t n = boxes.size();
        first_cell_.resize(n);
        last_cell_.resize(n);
        std::size_t total = 0;
        for (std::size_t b = 0; b < n; ++b) {
            std::size_t spanned = 1;
            for (std::size_t i = 0; i < D; ++i) {
                first_cell_[b][i] = cell_coordinate(boxes[b].lo[i], i);
                last_cell_[b][i] = cell_coordinate(boxes[b].hi[i], i);
                spanned *= last_cell_[b][i] - first_cell_[b][i] + 1;
            }
            total += spanned;
            for_each_cell(b, [&](std::size_t c) { ++starts_[c + 1]; });
        }
        if (total > std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("cell_sort_grid: more than 2^32 - 1 (cell, box) entries");
        stats_.entries = total;
        for (std::size_t c = 0; c < cells; ++c) starts_[c + 1] += starts_[c];
        entries_.resize(total);
        // Each cell is filled from its end down (cursor = the next cell's start), boxes in
        // decreasing order, so every cell lists its boxes in increasing order.
        cursors_.assign(starts_.begin() + 1, starts_.end());
        for (std::size_t b = n; b-- > 0;)
            for_each_cell(b, [&](std::size_t c) { entries_[--cursors_[c]] = static_cast<std::uint32_t>(b); });
    }

    template <class F>
    void for_each_cell(std::size_t b, F&& f) const {
        const auto& lo = first_cell_[b];
        const auto& hi = last_cell_[b];
        if constexpr (D == 2) {
            for (std::uint32_t y = lo[1]; y <= hi[1]; ++y)
                for (std::uint32_t x = lo[0]; x <= hi[0]; ++x) f(static_cast<std::size_t>(y) * dims_[0] + x);
        } else if constexpr (D == 3) {
            for (std::uint32_t z = lo[2]; z <= hi[2]; ++z)
                for (std::uint32_t y = lo[1]; y <= hi[1]; ++y) {
                    const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0];
                    for (std::uint32_t x = lo[0]; x <= hi[0]; ++x) f(row + x);
                }
        } else {
            std::array<std::uint32_t, D> c = lo;
            for (;;) {
                f(linear_cell(c));
                std::size_t i = 0;
                for (; i < D; ++i) {
                    if (c[i] < hi[i]) {
                        ++c[i];
                        break;
                    }
                    c[i] = lo[i];
                }
                if (i == D) break;
            }
        }
    }

    cell_sort_grid_config config_;
    std::array<T, D> origin_{};
    std::array<std::uint32_t, D> dims_{};
    double inv_h_ = 1;
    std::vector<std::uint32_t> starts_, cursors_, entries_, corner_, ids_;
    std::vector<bounds> sorted_, combined_;
    std::vector<std::array<std::uint32_t, D>> first_cell_, last_cell_;
    query_stats stats_;
};

}  // namespace spatial::collide
