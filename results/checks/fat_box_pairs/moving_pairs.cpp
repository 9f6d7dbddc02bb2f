// results/checks/fat_box_pairs: collision_grid's self pairs over moving boxes, with the
// candidate list (collide/fat_box_pairs.hpp) against the grid alone, plus the pair tracker:
// the collide stage of the boxes_100k scene (100000 cubes of edge 0.0136 in the unit cube,
// about two overlaps each, every box moving 0.001 per step in its own direction and bouncing
// off the walls; `speed` scales that; with `walk`, every box draws a new velocity of the same
// distribution at every step: motion that turns; with `mirror`, they move as in the scene
// runner, see below). Both paths' pair sets are compared every step. Build: see README.md.
// Run: moving_pairs <steps> <speed> [walk | mirror].
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "spatial/collide/cell_sort_grid.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/pair_changes.hpp"

using B = spatial::objects::box<double, 3>;
using pair32 = std::pair<std::uint32_t, std::uint32_t>;
using clock_type = std::chrono::steady_clock;
static double since(clock_type::time_point t) { return std::chrono::duration<double>(clock_type::now() - t).count(); }

int main(int argc, char** argv) {
    const int n = 100000, steps = argc > 1 ? std::atoi(argv[1]) : 100;
    const double speed = argc > 2 ? std::atof(argv[2]) : 1.0, half = 0.0068;
    std::mt19937_64 rng(100000);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<std::array<double, 3>> c(n), v(n);
    for (int i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) c[i][d] = half + u(rng) * (1 - 2 * half), v[i][d] = (u(rng) - 0.5) * 0.002 * speed;
    // `mirror`: as the scene runner moves them (datasets/scene_motion.hpp): a uniformly random
    // direction at speed 0.001 per step, and a box that crosses a wall is mirrored back inside
    // (moved in by twice its overshoot) as its velocity flips.
    const bool mirror = argc > 3 && std::string(argv[3]) == "mirror";
    if (mirror) {
        std::normal_distribution<double> g;
        for (auto& w : v) {
            double length = 0;
            for (double& x : w) x = g(rng), length += x * x;
            for (double& x : w) x *= 0.001 * speed / std::sqrt(length);
        }
    }
    auto box_of = [&](int i) {
        B b;
        for (int d = 0; d < 3; ++d) b.lo[d] = c[i][d] - half, b.hi[d] = c[i][d] + half;
        return b;
    };
    spatial::collision_grid<B> grid;
    std::vector<spatial::collision_grid<B>::iterator> handle;
    for (int i = 0; i < n; ++i) handle.push_back(grid.insert(box_of(i)));
    spatial::collide::cell_sort_grid<double, 3> plain;  // the grid alone: what every query ran before
    std::vector<spatial::collide::box_bounds<double, 3>> boxes(n);
    spatial::collide::pair_set_tracker<std::uint32_t> list_tracker, plain_tracker;
    std::vector<pair32> list_pairs, plain_pairs;
    double t_list = 0, t_list_track = 0, t_plain = 0, t_plain_track = 0, t_built = 0, t_reused = 0;
    std::size_t built = 0, reused = 0;
    const bool walk = argc > 3 && std::string(argv[3]) == "walk";
    for (int s = 0; s < steps; ++s) {
        if (walk)
            for (int i = 0; i < n; ++i)
                for (int d = 0; d < 3; ++d) v[i][d] = (u(rng) - 0.5) * 0.002 * speed;
        for (int i = 0; i < n; ++i)
            for (int d = 0; d < 3; ++d) {
                c[i][d] += v[i][d];
                const bool out = c[i][d] < half || c[i][d] > 1 - half;
                if (out && mirror) c[i][d] = c[i][d] < half ? 2 * half - c[i][d] : 2 * (1 - half) - c[i][d];
                if (out) v[i][d] = -v[i][d];
            }
        for (int i = 0; i < n; ++i) handle[i] = grid.update(handle[i], box_of(i));
        // The grid alone (rounds alternate with the list's, same boxes).
        auto t0 = clock_type::now();
        for (int i = 0; i < n; ++i) {
            const B b = box_of(i);
            boxes[i].lo = {b.lo[0], b.lo[1], b.lo[2]};
            boxes[i].hi = {b.hi[0], b.hi[1], b.hi[2]};
        }
        plain_pairs.clear();
        plain.self_pairs(boxes, [&](std::uint32_t i, std::uint32_t j) { plain_pairs.emplace_back(std::min(i, j), std::max(i, j)); });
        t_plain += since(t0);
        t0 = clock_type::now();
        plain_tracker.step(plain_pairs);
        t_plain_track += since(t0);
        // collision_grid, candidate list and all.
        const std::size_t built_before = grid.candidate_list_stats().built, reused_before = grid.candidate_list_stats().reused;
        t0 = clock_type::now();
        list_pairs.clear();
        grid.for_each_self_pair(spatial::pair_filter::exact, [&](auto a, auto b) {
            list_pairs.emplace_back(static_cast<std::uint32_t>(a.slot()), static_cast<std::uint32_t>(b.slot()));
        });
        const double q = since(t0);
        t_list += q;
        if (grid.candidate_list_stats().built > built_before) t_built += q, ++built;
        if (grid.candidate_list_stats().reused > reused_before) t_reused += q, ++reused;
        t0 = clock_type::now();
        list_tracker.step(list_pairs);
        t_list_track += since(t0);
        if (list_tracker.pairs() != plain_tracker.pairs()) {
            std::printf("step %d: the pair sets differ\n", s);
            return 1;
        }
    }
    const auto& st = grid.candidate_list_stats();
    std::printf("speed %g steps %d pairs %zu | grid alone: query %.3f ms tracker %.3f ms | with list: query %.3f ms tracker %.3f ms"
                " | lists built %zu (%.3f ms each) reused %zu (%.3f ms each) candidates %zu margin %g | query+tracker ratio %.2f\n",
                speed, steps, plain_tracker.pairs().size(), 1e3 * t_plain / steps, 1e3 * t_plain_track / steps, 1e3 * t_list / steps,
                1e3 * t_list_track / steps, built, built ? 1e3 * t_built / static_cast<double>(built) : 0.0, reused, reused ? 1e3 * t_reused / static_cast<double>(reused) : 0.0,
                st.candidates, st.margin[0], (t_plain + t_plain_track) / (t_list + t_list_track));
}
