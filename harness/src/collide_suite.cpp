// The collide suite (see collide_suite.hpp). Three workloads:
//   boxes         static self-intersection of n random cubes with about two overlaps each
//                 (side s with n (2s)^3 = 2 in the unit cube): build and pair-query time of
//                 every structure and peer;
//   moving_boxes  the same cubes moving linearly and bouncing off the unit cube's walls,
//                 `steps` steps: per step, update + exact pairs, for every structure (bvh with
//                 each motion strategy) and peer, and the refitted trees' quality per step;
//   triangles     a static soup of small random triangles: for the BVH of every bounding-
//                 volume type, candidate pairs (before the narrow phase) against time.
// Validation before any timing is recorded: every participant's pair set must EQUAL the
// reference's, and the reference is checked against an O(n^2) brute force (n <= brute_max_n)
// or, above that, against a linear scan for a seeded sample of boxes (every pair of a
// sampled box, both ways). On moving workloads this is done at every step.

#include "harness/collide_suite.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "datasets/random.hpp"
#include "harness/best_peer.hpp"
#include "harness/collide_adapters.hpp"
#include "harness/collide_oracles.hpp"
#include "harness/csv_writer.hpp"
#include "harness/fault_injection.hpp"
#include "harness/format.hpp"
#include "harness/our_collide_indexes.hpp"
#include "harness/progress.hpp"
#include "harness/run_info.hpp"
#include "harness/peer_registry.hpp"
#include "harness/structure_registry.hpp"
#include "harness/suite_cases.hpp"
#include "harness/suite_context.hpp"
#include "harness/timing.hpp"
#include "harness/tuning_sweep.hpp"
#include "harness/validation.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/pair_changes.hpp"
#include "spatial/core/parallel.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/objects/triangle.hpp"

namespace harness {
namespace {

using spatial::motion_strategy;

struct preset_config {
    std::vector<std::size_t> static_sizes, moving_sizes, triangle_sizes;
    std::size_t steps;         // moving_boxes steps
    std::size_t repetitions;   // timed repetitions of static workloads (median), after one validated run
    std::size_t oracle_sample; // boxes checked by linear scan when n > brute_max_n
    std::size_t brute_max_n;   // full O(n^2) check up to this n
    std::size_t slow_max_n;    // structures without a dedicated broad phase (sweep_and_prune,
                               // kd_tree, octree, hashed_grid, brute_force) up to this n
    // The tuning sweep (harness/tuning_sweep.hpp: CGAL's cutoff, Embree's build quality) runs
    // on static boxes of at least this many: the sizes that decide the targets (quick's
    // largest; every size in full; smoke's largest, so that the smoke run exercises it).
    std::size_t sweep_min_n;
};

preset_config preset(const std::string& name) {
    if (name == "smoke") return {{1000, 5000}, {2000}, {2000}, 5, 2, 64, 5000, 5000, 5000};
    // quick (the main job): the 1e5 moving-box target and everything up to 1e5 except the BVH
    // volume study at 1e5 (k-DOP builds take 2-10 s there); full: the 1e6 static target too
    // (results/collide_1e6.csv: --preset full --workload boxes --n 1000000).
    if (name == "quick") return {{10000, 100000}, {10000, 100000}, {10000}, 30, 3, 200, 20000, 100000, 100000};
    if (name == "full")
        return {{10000, 100000, 1000000}, {10000, 100000}, {10000, 100000}, 30, 3, 400, 20000, 100000, 0};
    throw std::invalid_argument("unknown preset '" + name + "' (expected smoke, quick or full)");
}

// Cubes of side s = (2 / n)^(1/3) / 2 with lower corners uniform in [0, 1)^3: the expected
// number of other cubes overlapping one is n (2s)^3 = 2.
double cube_side(std::size_t n) { return std::cbrt(2.0 / static_cast<double>(n)) / 2; }
std::vector<collide_box> random_cubes(std::size_t n, std::uint64_t seed) {
    datasets::random_stream rng(datasets::derive_seed(seed, 0xC0u /* stream: collide cubes */));
    const double s = cube_side(n);
    std::vector<collide_box> out(n);
    for (auto& b : out)
        for (std::size_t i = 0; i < 3; ++i) {
            b.lo[i] = rng.uniform01<double>() * (1 - s);
            b.hi[i] = b.lo[i] + s;
        }
    return out;
}

using context = suite_context<preset_config>;

// What one participant's rows share: the suite's context, who, on what, and what checked its
// answers (check.hpp).
struct row_sink {
    context& ctx;
    std::string structure, bv, workload;
    std::size_t n;
    std::string verified;

    // An untimed figure (all the collide workloads are 3D double).
    void add(const std::string& operation, const std::string& params, const std::string& metric, double value,
             const std::string& unit, const std::string& other_check = {}) const {
        const std::string c = other_check.empty() ? verified : other_check;
        ctx.rows.push_back(ctx.scope(workload, n).with_check(c).figure(structure, bv, operation, params, metric, value, unit));
    }
    // A timed figure, in seconds.
    void add_timed(const std::string& operation, const std::string& params, const timing_result& t) const {
        ctx.rows.push_back(ctx.scope(workload, n).with_check(verified).timed(structure, bv, operation, params, "time", t, "s"));
    }
};

// ---- validation --------------------------------------------------------------------------

// The sampled oracle: `draws` seeded draws of an element among n (repeats dropped); for each
// element drawn, its partners in `pairs` must be exactly the j != i with meets(i, j), found
// by a linear scan. `element` and `oracle` name them in the message ("box", "a linear scan
// finds"). Returns how many elements were checked.
template <class Meets>
std::size_t check_sampled_partners(std::size_t n, const std::vector<index_pair>& pairs, std::size_t draws,
                                   std::uint64_t seed, Meets&& meets, const std::string& where,
                                   const std::string& element, const std::string& oracle) {
    datasets::random_stream rng(seed);
    std::vector<char> sampled(n, 0);
    std::vector<std::uint32_t> sample;
    for (std::size_t k = 0; k < draws; ++k) {
        const auto i = static_cast<std::uint32_t>(rng.uniform_index(n));
        if (!sampled[i]) sampled[i] = 1, sample.push_back(i);
    }
    std::vector<std::vector<std::uint32_t>> got(n);
    for (const auto& [a, b] : pairs) {
        if (sampled[a]) got[a].push_back(b);
        if (sampled[b]) got[b].push_back(a);
    }
    for (std::uint32_t i : sample) {
        std::vector<std::uint32_t> want;
        for (std::uint32_t j = 0; j < n; ++j)
            if (j != i && meets(i, j)) want.push_back(j);
        std::sort(got[i].begin(), got[i].end());
        if (got[i] != want)
            throw validation_error(where + ": " + element + " " + std::to_string(i) + " has " +
                                   std::to_string(got[i].size()) + " partners, " + oracle + " " +
                                   std::to_string(want.size()));
    }
    return sample.size();
}

// Checks `pairs` (sorted, i < j) against brute force: all pairs when n <= brute_max_n, else
// every pair of each sampled box (a linear scan per sampled box, both directions). Returns
// what checked them.
std::string validate_pairs(const context& ctx, const std::vector<collide_box>& boxes, const std::vector<index_pair>& pairs,
                    std::uint64_t sample_seed, const std::string& where) {
    const std::size_t n = boxes.size();
    // Every participant's pairs went through sort_unique_pairs (collide_index.hpp), which
    // sorts them and drops repeats alike for all (some peers report a pair twice); that our
    // containers report each pair once is a library test (collide_pairs_test).
    if (!std::is_sorted(pairs.begin(), pairs.end())) throw validation_error(where + ": pairs not sorted");
    if (n <= ctx.cfg.brute_max_n) {
        std::vector<index_pair> want;
        for (std::uint32_t i = 0; i < n; ++i)
            for (std::uint32_t j = i + 1; j < n; ++j)
                if (closed_boxes_overlap(boxes[i], boxes[j])) want.emplace_back(i, j);
        if (want != pairs)
            throw validation_error(where + ": " + std::to_string(pairs.size()) + " pairs, brute force finds " +
                                   std::to_string(want.size()) + " (or different ones)");
        return check::oracle_all;
    }
    for (const auto& [a, b] : pairs)
        if (a >= b || b >= n) throw validation_error(where + ": malformed pair");
    return check::oracle_sample(check_sampled_partners(
        n, pairs, ctx.cfg.oracle_sample, sample_seed,
        [&](std::uint32_t i, std::uint32_t j) { return closed_boxes_overlap(boxes[i], boxes[j]); }, where, "box",
        "a linear scan finds"));
}

// ---- participants -----------------------------------------------------------------------

struct participant {
    std::unique_ptr<collide_index> index;
    std::string bv;  // "aabb" for bvh, "-" otherwise
};

// Every participant for n boxes: the registry's structures of the static or the moving part
// (harness/structure_registry.hpp; moving runs the bvh once per motion strategy), slow ones up
// to slow_max_n and the oracle up to brute_max_n (a tenth and a quarter when moving); the
// peers in every configuration of their tuning sweep too when `sweep`.
std::vector<participant> participants(const context& ctx, std::size_t n, bool moving, bool sweep = false) {
    std::vector<participant> out;
    const std::size_t slow_max = ctx.cfg.slow_max_n / (moving ? 10 : 1), oracle_max = ctx.cfg.brute_max_n / (moving ? 4 : 1);
    auto add = [&]<class E>() {
        const structure_info info = E::info();
        if (within_limits(info, n, slow_max, oracle_max))
            out.push_back({std::make_unique<container_collide_index<typename E::template container<collide_box3>>>(
                               info.name, info.motion),
                           info.bv.empty() ? "-" : info.bv});
    };
    if (moving) for_each_structure<collide_box3, in::collide_moving>(add);
    else for_each_structure<collide_box3, in::collide_static>(add);
    for (auto& p : make_peer_collide_indices(sweep))  // their limits: harness/peer_registry.hpp
        if (peer_within_limits(p->name(), n, slow_max, oracle_max)) out.push_back({std::move(p), "-"});
    std::vector<participant> kept;
    for (auto& p : out)
        if (ctx.wants(p.index->name())) kept.push_back(std::move(p));
    return kept;
}

// ---- static boxes -------------------------------------------------------------------------

// A checksum of a pair list (order-sensitive: the lists are sorted): a 64-bit FNV-1a over
// the pairs, kept to the 53 bits a double holds exactly.
double pairs_checksum(const std::vector<index_pair>& pairs) {
    std::uint64_t h = 14695981039346656037ull;
    for (const auto& [a, b] : pairs) h = ((h ^ a) * 1099511628211ull ^ b) * 1099511628211ull;
    return static_cast<double>(h >> 11);
}

// The validated run: every participant built and asked once, the first against brute force
// (or its sample), every other one against the first. Returns the first's pairs; `verified`
// says what checked them (the same for all: the others equal the first on every pair).
std::vector<index_pair> validated_self_pairs(const context& ctx, std::vector<participant>& ps,
                                             const std::vector<collide_box>& boxes, std::string& verified) {
    std::vector<index_pair> reference;
    for (std::size_t i = 0; i < ps.size(); ++i) {
        auto& p = *ps[i].index;
        p.build(boxes);
        auto pairs = p.self_pairs();
        if (!pairs.empty() && injected_fault(p.name())) pairs.pop_back();
        const std::string where = labelled(p) + " on boxes n=" + fmt_n(boxes.size());
        if (i == 0) {
            verified = validate_pairs(ctx, boxes, pairs, datasets::derive_seed(ctx.opt.seed, 0xC1u), where);
            reference = std::move(pairs);
        } else if (pairs != reference) {
            throw validation_error(where + ": " + std::to_string(pairs.size()) + " pairs, " + labelled(*ps[0].index) +
                                   " reports " + std::to_string(reference.size()) + " (or different ones)");
        }
    }
    if (ps.size() > 1) verified = check::all_of({verified, check::cross_all});
    return reference;
}

// ---- self pairs on several threads (issue 18's 2-core figure) ----------------------------

// Order-free checksums of a pair set (the parallel query's order depends on its slabs): a
// sum of one hash per pair, so parts summed separately add up to the whole.
std::uint64_t unordered_pair_hash(std::uint32_t a, std::uint32_t b) {
    std::uint64_t h = (std::uint64_t{a} << 32 | b) * 0x9E3779B97F4A7C15ull;
    h ^= h >> 29;
    return h;
}

std::uint64_t unordered_pair_hash_sum(const std::vector<index_pair>& pairs) {
    std::uint64_t sum = 0;
    for (const auto& [a, b] : pairs) sum += unordered_pair_hash(a, b);
    return sum;
}

double unordered_pairs_checksum(std::uint64_t hash_sum) { return static_cast<double>(hash_sum >> 11); }
double unordered_pairs_checksum(const std::vector<index_pair>& pairs) {
    return unordered_pairs_checksum(unordered_pair_hash_sum(pairs));
}

// collision_grid's pair query on one thread (for_each_self_pair) against the same query on
// every thread of the parallel back end (slabs of cell layers, collide/cell_sort_grid.hpp),
// interleaved, on the grid built once, in two ways of handing over the pairs:
//   * for_each_self_pair(spatial::par): the slabs' pairs given to the consumer on the calling
//     thread (params threads=N);
//   * for_each_self_pair_concurrently(spatial::par): each pair given to the consumer in the
//     thread that found it, one list per part (threads=N;delivery=concurrent).
// The consumer's work is the same in all three: each pair appended to a list, then the
// lists' checksum, which the concurrent delivery takes per part on every core. Every answer
// must equal the validated reference pair for pair before timing, and every timed run must
// reproduce its checksum. Rows: parallel_self_pairs for each, and a speedup per parallel one.
void run_parallel_self_pairs(context& ctx, const std::vector<collide_box>& boxes,
                             const std::vector<index_pair>& reference, const std::string& verified) {
    std::size_t threads = spatial::detail::parallel_threads();
    const std::string workload = "boxes";
    const std::size_t n = boxes.size();
    if (threads < 2) {
        ctx.prog.say("collision_grid parallel pairs: skipped (the parallel back end has one thread)");
        return;
    }
    std::vector<collide_box3> objects;
    objects.reserve(n);
    for (const auto& b : boxes) objects.push_back(to_object(b));
    const spatial::collision_grid<collide_box3> grid(objects.begin(), objects.end());
    enum class delivery { one_thread, calling_thread, concurrent };
    std::vector<index_pair> found;
    // One list per part, each on its own cache lines: adjacent vectors shared the line that
    // holds their end pointers, which both threads wrote at every pair (false sharing).
    struct alignas(64) part_list {
        std::vector<index_pair> pairs;
    };
    std::vector<part_list> parts(threads);
    std::vector<std::uint64_t> part_sums(threads);
    auto query = [&](delivery how) {
        if (how == delivery::concurrent) {
            for (auto& part : parts) part.pairs.clear();
            grid.for_each_self_pair_concurrently(spatial::par, spatial::pair_filter::exact, [&](std::size_t k, auto a, auto b) {
                parts[k].pairs.emplace_back(a.slot(), b.slot());
            });
            spatial::detail::parallel_chunks(threads, 1, [&](std::size_t first, std::size_t last) {
                for (std::size_t k = first; k < last; ++k) part_sums[k] = unordered_pair_hash_sum(parts[k].pairs);
            });
            std::uint64_t sum = 0;
            for (std::uint64_t x : part_sums) sum += x;
            return unordered_pairs_checksum(sum);
        }
        found.clear();
        auto add = [&](auto a, auto b) { found.emplace_back(a.slot(), b.slot()); };
        if (how == delivery::calling_thread) grid.for_each_self_pair(spatial::par, spatial::pair_filter::exact, add);
        else grid.for_each_self_pair(spatial::pair_filter::exact, add);
        return unordered_pairs_checksum(found);
    };
    const std::string where = "collision_grid on boxes n=" + fmt_n(n);
    const std::string on_n = " on " + std::to_string(threads) + " threads";
    const std::array<std::string, 3> told{" on one thread", on_n, on_n + ", delivered concurrently"};
    for (delivery how : {delivery::one_thread, delivery::calling_thread, delivery::concurrent}) {
        const double sum = query(how);
        if (how == delivery::concurrent) {
            found.clear();
            for (const auto& part : parts) found.insert(found.end(), part.pairs.begin(), part.pairs.end());
            if (sum != unordered_pairs_checksum(found))
                throw validation_error(where + told[2] + ": the checksum differs from the pairs' own");
        }
        sort_unique_pairs(found);
        if (found != reference)
            throw validation_error(where + told[static_cast<std::size_t>(how)] +
                                   ": the self pairs differ from the validated reference");
    }
    const double checksum = unordered_pairs_checksum(reference);
    const std::string t1 = "threads=1", tn = "threads=" + std::to_string(threads), tc = tn + ";delivery=concurrent";
    // A speed-up is a ratio of two medians: at least 7 interleaved rounds of each, also where
    // the static figures take fewer (a query of 1e6 boxes is about a tenth of a second; two
    // rounds made the 1e6 speed-ups of one day spread from 1.5 to 2.1 between runs).
    const std::size_t reps = std::max<std::size_t>(ctx.cfg.repetitions, 7);
    const auto t = time_interleaved({{where + ", self pairs" + told[0], [&] { return query(delivery::one_thread); }, checksum},
                                     {where + ", self pairs" + told[1], [&] { return query(delivery::calling_thread); }, checksum},
                                     {where + ", self pairs" + told[2], [&] { return query(delivery::concurrent); }, checksum}},
                                    1, reps);
    const std::string params = "overlaps_per_box=2";
    const row_sink rows{ctx, "collision_grid", "-", workload, n, check::all_of({verified, check::cross_all})};
    rows.add_timed("parallel_self_pairs", params + ";" + t1, t[0]);
    for (std::size_t k : {std::size_t{1}, std::size_t{2}}) {
        const std::string setting = params + ";" + (k == 1 ? tn : tc);
        rows.add_timed("parallel_self_pairs", setting, t[k]);
        rows.add("parallel_self_pairs", setting, "speedup", t[0].median_seconds / t[k].median_seconds, "x", check::derived);
    }
    std::ostringstream msg;
    msg.precision(3);
    msg << where << ", self pairs on " << threads << " threads: " << t[0].median_seconds << " -> " << t[1].median_seconds
        << " s (" << t[0].median_seconds / t[1].median_seconds << "x), delivered concurrently " << t[2].median_seconds
        << " s (" << t[0].median_seconds / t[2].median_seconds << "x)";
    ctx.prog.say(msg.str());
}

void run_static_boxes(context& ctx, std::size_t n) {
    const std::string workload = "boxes";
    const std::string params = "overlaps_per_box=2";
    const auto boxes = random_cubes(n, ctx.opt.seed);
    auto ps = participants(ctx, n, false, n >= ctx.cfg.sweep_min_n);
    if (ps.empty()) return;
    std::string verified;
    const std::vector<index_pair> reference = validated_self_pairs(ctx, ps, boxes, verified);
    const double checksum = pairs_checksum(reference);
    // Timed: each participant's build, then its query on the tree just built, interleaved
    // across participants (build A, pairs A, build B, pairs B, ...); every query must
    // reproduce the validated pairs. A round's build plus its query is what a one-shot broad
    // phase costs.
    std::vector<timed_work> work;
    for (auto& p : ps) {
        collide_index& index = *p.index;
        const std::string where = labelled(index) + " on boxes n=" + fmt_n(n);
        work.push_back({where + ", build",
                        [&index, &boxes] {
                            index.build(boxes);
                            return 0.0;
                        },
                        0.0});
        work.push_back({where + ", self pairs", [&index] { return pairs_checksum(index.self_pairs()); }, checksum});
    }
    const std::size_t reps = n >= 1000000 ? std::max<std::size_t>(1, ctx.cfg.repetitions - 1) : ctx.cfg.repetitions;
    const auto t = time_interleaved(work, 0, reps);
    // figure (operation) -> every participant's median, for the best_peer_ratio rows.
    std::map<std::string, std::vector<configured_figure>> figures;
    for (std::size_t i = 0; i < ps.size(); ++i) {
        const timing_result &build = t[2 * i], &query = t[2 * i + 1];
        const collide_index& index = *ps[i].index;
        const std::string& name = index.name();
        // A swept configuration's rows carry it after the params; the default's keep theirs.
        const std::string own = joined_params(params, index.configuration());
        // A build is checked by the pairs of the index it built.
        const row_sink rows{ctx, name, ps[i].bv, workload, n, verified};
        const timing_result both = summed_rounds(build, query);
        rows.add_timed("build", own, build);
        rows.add_timed("self_pairs", own, query);
        rows.add_timed("build_and_self_pairs", own, both);
        rows.add("self_pairs", own, "pairs", static_cast<double>(reference.size()), "count");
        rows.add("build", own, "memory", static_cast<double>(index.memory_bytes()), "bytes");
        const bool validated = verified != check::none;
        figures["build"].push_back({name, index.configuration(), build.median_seconds, validated});
        figures["self_pairs"].push_back({name, index.configuration(), query.median_seconds, validated});
        figures["build_and_self_pairs"].push_back({name, index.configuration(), both.median_seconds, validated});
        ctx.prog.say("collide boxes n=" + fmt_n(n) + " " + labelled(index) + ": build " +
                     std::to_string(build.median_seconds) + " s, pairs " + std::to_string(query.median_seconds) +
                     " s (" + std::to_string(reference.size()) + " pairs)");
    }
    // Issue 18's reference figure per static figure: collision_grid (the target's structure,
    // its default configuration) divided by the fastest validated configuration of any peer
    // (harness/best_peer.hpp), naming that peer and its every setting after the params.
    for (const auto& [operation, all] : figures) {
        const auto ours = std::find_if(all.begin(), all.end(), [](const auto& f) {
            return f.structure == "collision_grid" && f.configuration.empty();
        });
        if (ours == all.end()) continue;
        if (const auto best = best_peer(*ours, all))
            ctx.rows.push_back(ctx.scope(workload, n)
                                   .with_check(check::derived)
                                   .figure(best->structure, "-", operation, joined_params(params, best->configuration),
                                           "best_peer_ratio", best->ratio, "ratio"));
    }
    // Embree's devices cap oneTBB (process-wide) at one thread while they live ("threads=1"):
    // the participants go first.
    ps.clear();
    if (n >= ctx.cfg.sweep_min_n && ctx.wants("collision_grid") && verified != check::none)
        run_parallel_self_pairs(ctx, boxes, reference, verified);
}

// ---- moving boxes -------------------------------------------------------------------------

// Linear motion with bounces: each cube moves by a quarter of its side per step in a random
// direction; a cube leaving [0, 1]^3 has that velocity component reflected.
struct moving_cubes {
    std::vector<collide_box> boxes;
    std::vector<std::array<double, 3>> velocity;
    moving_cubes(std::size_t n, std::uint64_t seed) : boxes(random_cubes(n, seed)), velocity(n) {
        datasets::random_stream rng(datasets::derive_seed(seed, 0xC2u /* stream: velocities */));
        const double speed = cube_side(n) / 4;
        for (auto& v : velocity) {
            double l = 0;
            do {
                for (double& c : v) c = 2 * rng.uniform01<double>() - 1;
                l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            } while (l > 1 || l < 1e-3);
            for (double& c : v) c *= speed / l;
        }
    }
    void step() {
        for (std::size_t k = 0; k < boxes.size(); ++k)
            for (std::size_t i = 0; i < 3; ++i) {
                auto& b = boxes[k];
                const double e = b.hi[i] - b.lo[i];
                b.lo[i] += velocity[k][i];
                if (b.lo[i] < 0) b.lo[i] = -b.lo[i], velocity[k][i] = -velocity[k][i];
                if (b.lo[i] + e > 1) b.lo[i] = 2 * (1 - e) - b.lo[i], velocity[k][i] = -velocity[k][i];
                b.hi[i] = b.lo[i] + e;
            }
    }
};

// Each participant runs all its steps back to back, as a simulation loop would (motion,
// update, pairs; only update + pairs timed): interleaving the participants step by step
// would start every timed step with caches emptied by the others and by the validation.
// Each step's answer is kept (moved, not copied) and validated after the loop, BEFORE any
// row is recorded: the first participant's against brute force on the replayed scene, every
// other's against the first's, step by step.
void run_moving_boxes(context& ctx, std::size_t n) {
    const std::string workload = "moving_boxes";
    const std::string params = "overlaps_per_box=2;steps=" + std::to_string(ctx.cfg.steps) + ";speed=side/4";
    auto ps = participants(ctx, n, true);
    if (ps.empty()) return;
    const std::size_t steps = ctx.cfg.steps;
    std::vector<std::vector<index_pair>> reference(steps);  // the first participant's, validated
    const std::string reference_name = ps[0].index->name();
    std::string reference_check;  // what checked the first participant's pairs, every step
    std::vector<double> changed;
    for (std::size_t i = 0; i < ps.size(); ++i) {
        auto& p = *ps[i].index;
        auto* refitted = dynamic_cast<container_collide_index<spatial::bvh<collide_box3>>*>(&p);
        moving_cubes scene(n, ctx.opt.seed);  // the same motion for every participant
        auto t0 = std::chrono::steady_clock::now();
        p.build(scene.boxes);
        const double build_s = seconds_since(t0);
        std::vector<double> step_s, quality;
        std::vector<std::vector<index_pair>> answers(steps);
        step_s.reserve(steps);
        for (std::size_t s = 0; s < steps; ++s) {
            scene.step();
            t0 = std::chrono::steady_clock::now();
            p.update(scene.boxes);
            answers[s] = p.self_pairs();
            step_s.push_back(seconds_since(t0));
            // The refitted trees' decay: quality (expected nodes entered per ray through the
            // root; grows as a refitted tree ages), recorded with this step's time below.
            if (refitted) quality.push_back(refitted->container().quality());
        }
        // Validation, before any row of this participant is recorded.
        moving_cubes replay(n, ctx.opt.seed);
        for (std::size_t s = 0; s < steps; ++s) {
            replay.step();
            const std::string where = p.name() + " on moving_boxes n=" + fmt_n(n) + " step " + std::to_string(s + 1);
            if (i == 0) {
                reference_check = validate_pairs(ctx, replay.boxes, answers[s], datasets::derive_seed(ctx.opt.seed, 0xC300u + s), where);
                reference[s] = std::move(answers[s]);
            } else if (answers[s] != reference[s]) {
                throw validation_error(where + ": " + std::to_string(answers[s].size()) + " pairs, " + reference_name +
                                       " reports " + std::to_string(reference[s].size()) + " (or different ones)");
            }
        }
        if (i == 0) {
            spatial::collide::pair_set_tracker<std::uint32_t> tracker;
            for (const auto& r : reference) changed.push_back(static_cast<double>(tracker.step(r)));
        }
        const std::string name = p.name();
        // Every step's pairs were checked: the first participant's against the oracle, the
        // others' against the first's on every pair. The rows of the first participant are
        // written before the others exist, so only theirs say cross:all.
        const row_sink rows{ctx, name, ps[i].bv, workload, n,
                            check::all_of({reference_check, i > 0 ? check::cross_all : check::none})};
        const row_sink aabb_rows{ctx, name, "aabb", workload, n, rows.verified};
        for (std::size_t s = 0; s < quality.size(); ++s) {
            const std::string sp = params + ";step=" + std::to_string(s + 1);
            aabb_rows.add("update_and_self_pairs", sp, "quality", quality[s], "ratio");
            aabb_rows.add("update_and_self_pairs", sp, "time", step_s[s], "s");
        }
        const auto ts = summarize(step_s);
        const auto tc = summarize(changed);
        double total = 0;
        for (double x : step_s) total += x;
        rows.add("build", params, "time", build_s, "s");
        rows.add_timed("update_and_self_pairs", params, ts);
        rows.add("update_and_self_pairs", params, "steps_per_second", static_cast<double>(step_s.size()) / total, "1/s");
        rows.add("update_and_self_pairs", params, "pairs_changed_per_step", tc.median_seconds, "count", reference_check);
        ctx.prog.say("collide moving_boxes n=" + fmt_n(n) + " " + name + ": " +
                     std::to_string(ts.median_seconds * 1e3) + " ms per step (median of " +
                     std::to_string(step_s.size()) + ")");
        ps[i].index.reset();  // free its memory before the next participant runs
    }
}

// ---- triangles: BVH per bounding-volume type ----------------------------------------------

using triangle3 = spatial::objects::triangle<double, 3>;

std::vector<triangle3> random_triangles(std::size_t n, std::uint64_t seed) {
    datasets::random_stream rng(datasets::derive_seed(seed, 0xC4u /* stream: collide triangles */));
    // Vertices within +-h of a uniform centre; h chosen so a triangle meets a few others.
    const double h = 0.6 * std::cbrt(1.0 / static_cast<double>(n));
    std::vector<triangle3> out;
    out.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
        spatial::point<double, 3> c, v[3];
        for (std::size_t i = 0; i < 3; ++i) c[i] = h + rng.uniform01<double>() * (1 - 2 * h);
        for (auto& p : v)
            for (std::size_t i = 0; i < 3; ++i) p[i] = c[i] + h * (2 * rng.uniform01<double>() - 1);
        out.emplace_back(v[0], v[1], v[2]);
    }
    return out;
}

// The input index of each slot of `c`, bulk-built from `tris`: a bvh stores a batch in its leaf
// order, not in insertion order, so slots are matched back to the batch by value (both sides
// sorted by vertices; equal triangles are interchangeable, having the same partners).
template <class Container>
std::vector<std::uint32_t> input_index_of_slots(const Container& c, const std::vector<triangle3>& tris,
                                                const std::string& where) {
    const auto key = [](const triangle3& t) {
        std::array<double, 9> k{};
        for (std::size_t v = 0; v < 3; ++v)
            for (std::size_t a = 0; a < 3; ++a) k[3 * v + a] = t.vertex(v)[a];
        return k;
    };
    std::vector<std::uint32_t> by_value(tris.size());
    std::iota(by_value.begin(), by_value.end(), 0u);
    std::sort(by_value.begin(), by_value.end(), [&](std::uint32_t a, std::uint32_t b) { return key(tris[a]) < key(tris[b]); });
    std::vector<typename Container::const_iterator> stored;
    for (auto it = c.begin(); it != c.end(); ++it) stored.push_back(it);
    std::sort(stored.begin(), stored.end(), [&](const auto& a, const auto& b) { return key(*a) < key(*b); });
    if (stored.size() != tris.size()) throw validation_error(where + ": holds " + std::to_string(stored.size()) + " triangles, not " + std::to_string(tris.size()));
    std::vector<std::uint32_t> index(c.end().slot(), ~std::uint32_t{0});
    for (std::size_t k = 0; k < stored.size(); ++k) {
        if (key(*stored[k]) != key(tris[by_value[k]])) throw validation_error(where + ": holds a triangle it was not given");
        index[stored[k].slot()] = by_value[k];
    }
    return index;
}

// Pairs of iterators as pairs of input indices, each pair's smaller index first.
template <class Pairs>
std::vector<index_pair> input_pairs(const Pairs& pairs, const std::vector<std::uint32_t>& index) {
    std::vector<index_pair> out;
    out.reserve(pairs.size());
    for (const auto& [a, b] : pairs) out.emplace_back(std::minmax(index[a.slot()], index[b.slot()]));
    return out;
}
// The same, sorted: the exact pair set compared between trees and with brute force.
template <class Pairs>
std::vector<index_pair> sorted_input_pairs(const Pairs& pairs, const std::vector<std::uint32_t>& index) {
    std::vector<index_pair> out = input_pairs(pairs, index);
    std::sort(out.begin(), out.end());
    return out;
}

#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
// The oracle that shares no code with ours: for `sample` seeded triangles, every partner by a
// linear scan with CGAL's exact predicates (do_intersect on Epick, collide_oracles.hpp) behind
// an exact bounding-box reject, against the partners in `pairs`. Returns the check.
std::string validate_triangle_pairs_with_cgal(const std::vector<triangle3>& tris, const std::vector<index_pair>& pairs,
                                              std::size_t sample, std::uint64_t seed, const std::string& where) {
    const std::size_t n = tris.size();
    auto coords = [&](std::size_t i) {
        std::array<double, 9> c{};
        for (std::size_t v = 0; v < 3; ++v)
            for (std::size_t k = 0; k < 3; ++k) c[3 * v + k] = tris[i].vertex(v)[k];
        return c;
    };
    // Disjoint bounding boxes (closed) are an exact "no" before CGAL is asked.
    auto meets = [&](std::uint32_t i, std::uint32_t j) {
        return spatial::object_boxes_overlap(tris[i], tris[j]) && cgal_triangles_intersect(coords(i), coords(j));
    };
    return check::cgal_sample(check_sampled_partners(n, pairs, std::min(sample, n), seed, meets, where, "triangle",
                                                     "CGAL's exact predicates find"));
}
#endif

// The triangle pairs every bvh must reproduce, and what checked them.
struct triangle_reference {
    std::vector<index_pair> pairs;
    std::string verified;
};

// The first tree's exact pairs: against brute force (our narrow phase) up to brute_max_n, and
// for a sample of triangles against CGAL's exact predicates, at every n (when CGAL is built).
std::string validate_first_tree(const context& ctx, const std::vector<triangle3>& tris, const std::vector<index_pair>& exact,
                                const std::string& where) {
    std::string by_brute_force;
    if (tris.size() <= ctx.cfg.brute_max_n) {
        const spatial::brute_force<triangle3> brute(tris.begin(), tris.end());
        if (sorted_input_pairs(brute.self_pairs(), input_index_of_slots(brute, tris, where + ", brute force")) != exact)
            throw validation_error(where + ": exact pairs differ from brute force");
        by_brute_force = check::oracle_all;
    }
    std::string by_cgal;
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    by_cgal = validate_triangle_pairs_with_cgal(tris, exact, ctx.cfg.oracle_sample,
                                                datasets::derive_seed(ctx.opt.seed, 0xC5u), where);
#endif
    return check::all_of({by_brute_force, by_cgal});
}

// One bvh of one volume type on the triangle soup: its exact pairs validated (the first tree
// by validate_first_tree, later trees against the first, whose pairs become the reference),
// its candidates checked to hold every exact pair, then build, candidate search and exact
// search timed, in turn, repetition by repetition.
template <class Tree>
void bv_row(context& ctx, const structure_info& info, const std::vector<triangle3>& tris, triangle_reference& reference) {
    const std::size_t n = tris.size();
    const std::string name = bv_study_name(info), bv = info.bv, workload = "triangles", params = "soup";
    if (!ctx.wants(name) && !ctx.wants(info.family)) return;
    const std::string where = name + " on triangles n=" + fmt_n(n);
    Tree tree(tris.begin(), tris.end());
    // Every build of the same batch stores it in the same slots (the timed rebuilds too).
    const std::vector<std::uint32_t> index = input_index_of_slots(tree, tris, where);
    const auto exact = sorted_input_pairs(tree.self_pairs(spatial::pair_filter::exact), index);
    std::string verified;
    if (reference.pairs.empty() && reference.verified.empty()) {
        reference = {exact, validate_first_tree(ctx, tris, exact, where)};
        verified = reference.verified;
    } else if (exact != reference.pairs) {
        throw validation_error(where + ": exact pairs differ from the first tree's");
    } else {
        verified = check::all_of({reference.verified, check::cross_all});
    }
    auto candidate_pairs = sorted_input_pairs(tree.self_pairs(spatial::pair_filter::candidates), index);
    const std::size_t candidates = candidate_pairs.size();
    if (!std::includes(candidate_pairs.begin(), candidate_pairs.end(), exact.begin(), exact.end()))
        throw validation_error(where + ": an exact pair is missing from the candidates");
    candidate_pairs = {};
    const auto t = time_interleaved(
        {{where + ", build",
          [&] {
              tree.clear();
              tree.insert(tris.begin(), tris.end());
              return static_cast<double>(tree.size());
          },
          static_cast<double>(n)},
         {where + ", candidate pairs",
          [&] { return static_cast<double>(tree.self_pairs(spatial::pair_filter::candidates).size()); },
          static_cast<double>(candidates)},
         {where + ", exact pairs",
          [&] { return unordered_pairs_checksum(input_pairs(tree.self_pairs(spatial::pair_filter::exact), index)); },
          unordered_pairs_checksum(exact)}},
        0, ctx.cfg.repetitions);
    // The candidates have no oracle of their own: they are checked to hold every exact pair.
    const row_sink rows{ctx, name, bv, workload, n, verified};
    const row_sink candidate_rows{ctx, name, bv, workload, n, check::all_of({check::superset_all, verified})};
    rows.add_timed("build", params, t[0]);
    candidate_rows.add_timed("candidate_pairs", params, t[1]);
    rows.add_timed("exact_pairs", params, t[2]);
    candidate_rows.add("candidate_pairs", params, "pairs", static_cast<double>(candidates), "count");
    rows.add("exact_pairs", params, "pairs", static_cast<double>(exact.size()), "count");
    candidate_rows.add("candidate_pairs", params, "false_positive_ratio",
                       candidates ? static_cast<double>(candidates - exact.size()) / static_cast<double>(candidates) : 0.0,
                       "ratio");
    ctx.prog.say("collide triangles n=" + fmt_n(n) + " " + name + ": " + std::to_string(candidates) + " candidates, " +
                 std::to_string(exact.size()) + " exact, " + std::to_string(t[2].median_seconds) + " s");
}

// One bvh per volume type (the registry's in::collide_bv entries), in registry order: aabb
// first, whose pairs are checked against brute force and then are the others' reference.
void run_triangles(context& ctx, std::size_t n) {
    const auto tris = random_triangles(n, ctx.opt.seed);
    triangle_reference reference;
    for_each_structure<triangle3, in::collide_bv>([&]<class E>() {
        bv_row<typename E::template container<triangle3>>(ctx, E::info(), tris, reference);
    });
}

}  // namespace

namespace {

context make_context(const suite_options& options) {
    return make_suite_context("collide", options, preset(options.preset));
}

// ---- memory estimate (harness/memory_budget.hpp) ------------------------------------------

// Bytes per box one participant's structure may take, above what the tables measure at 1e6
// boxes (results/collide_1e6.csv, `memory`): FCL's managers 568 B (an fcl::CollisionObjectd
// and its fcl::Boxd per box), every other participant 26-206 B.
std::size_t structure_bytes_per_box(const std::string& name) { return name.rfind("fcl_", 0) == 0 ? 640 : 256; }

// What a case needs per box or triangle, for the check before the run allocates anything.
//   boxes         every participant's structure is alive at once (all are built and
//                 validated, then timed round by round), so their sum; with the tuning sweep
//                 each configuration counts. A full-preset run at 1e7 boxes with all eight
//                 1e6 participants and the sweep was killed by the OOM killer at 24 GB when
//                 this was one flat 256 B per box (tests/harness.cmake has the case).
//   moving_boxes  one participant at a time, plus every step's pairs of the reference and of
//                 the participant (about two 8 B pairs per box each).
//   triangles     one bvh at a time; the convex-hull one measures about 1.7 kB per triangle.
// Plus the case's own per object: the input, the reference pairs and one answer in flight.
std::size_t estimated_bytes_per_object(const context& ctx, const std::string& workload, std::size_t n) {
    constexpr std::size_t own = 128, pair_bytes_per_box = 2 * sizeof(index_pair);
    if (workload == "triangles") return own + 2048;
    const bool moving = workload == "moving_boxes";
    std::size_t sum = 0, largest = 0;
    for (const participant& p : participants(ctx, n, moving, !moving && n >= ctx.cfg.sweep_min_n)) {
        const std::size_t b = structure_bytes_per_box(p.index->name());
        sum += b;
        largest = std::max(largest, b);
    }
    return own + (moving ? largest + 2 * ctx.cfg.steps * pair_bytes_per_box : sum);
}

// The suite's independent cases: static boxes, moving boxes and triangles at each size.
std::vector<suite_case> collide_cases(context& ctx) {
    std::vector<std::string> workloads = ctx.opt.workloads;
    if (workloads.empty()) workloads = {"boxes", "moving_boxes", "triangles"};
    for (const auto& w : workloads)
        if (w != "boxes" && w != "moving_boxes" && w != "triangles")
            throw std::invalid_argument("unknown collide workload '" + w + "' (expected boxes, moving_boxes, triangles)");
    auto sizes = [&](const std::vector<std::size_t>& preset_sizes) { return ctx.opt.sizes.empty() ? preset_sizes : ctx.opt.sizes; };
    std::vector<suite_case> cases;
    for (const auto& w : workloads) {
        const auto& preset_sizes = w == "boxes" ? ctx.cfg.static_sizes : w == "moving_boxes" ? ctx.cfg.moving_sizes
                                                                                            : ctx.cfg.triangle_sizes;
        void (*run)(context&, std::size_t) = w == "boxes" ? &run_static_boxes : w == "moving_boxes" ? &run_moving_boxes
                                                                                                    : &run_triangles;
        for (std::size_t n : sizes(preset_sizes))
            cases.push_back({"collide/" + w + "/" + case_size(n), [&ctx, run, n] { run(ctx, n); }, n,
                             estimated_bytes_per_object(ctx, w, n)});
    }
    return cases;
}

}  // namespace

void run_collide_suite(const suite_options& options) {
    context ctx = make_context(options);
    ctx.run(collide_cases(ctx));
    ctx.finish();
}

std::vector<std::string> collide_case_ids(const suite_options& options) {
    context ctx = make_context(options);
    return ids_of(collide_cases(ctx), options);
}

}  // namespace harness
