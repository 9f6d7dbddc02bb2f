// results/checks/stream_prefetch: a replica of cell_sort_grid's slab listing (per box of 1e6
// double 3D cubes in input order: the cell coordinates of both corners on every axis, the
// slab of the last axis's layers, a (box, first cell) member appended to its slab's list),
// timed with a software prefetch of the box `distance` boxes ahead (0: none), one thread,
// medians of 21 passes. What it asks: does a pass this slow (tens of instructions a box) get
// its boxes from the hardware prefetcher in time, and how far ahead must software ask?
// Build: g++ -std=c++20 -O3 -DNDEBUG -march=native results/checks/stream_prefetch/listing_prefetch.cpp -o listing_prefetch
// Run: listing_prefetch
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

struct bounds {
    std::array<double, 3> lo, hi;
};
struct member {
    std::uint32_t box, corner;
};
static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

int main() {
    const std::size_t n = 1000000;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    const double s = std::cbrt(2.0 / double(n)) / 2;
    std::vector<bounds> boxes(n);
    for (auto& b : boxes)
        for (int i = 0; i < 3; ++i) b.lo[i] = u(rng) * (1 - s), b.hi[i] = b.lo[i] + s;
    const double inv_h = 1.0 / (4 * s);  // cell = twice the mean edge, as collision_grid's default
    const std::uint32_t dims = static_cast<std::uint32_t>(std::floor(1.0 / (4 * s))) + 1;
    auto cell = [&](double x) { return static_cast<std::uint32_t>(std::min(x * inv_h, double(dims - 1))); };
    const std::uint32_t boundary = dims / 2;
    std::array<std::vector<member>, 2> lists;
    std::uint64_t check = 0;
    for (std::size_t distance : {0, 8, 16, 32, 64, 128}) {
        std::vector<double> t;
        for (int r = 0; r < 21; ++r) {
            for (auto& l : lists) l.clear();
            const double start = now();
            for (std::size_t b = 0; b < n; ++b) {
                if (distance && b + distance < n) {
                    const char* next = reinterpret_cast<const char*>(&boxes[b + distance]);
                    __builtin_prefetch(next);
                    __builtin_prefetch(next + sizeof(bounds) - 1);
                }
                const bounds& x = boxes[b];
                const std::uint32_t first = cell(x.lo[2]), last = cell(x.hi[2]);
                for (std::uint32_t slab = first >= boundary; slab <= static_cast<std::uint32_t>(last >= boundary); ++slab) {
                    const std::uint32_t layer = std::max(first, slab * boundary) - slab * boundary;
                    const std::uint32_t corner = (layer * dims + cell(x.lo[1])) * dims + cell(x.lo[0]);
                    lists[slab].push_back({static_cast<std::uint32_t>(b), corner + (cell(x.hi[0]) - cell(x.lo[0]))});
                }
            }
            t.push_back(now() - start);
            check += lists[0].size() + lists[1].back().corner;
        }
        std::sort(t.begin(), t.end());
        std::printf("distance %3zu boxes (%5zu bytes): %.2f ms\n", distance, distance * sizeof(bounds), t[10] * 1e3);
    }
    std::printf("check %llu\n", static_cast<unsigned long long>(check));
}
