// results/checks/scene_step: the timed stages of
// `spatialbench scene datasets/scenes/boxes_100k.toml --structure collision_grid` (motion,
// update, exact self pairs, pairs added / removed), as the scene runner runs them on the
// scene's own objects and motion, without its validation and without its virtual calls.
// Between steps it writes to `trash_mb` megabytes (one double per cache line), as the
// runner's untimed validation evicts the caches between the timed stages: 0 measures a
// simulation loop that does nothing else; with SPIN_MS=t in the environment it also spins for
// t milliseconds between steps without touching memory. It prints the mean time per step of each stage,
// the median step, steps per second (steps over the sum of the step times, as the runner's
// steps_per_second), the mean pairs and pairs changed per step, the candidate lists built,
// and a hash of the objects after the last step (motion that must stay bit-identical).
// Build: see README.md. Run: scene_step [scene.toml] [steps] [trash_mb] [cell_size_factor].
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <utility>
#include <vector>

#include "datasets/scene.hpp"
#include "datasets/scene_motion.hpp"
#include "datasets/scene_objects.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/pair_changes.hpp"

using B = spatial::objects::box<double, 3>;
using clock_type = std::chrono::steady_clock;
static double since(clock_type::time_point t) { return std::chrono::duration<double>(clock_type::now() - t).count(); }

int main(int argc, char** argv) {
    const auto scene = datasets::load_scene(argc > 1 ? argv[1] : "datasets/scenes/boxes_100k.toml");
    const int steps = argc > 2 ? std::atoi(argv[2]) : 100;
    const std::size_t trash_mb = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 0;
    const double spin_ms = std::getenv("SPIN_MS") ? std::atof(std::getenv("SPIN_MS")) : 0;
    spatial::collide::cell_sort_grid_config config;
    if (argc > 4) config.cell_size_factor = std::atof(argv[4]);

    auto objects = datasets::generate_objects<B>(scene, 0);
    datasets::scene_motion<B> motion(scene, 0, objects.size());
    spatial::collision_grid<B> grid(config);
    std::vector<spatial::collision_grid<B>::iterator> handle;
    for (const B& o : objects) handle.push_back(grid.insert(o));
    spatial::collide::pair_set_tracker<std::uint32_t> tracker;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    std::vector<double> trash(trash_mb << 17), step_times;
    double t_motion = 0, t_update = 0, t_pairs = 0, t_changes = 0;
    std::size_t pair_count = 0, changed = 0;
    for (int s = 0; s < steps; ++s) {
        auto t0 = clock_type::now();
        motion.step(std::span<B>(objects), scene.time_step);
        const double a = since(t0);
        t0 = clock_type::now();
        for (std::size_t i = 0; i < objects.size(); ++i) grid.update(handle[i], objects[i]);
        const double b = since(t0);
        t0 = clock_type::now();
        pairs.clear();
        grid.for_each_self_pair(spatial::pair_filter::exact, [&](const auto& x, const auto& y) {
            const auto i = static_cast<std::uint32_t>(x.slot()), j = static_cast<std::uint32_t>(y.slot());
            pairs.emplace_back(std::min(i, j), std::max(i, j));
        });
        const double p = since(t0);
        t0 = clock_type::now();
        changed += tracker.step(pairs);
        const double c = since(t0);
        pair_count += tracker.pairs().size();
        for (std::size_t k = 0; k < trash.size(); k += 8) trash[k] += 1;
        if (spin_ms > 0) {  // a pause that touches no memory
            const auto t = clock_type::now();
            volatile double x = 1;
            while (since(t) < spin_ms * 1e-3) x = x * 1.0000001;
        }
        t_motion += a, t_update += b, t_pairs += p, t_changes += c;
        step_times.push_back(a + b + p + c);
    }
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the objects' bytes
    for (const B& o : objects) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(&o);
        for (std::size_t k = 0; k < sizeof(o); ++k) hash = (hash ^ bytes[k]) * 1099511628211ull;
    }
    const double total = t_motion + t_update + t_pairs + t_changes;
    std::sort(step_times.begin(), step_times.end());
    std::printf("steps %d trash %zu MB spin %g ms | mean ms: motion %.3f update %.3f pairs %.3f changes %.3f step %.3f (median %.3f) | "
                "%.1f steps/s | pairs %zu changed %zu | lists built %zu | objects %016llx\n",
                steps, trash_mb, spin_ms, t_motion * 1e3 / steps, t_update * 1e3 / steps, t_pairs * 1e3 / steps, t_changes * 1e3 / steps,
                total * 1e3 / steps, step_times[step_times.size() / 2] * 1e3, steps / total, pair_count / steps, changed / steps,
                grid.candidate_list_stats().built, static_cast<unsigned long long>(hash));
}
