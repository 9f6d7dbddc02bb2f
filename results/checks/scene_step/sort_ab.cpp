// results/checks/scene_step: fat_box_pairs' sort of a candidate list by (lower, higher) index,
// as committed (one counting-sort scatter by the lower index, then an insertion sort of each
// index's few partners), against two-step scatters (by blocks of 2^b lower indices first,
// then within each block) and a least-significant-digit pair of counting sorts (by the higher
// index, then stably by the lower); and, for scale, the scatter alone. The candidates are
// those of 1e5 uniform cubes of edge 0.0136 grown by 0.0029 on every side (boxes_100k's fat
// boxes), in the order cell_sort_grid reports them. Medians of 15 alternating rounds; every
// variant's list must equal the committed one's.
// Build (one line): g++ -std=c++20 -O3 -DNDEBUG -march=native -ffp-contract=off
//     -Istructures/include results/checks/scene_step/sort_ab.cpp -o sort_ab
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

#include "spatial/collide/cell_sort_grid.hpp"

using pair32 = std::pair<std::uint32_t, std::uint32_t>;
using clock_type = std::chrono::steady_clock;
static double since(clock_type::time_point t) { return std::chrono::duration<double>(clock_type::now() - t).count(); }

struct sorter {
    std::vector<std::uint32_t> starts, cursor, block_cursor, by_higher;
    std::vector<pair32> scratch;

    void prefix(std::size_t n) {
        for (std::size_t k = 0; k < n; ++k) starts[k + 1] += starts[k];
    }
    void insertion_sort_rows(std::size_t first, std::size_t last, std::vector<pair32>& pairs) {
        for (std::size_t k = first; k < last; ++k)
            for (std::uint32_t x = starts[k] + 1; x < starts[k + 1]; ++x)
                for (std::uint32_t y = x; y > starts[k] && pairs[y].second < pairs[y - 1].second; --y) std::swap(pairs[y], pairs[y - 1]);
    }
    // The committed sort.
    void one_scatter(std::size_t n, const std::vector<pair32>& in, std::vector<pair32>& out, bool rows = true) {
        prefix(n);
        out.resize(in.size());
        cursor.assign(starts.begin(), starts.end() - 1);
        for (const auto& p : in) out[cursor[p.first]++] = p;
        if (rows) insertion_sort_rows(0, n, out);
    }
    void two_step(std::size_t n, const std::vector<pair32>& in, std::vector<pair32>& out, unsigned block_bits) {
        prefix(n);
        const std::size_t blocks = (n >> block_bits) + 1;
        block_cursor.resize(blocks);
        for (std::size_t b = 0; b < blocks; ++b) block_cursor[b] = starts[b << block_bits];
        scratch.resize(in.size());
        for (const auto& p : in) scratch[block_cursor[p.first >> block_bits]++] = p;
        out.resize(in.size());
        cursor.assign(starts.begin(), starts.end() - 1);
        for (std::size_t b = 0; b < blocks; ++b) {
            const std::size_t first = b << block_bits, last = std::min(n, (b + 1) << block_bits);
            for (std::uint32_t x = starts[first]; x < starts[last]; ++x) out[cursor[scratch[x].first]++] = scratch[x];
            insertion_sort_rows(first, last, out);
        }
    }
    void lsd(std::size_t n, const std::vector<pair32>& in, std::vector<pair32>& out) {
        by_higher.assign(n + 1, 0);
        for (const auto& p : in) ++by_higher[p.second + 1];
        for (std::size_t k = 0; k < n; ++k) by_higher[k + 1] += by_higher[k];
        scratch.resize(in.size());
        for (const auto& p : in) scratch[by_higher[p.second]++] = p;
        one_scatter(n, scratch, out, false);
    }
};

int main() {
    const std::size_t n = 100000;
    const double half = 0.0068 + 0.0029;
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<spatial::collide::box_bounds<double, 3>> boxes(n);
    for (auto& b : boxes)
        for (int d = 0; d < 3; ++d) {
            const double c = u(rng);
            b.lo[d] = c - half, b.hi[d] = c + half;
        }
    spatial::collide::cell_sort_grid<double, 3> grid;
    std::vector<pair32> candidates;
    std::vector<std::uint32_t> counts(n + 1);
    grid.self_pairs(boxes, [&](std::uint32_t i, std::uint32_t j) {
        const std::uint32_t lower = std::min(i, j);
        candidates.emplace_back(lower, std::max(i, j));
        ++counts[lower + 1];
    });
    sorter s;
    std::vector<pair32> reference, out;
    const char* names[] = {"committed", "two_step_6", "two_step_8", "two_step_10", "lsd", "scatter_only"};
    std::vector<std::vector<double>> times(6);
    for (int round = 0; round < 15; ++round)
        for (int v = 0; v < 6; ++v) {
            s.starts = counts;
            const auto t0 = clock_type::now();
            switch (v) {
                case 0: s.one_scatter(n, candidates, reference); break;
                case 1: s.two_step(n, candidates, out, 6); break;
                case 2: s.two_step(n, candidates, out, 8); break;
                case 3: s.two_step(n, candidates, out, 10); break;
                case 4: s.lsd(n, candidates, out); break;
                case 5: s.one_scatter(n, candidates, out, false); break;
            }
            times[v].push_back(since(t0));
            if (v != 0 && v != 5 && out != reference) {
                std::printf("%s: a different list\n", names[v]);
                return 1;
            }
        }
    std::printf("%zu candidates | median ms:", candidates.size());
    for (int v = 0; v < 6; ++v) {
        std::sort(times[v].begin(), times[v].end());
        std::printf(" %s %.3f", names[v], times[v][7] * 1e3);
    }
    std::printf("\n");
}
