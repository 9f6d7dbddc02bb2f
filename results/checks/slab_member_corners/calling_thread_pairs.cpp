// results/checks/slab_member_corners: collision_grid<box<double, 3>>'s pair query on one
// thread (for_each_self_pair) against the parallel one that hands every pair over on the
// calling thread (for_each_self_pair(spatial::par, ...)), pairs appended to one list, on 1e6
// uniform cubes with about two overlaps each; medians of `reps` alternated queries.
// Build (one line): g++ -std=c++20 -O3 -DNDEBUG -march=native -ffp-contract=off
//     -Istructures/include -isystem /usr/include/eigen3 -DSPATIAL_HAVE_TBB
//     results/checks/slab_member_corners/calling_thread_pairs.cpp -o calling_thread_pairs -ltbb
// Run: calling_thread_pairs [reps]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

#include "spatial/collide/collision_grid.hpp"

using B = spatial::objects::box<double, 3>;
using P = spatial::point<double, 3>;
static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

int main(int argc, char** argv) {
    const std::size_t n = 1000000;
    const int reps = argc > 1 ? std::atoi(argv[1]) : 21;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    const double s = std::cbrt(2.0 / double(n)) / 2;
    std::vector<B> boxes;
    boxes.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const P lo{{u(rng) * (1 - s), u(rng) * (1 - s), u(rng) * (1 - s)}};
        boxes.emplace_back(lo, P{{lo[0] + s, lo[1] + s, lo[2] + s}});
    }
    const spatial::collision_grid<B> grid(boxes.begin(), boxes.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found;
    found.reserve(3 * n);
    std::vector<double> one, two;
    std::size_t pairs_one = 0, pairs_two = 0;
    auto add = [&](auto a, auto b) { found.emplace_back(static_cast<std::uint32_t>(a.slot()), static_cast<std::uint32_t>(b.slot())); };
    for (int r = 0; r < reps; ++r) {
        double t = now();
        found.clear();
        grid.for_each_self_pair(spatial::pair_filter::exact, add);
        pairs_one = found.size();
        one.push_back(now() - t);
        t = now();
        found.clear();
        grid.for_each_self_pair(spatial::par, spatial::pair_filter::exact, add);
        pairs_two = found.size();
        two.push_back(now() - t);
    }
    std::sort(one.begin(), one.end());
    std::sort(two.begin(), two.end());
    std::printf("pairs %zu/%zu one thread %.2f ms, %zu threads (calling thread) %.2f ms, speed-up %.3f\n", pairs_one, pairs_two,
                one[reps / 2] * 1e3, spatial::detail::parallel_threads(), two[reps / 2] * 1e3, one[reps / 2] / two[reps / 2]);
    return pairs_one == pairs_two ? 0 : 1;
}
