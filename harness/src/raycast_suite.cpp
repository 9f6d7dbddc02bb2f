// The raycast suite (see raycast_suite.hpp). Flow for one mesh (generated or loaded):
//   1. the mesh and its triangles in double; rays of both kinds from the seed, unit
//      directions (so t is a distance);
//   2. the oracle brute_force<triangle> answers a seeded random sample of each kind (random,
//      not a stride, so the camera sample covers the whole image);
//   3. each structure is built (timed, repeated; the last build stays), answers every ray once,
//      and is validated: against the oracle on the sample, then against the reference
//      structure on every ray (harness/ray_validation.hpp for the tolerances and the
//      excuse of ambiguous rays);
//   4. timed repetitions, interleaved across structures (rep 1: A, B, C; rep 2: A, B, C, ...)
//      so that noise on the shared machine hits all alike; each must reproduce the checksum
//      of the validated answers;
//   5. rows are written atomically once the whole suite has passed.

#include "harness/raycast_suite.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "datasets/mesh_generators.hpp"
#include "datasets/random.hpp"
#include "harness/best_peer.hpp"
#include "harness/csv_writer.hpp"
#include "harness/fault_injection.hpp"
#include "harness/format.hpp"
#include "harness/mesh_loading.hpp"
#include "harness/object_ray_index.hpp"
#include "harness/our_ray_indexes.hpp"
#include "harness/progress.hpp"
#include "harness/ray_adapters.hpp"
#include "harness/ray_validation.hpp"
#include "harness/run_info.hpp"
#include "harness/structure_registry.hpp"
#include "harness/suite_cases.hpp"
#include "harness/suite_context.hpp"
#include "harness/timing.hpp"
#include "harness/tuning_sweep.hpp"
#include "harness/validation.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/objects/box.hpp"

#if defined(SPATIAL_HAVE_TBB)
#include <tbb/info.h>
#endif

namespace harness {
namespace {

using T = double;  // the suite's scalar; Embree rounds to float internally (ray_adapters.hpp)
using point3 = spatial::point<T, 3>;
using triangle3 = spatial::objects::triangle<T, 3>;

// Our containers in the suite: every registry entry in `part` (harness/structure_registry.hpp)
// that may be timed at n objects, each behind the suite's runtime interface `Index`.
template <class O, unsigned Part, template <class> class Index, class Base>
void add_registered(std::vector<std::unique_ptr<Base>>& out, std::size_t n, std::size_t oracle_max_n) {
    for_each_structure<O, Part>([&]<class E>() {
        const structure_info info = E::info();
        if (within_limits(info, n, 0, oracle_max_n))
            out.push_back(std::make_unique<Index<typename E::template container<O>>>(info.name, info.bv));
    });
}

struct preset_config {
    std::vector<std::size_t> sizes;  // triangles of the generated meshes
    std::size_t incoherent_rays;
    std::size_t camera_side;         // coherent rays: camera_side^2
    std::size_t repetitions;         // timed repetitions (median reported), after one warm-up
    std::size_t build_repetitions;
    std::size_t oracle_rays;         // rays of each kind checked against brute force
    std::size_t brute_max_n;         // brute_force timed (on oracle_rays rays) up to this n
    // The tuning sweep (harness/tuning_sweep.hpp: Embree's build qualities besides the
    // default) runs on generated meshes of at least this many triangles (the size asked for)
    // and on every real mesh: the sizes that decide the targets (quick's largest; every size
    // in full; smoke's largest, so that the smoke run exercises it).
    std::size_t sweep_min_n;
};

preset_config preset(const std::string& name) {
    if (name == "smoke") return {{1000, 4000}, 2048, 48, 2, 1, 48, 4000, 4000};
    // quick: three timed rounds, not five, to keep the main job's suites near 15 minutes
    // (issue 18 allows the quick preset fewer repetitions; the 1e6 targets run in full).
    if (name == "quick") return {{1000, 10000, 100000}, 16384, 128, 3, 3, 200, 10000, 100000};
    if (name == "full") return {{1000, 10000, 100000, 1000000}, 65536, 256, 5, 3, 128, 10000, 0};
    throw std::invalid_argument("unknown preset '" + name + "' (expected smoke, quick or full)");
}

using context = suite_context<preset_config>;

struct ray {
    point3 origin, direction;  // |direction| = 1
};

struct ray_set {
    std::string kind;    // incoherent | coherent
    std::string params;  // CSV params column
    std::vector<ray> rays;
    std::vector<std::size_t> oracle_sample;  // indices checked against brute force
};

point3 unit(double x, double y, double z) {
    const double l = std::sqrt(x * x + y * y + z * z);
    return {{x / l, y / l, z / l}};
}

// Origins uniform on the sphere of radius 1.5 * (half diagonal) around the box centre,
// towards points uniform in the box: a ray hits the mesh or passes near it, from any side.
std::vector<ray> incoherent_rays(const datasets::mesh_bounds& b, std::size_t count, std::uint64_t seed) {
    datasets::random_stream rng(datasets::derive_seed(seed, 0x7A1));
    const auto c = b.center();
    const double radius = 0.75 * b.diagonal();
    std::vector<ray> out;
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const point3 u = unit(rng.gaussian(), rng.gaussian(), rng.gaussian());
        point3 o, target;
        for (std::size_t d = 0; d < 3; ++d) {
            o[d] = c[d] + radius * u[d];
            target[d] = b.lo[d] + (b.hi[d] - b.lo[d]) * rng.uniform01<double>();
        }
        out.push_back({o, unit(target[0] - o[0], target[1] - o[1], target[2] - o[2])});
    }
    return out;
}

// A pinhole camera at 2.5 half-diagonals from the centre, looking at it, whose square image
// just contains the bounding sphere: one ray per pixel centre, row by row (coherent: nearby
// rays traverse nearby nodes).
std::vector<ray> camera_rays(const datasets::mesh_bounds& b, std::size_t side) {
    const auto c = b.center();
    const double r = b.diagonal() / 2, distance = 2.5 * r;
    const point3 back = unit(0.35, 0.45, 0.82);  // an oblique view, not along an axis
    point3 eye;
    for (std::size_t d = 0; d < 3; ++d) eye[d] = c[d] + distance * back[d];
    const point3 forward{{-back[0], -back[1], -back[2]}};
    const point3 right = unit(forward[1] * 1.0 - forward[2] * 0.0, forward[2] * 0.0 - forward[0] * 1.0,
                              forward[0] * 0.0 - forward[1] * 0.0);  // forward x (0, 0, 1)
    const point3 up{{right[1] * forward[2] - right[2] * forward[1], right[2] * forward[0] - right[0] * forward[2],
                     right[0] * forward[1] - right[1] * forward[0]}};
    const double half = r / std::sqrt(distance * distance - r * r);  // tan of the half field of view
    std::vector<ray> out;
    out.reserve(side * side);
    for (std::size_t j = 0; j < side; ++j)
        for (std::size_t i = 0; i < side; ++i) {
            const double x = ((static_cast<double>(i) + 0.5) / static_cast<double>(side) * 2 - 1) * half;
            const double y = (1 - (static_cast<double>(j) + 0.5) / static_cast<double>(side) * 2) * half;
            out.push_back({eye, unit(forward[0] + x * right[0] + y * up[0], forward[1] + x * right[1] + y * up[1],
                                     forward[2] + x * right[2] + y * up[2])});
        }
    return out;
}

// `sample` distinct ray indices drawn uniformly (seeded), in increasing order: a regular
// stride would pick one column of the camera image.
std::vector<std::size_t> random_sample(std::size_t count, std::size_t sample, std::uint64_t seed) {
    datasets::random_stream rng(datasets::derive_seed(seed, 0x5A3));
    std::vector<std::size_t> all(count);
    for (std::size_t i = 0; i < count; ++i) all[i] = i;
    sample = std::min(sample, count);
    for (std::size_t k = 0; k < sample; ++k) std::swap(all[k], all[k + rng.uniform_index(count - k)]);
    all.resize(sample);
    std::sort(all.begin(), all.end());
    return all;
}

struct answers {
    std::vector<ray_answer> per_ray;
    double checksum = 0;  // sum of hit t plus the hit count, in ray order
    std::size_t hits = 0;
    double nodes_visited = -1;  // per ray, when the structure reports it
};

double checksum_of(const ray_answer& a) { return a.hit ? a.t + 1 : 0.0; }

// One ray through the interface, as a ray_answer.
ray_answer cast(ray_index<T>& s, const ray& r) {
    ray_hit<T> hit;
    if (!s.intersect(r.origin, r.direction, std::numeric_limits<T>::infinity(), hit)) return {};
    return {true, hit.t};
}

// Issue 18's reference figure: bvh (its default configuration) divided by the fastest
// validated configuration of any peer (harness/best_peer.hpp), when both were measured: a
// `best_peer_ratio` row naming that peer and its every setting after the operation's params.
void add_best_peer_ratio(context& ctx, const row_scope& scope, const std::string& operation, const std::string& params,
                         const std::vector<configured_figure>& figures) {
    const auto ours = std::find_if(figures.begin(), figures.end(),
                                   [](const auto& f) { return f.structure == "bvh" && f.configuration.empty(); });
    if (ours == figures.end()) return;
    const auto best = best_peer(*ours, figures);
    if (!best) return;
    ctx.rows.push_back(scope.with_check(check::derived)
                           .figure(best->structure, "", operation, joined_params(params, best->configuration),
                                   "best_peer_ratio", best->ratio, "ratio"));
}

class mesh_measurement {
public:
    // sweep: the peers in every configuration of their tuning sweep too (preset_config).
    mesh_measurement(context& ctx, std::string label, datasets::triangle_mesh mesh, bool sweep)
        : ctx_(ctx), label_(std::move(label)), mesh_(std::move(mesh)), sweep_(sweep) {}

    void run() {
        triangles_ = datasets::to_triangles<T>(mesh_);
        bounds_ = datasets::bounds_of(mesh_);
        scale_ = scene_scale(mesh_);
        const std::uint64_t seed = datasets::derive_seed(ctx_.opt.seed, datasets::label_stream(label_));
        ray_set incoherent{"incoherent", "rays=incoherent", incoherent_rays(bounds_, ctx_.cfg.incoherent_rays, seed), {}};
        const std::string side = std::to_string(ctx_.cfg.camera_side);
        ray_set coherent{"coherent", "rays=coherent;camera=" + side + "x" + side, camera_rays(bounds_, ctx_.cfg.camera_side), {}};
        sets_ = {std::move(incoherent), std::move(coherent)};
        for (auto& s : sets_) s.oracle_sample = random_sample(s.rays.size(), ctx_.cfg.oracle_rays, seed);
        ctx_.prog.say("== " + label_ + " n=" + fmt_n(triangles_.size()) + " (" + std::to_string(mesh_.vertices.size()) +
                      " vertices)");

        oracle_answers();
        std::vector<std::unique_ptr<ray_index<T>>> structures;
        add_registered<triangle3, in::raycast, container_ray_index>(structures, triangles_.size(), ctx_.cfg.brute_max_n);
        for (auto& p : make_peer_ray_indices<T>(sweep_)) structures.push_back(std::move(p));
        std::erase_if(structures, [&](const auto& s) { return !ctx_.wants(s->name()); });
        // The oracle answers a sample of the rays only (rays_for): it goes last.
        std::stable_partition(structures.begin(), structures.end(), [](const auto& s) { return !is_oracle(s->name()); });
        measure(structures);
        // Embree's devices are created with "threads=1", which caps oneTBB (Embree's tasking
        // system, process-wide) at one thread while they live: release them first.
        structures.clear();
        if (ctx_.wants("bvh")) measure_parallel();
    }

private:
    std::string where(const std::string& structure, const ray_set& s) const {
        return structure + " " + s.kind + " rays on " + label_ + " n=" + fmt_n(triangles_.size());
    }

    void oracle_answers() {
        const spatial::brute_force<triangle3> oracle(triangles_.begin(), triangles_.end());
        oracle_.assign(sets_.size(), {});
        for (std::size_t k = 0; k < sets_.size(); ++k)
            for (std::size_t i : sets_[k].oracle_sample) {
                spatial::intersect_info<point3> info;
                const auto& r = sets_[k].rays[i];
                oracle_[k].push_back(oracle.intersect(r.origin, r.direction, info) ? ray_answer{true, info.hit_time}
                                                                                    : ray_answer{});
            }
    }

    static ray_tolerance tolerance_of(const ray_index<T>& s) {
        return s.name().rfind("embree", 0) == 0 ? float_peer_tolerance : double_peer_tolerance;
    }
    static ray_tolerance looser(const ray_tolerance& a, const ray_tolerance& b) {
        return {std::max(a.time_relative, b.time_relative), std::max(a.edge_relative, b.edge_relative)};
    }

    // Rays structure `s` answers: all of them, or the oracle sample for brute_force.
    std::vector<std::size_t> rays_for(const ray_index<T>& s, const ray_set& set) const {
        if (is_oracle(s.name())) return set.oracle_sample;
        std::vector<std::size_t> all(set.rays.size());
        for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
        return all;
    }

    answers answer(ray_index<T>& s, const ray_set& set, const std::vector<std::size_t>& which) {
        answers a;
        double nodes = 0;
        bool reports_nodes = true;
        for (std::size_t i : which) {
            a.per_ray.push_back(cast(s, set.rays[i]));
            a.checksum += checksum_of(a.per_ray.back());
            a.hits += a.per_ray.back().hit;
            const long long v = s.last_nodes_visited();
            if (v < 0) reports_nodes = false;
            else nodes += static_cast<double>(v);
        }
        if (reports_nodes && !which.empty()) a.nodes_visited = nodes / static_cast<double>(which.size());
        if (injected_fault(s.name()))
            for (auto& r : a.per_ray) r.t = r.hit ? 2 * r.t + 1 : r.t;
        return a;
    }

    // Returns the number of excused (ambiguous) disagreements; throws on a wrong answer.
    std::size_t validate(const ray_index<T>& s, std::size_t k, const std::vector<std::size_t>& which,
                         const answers& got, const answers* reference, const ray_tolerance& reference_tol,
                         const std::string& reference_name) {
        const ray_set& set = sets_[k];
        std::size_t excused = 0;
        const double far = 4 * scale_;
        auto check = [&](const ray_answer& mine, const ray_answer& want, std::size_t ray_index_in_set,
                         const ray_tolerance& tol, const std::string& against) {
            const auto& r = set.rays[ray_index_in_set];
            const auto verdict = compare_ray<T>(mine, want, triangles_, r.origin, r.direction, tol, scale_, far);
            if (verdict == ray_agreement::different) {
                std::ostringstream os;
                os.precision(17);
                os << where(labelled(s), set) << ", ray " << ray_index_in_set << " (origin " << r.origin
                   << ", direction " << r.direction << "): ";
                os << (mine.hit ? "hit at t=" + std::to_string(mine.t) : std::string("miss")) << ", but " << against
                   << " says " << (want.hit ? "hit at t=" + std::to_string(want.t) : std::string("miss"));
                throw validation_error(os.str());
            }
            return verdict == ray_agreement::excused_ambiguous;
        };
        // Against the oracle on its sample.
        std::map<std::size_t, std::size_t> position;  // ray index -> position in `which`
        for (std::size_t p = 0; p < which.size(); ++p) position[which[p]] = p;
        for (std::size_t j = 0; j < set.oracle_sample.size(); ++j) {
            const auto it = position.find(set.oracle_sample[j]);
            if (it == position.end()) continue;
            excused += check(got.per_ray[it->second], oracle_[k][j], set.oracle_sample[j], tolerance_of(s),
                             "brute-force oracle");
        }
        // Against the validated reference on every ray both answered.
        if (reference && which.size() == set.rays.size() && reference->per_ray.size() == set.rays.size())
            for (std::size_t i = 0; i < which.size(); ++i)
                excused += check(got.per_ray[i], reference->per_ray[i], i, looser(tolerance_of(s), reference_tol),
                                 "validated " + reference_name);
        return excused;
    }

    row_scope rows() const { return ctx_.scope(label_, triangles_.size()); }
    void add(result_row r) { ctx_.rows.push_back(std::move(r)); }

    // The reference for the every-ray check: the first structure of double precision that
    // answers every ray (ours, else CGAL) moves to the front; it is validated against the
    // oracle alone. Returns whether there is one.
    static bool put_reference_first(std::vector<std::unique_ptr<ray_index<T>>>& structures) {
        const auto it = std::find_if(structures.begin(), structures.end(), [](const auto& s) {
            return !is_oracle(s->name()) && tolerance_of(*s).time_relative < 1e-6;
        });
        if (it == structures.end()) return false;
        std::rotate(structures.begin(), it, it + 1);
        return true;
    }

    // Builds, interleaved; the last repetition leaves every structure built. A build must hold
    // every triangle.
    std::vector<timing_result> build_all(std::vector<std::unique_ptr<ray_index<T>>>& structures) {
        std::vector<timed_work> work;
        for (auto& s : structures)
            work.push_back({labelled(*s) + " on " + label_ + " n=" + fmt_n(triangles_.size()) + ", size after build",
                            [this, &s] {
                                s->build(mesh_, triangles_);
                                return static_cast<double>(s->size());
                            },
                            static_cast<double>(triangles_.size())});
        return time_interleaved(work, 0, ctx_.cfg.build_repetitions);
    }

    void measure(std::vector<std::unique_ptr<ray_index<T>>>& structures) {
        const bool have_reference = put_reference_first(structures);
        const std::vector<timing_result> builds = build_all(structures);
        std::vector<std::string> summary(structures.size());
        // A build is checked by its size and by the answers of the tree it built (each set's
        // checks; those of the first set stand for them all).
        std::vector<std::string> built(structures.size());
        for (std::size_t k = 0; k < sets_.size(); ++k) measure_set(structures, k, have_reference, summary, built);
        std::vector<configured_figure> build_figures;
        for (std::size_t i = 0; i < structures.size(); ++i) {
            const auto& s = *structures[i];
            const std::string build_check = check::all_of({check::size, built[i]});
            const row_scope scope = rows().with_check(build_check);
            const timing_result& b = builds[i];
            const double bytes = static_cast<double>(s.memory_bytes());
            // A swept configuration's rows carry it in their params; the default's keep theirs.
            const std::string params = s.configuration();
            add(scope.timed(s.name(), s.bv(), "build", params, "build_time", b, "s"));
            add(scope.figure(s.name(), s.bv(), "build", params, "memory_bytes", bytes, "B"));
            add(scope.figure(s.name(), s.bv(), "build", params, "bytes_per_triangle",
                             bytes / static_cast<double>(triangles_.size()), "B"));
            for (const auto& [metric, value] : s.build_metrics())
                add(scope.figure(s.name(), s.bv(), "build", params, metric, value, "ratio"));
            build_figures.push_back({s.name(), s.configuration(), b.median_seconds, build_check != check::none});
            std::ostringstream msg;
            msg.precision(3);
            msg << labelled(s) << " on " << label_ << " n=" << fmt_n(triangles_.size()) << ": build "
                << b.median_seconds << " s, " << bytes / static_cast<double>(triangles_.size()) << " B/tri"
                << summary[i];
            ctx_.prog.say(msg.str());
        }
        add_best_peer_ratio(ctx_, rows(), "build", "", build_figures);
    }

    // Ray set k: every structure answers once and is validated (the reference, first, against
    // the oracle; the others also against the reference on every ray), then the timed
    // repetitions, interleaved.
    void measure_set(std::vector<std::unique_ptr<ray_index<T>>>& structures, std::size_t k, bool have_reference,
                     std::vector<std::string>& summary, std::vector<std::string>& built) {
        const ray_set& set = sets_[k];
        const std::size_t S = structures.size();
        std::vector<answers> validated(S);
        std::vector<std::vector<std::size_t>> which(S);
        std::vector<std::size_t> excused(S, 0);
        std::vector<std::string> verified(S);
        std::vector<timed_work> work;
        const std::string oracle_check = set.oracle_sample.size() == set.rays.size()
                                             ? check::oracle_all
                                             : check::oracle_sample(set.oracle_sample.size());
        for (std::size_t i = 0; i < S; ++i) {
            auto& s = *structures[i];
            which[i] = rays_for(s, set);
            validated[i] = answer(s, set, which[i]);
            const bool against_reference = have_reference && i > 0;
            excused[i] = validate(s, k, which[i], validated[i], against_reference ? &validated[0] : nullptr,
                                  have_reference ? tolerance_of(*structures[0]) : double_peer_tolerance,
                                  have_reference ? structures[0]->name() : std::string());
            // validate() compares with the reference on every ray only when both answered all.
            const bool every_ray = against_reference && which[i].size() == set.rays.size() &&
                                   validated[0].per_ray.size() == set.rays.size();
            verified[i] = check::all_of({oracle_check, every_ray ? check::cross_all : check::none});
            if (every_ray) verified[0] = check::all_of({oracle_check, check::cross_all});
            work.push_back({where(labelled(s), set),
                            [&s, &set, &rays = which[i]] {
                                double sum = 0;
                                for (std::size_t r : rays) sum += checksum_of(cast(s, set.rays[r]));
                                return sum;
                            },
                            validated[i].checksum});
        }
        const std::vector<timing_result> times = time_interleaved(work, 1, ctx_.cfg.repetitions);
        std::vector<configured_figure> ray_figures;
        for (std::size_t i = 0; i < S; ++i) {
            const auto& s = *structures[i];
            const row_scope scope = rows().with_check(verified[i]);
            if (k == 0) built[i] = verified[i];
            const double per_ray_ns = 1e9 / static_cast<double>(which[i].size());
            const std::string params = joined_params(set.params, s.configuration());
            auto figure = [&](const std::string& metric, double value) {
                add(scope.figure(s.name(), s.bv(), "ray", params, metric, value, "count"));
            };
            add(scope.timed(s.name(), s.bv(), "ray", params, "time_per_op", times[i], "ns", per_ray_ns));
            ray_figures.push_back(
                {s.name(), s.configuration(), times[i].median_seconds * per_ray_ns, verified[i] != check::none});
            figure("rays", static_cast<double>(which[i].size()));
            figure("hits", static_cast<double>(validated[i].hits));
            figure("ambiguous_rays", static_cast<double>(excused[i]));
            if (validated[i].nodes_visited >= 0) figure("nodes_visited", validated[i].nodes_visited);
            std::ostringstream msg;
            msg.precision(3);
            msg << ", " << set.kind << " " << times[i].median_seconds * per_ray_ns / 1000 << " us/ray ("
                << validated[i].hits << "/" << which[i].size() << " hit";
            if (excused[i]) msg << ", " << excused[i] << " ambiguous";
            msg << ")";
            summary[i] += msg.str();
        }
        add_best_peer_ratio(ctx_, rows(), "ray", set.params, ray_figures);
    }

    using tree = spatial::bvh<triangle3>;

    // The checksum of a batched cast (hit t + 1 summed over the hits), leaving each ray's
    // answer in hits / infos.
    static double batch_checksum(const tree& t, std::span<const spatial::ray<point3>> rays, std::vector<tree::iterator>& hits,
                                 std::vector<spatial::intersect_info<point3>>& infos, bool parallel) {
        for (auto& i : infos) i = {};
        if (parallel) t.intersect_batch(rays, hits, infos, spatial::par);
        else t.intersect_batch(rays, hits, infos, spatial::seq);
        double sum = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) sum += hits[i] == t.end() ? 0.0 : infos[i].hit_time + 1;
        return sum;
    }

    // The parallel tree's batched answers must equal the one-thread batch on every ray, and
    // brute force on the oracle sample. Returns the validated checksum.
    double validate_parallel(const tree& one, const tree& many, std::span<const spatial::ray<point3>> rays) {
        const ray_set& set = sets_[0];
        const std::size_t n = rays.size();
        std::vector<tree::iterator> hits_one(n), hits_many(n);
        std::vector<spatial::intersect_info<point3>> infos_one(n), infos_many(n);
        const double checksum = batch_checksum(one, rays, hits_one, infos_one, false);
        batch_checksum(many, rays, hits_many, infos_many, true);
        for (std::size_t i = 0; i < n; ++i)
            if ((hits_one[i] == one.end()) != (hits_many[i] == many.end()) || !(infos_one[i].hit_time == infos_many[i].hit_time))
                throw validation_error(where("bvh", set) + ": the parallel build and batch disagree with one thread on ray " +
                                       std::to_string(i));
        for (std::size_t j = 0; j < set.oracle_sample.size(); ++j) {
            const std::size_t i = set.oracle_sample[j];
            const ray_answer& want = oracle_[0][j];
            const bool hit = hits_many[i] != many.end();
            if (hit != want.hit || (hit && !(infos_many[i].hit_time == want.t)))
                throw validation_error(where("bvh", set) + ": the parallel batch disagrees with brute force on ray " +
                                       std::to_string(i));
        }
        return checksum;
    }

    // Multi-threaded build (bvh(first, last, spatial::par), then prepare_rays(spatial::par))
    // and batched incoherent casts (intersect_batch with spatial::par) of `bvh` on every core
    // the back end uses, against the same work on one thread, interleaved in the same run and
    // validated before timing.
    void measure_parallel() {
        std::size_t threads = 1;
#if defined(SPATIAL_HAVE_TBB)
        threads = static_cast<std::size_t>(tbb::info::default_concurrency());
#endif
        if (threads < 2) {
            ctx_.prog.say("bvh parallel: skipped (the parallel back end has one thread)");
            return;
        }
        const ray_set& set = sets_[0];  // incoherent
        const std::string t1 = "threads=1", tn = "threads=" + std::to_string(threads);
        // Each round rebuilds the same tree object as every build of the suite does
        // (our_ray_indexes.hpp: clear(), which keeps the arrays' capacity, then one bulk
        // insertion into the empty tree, the constructor's build): constructing a fresh tree
        // per round timed the previous one's destruction and a second tree's allocation and
        // page faults too: serial work in both figures.
        tree one, many;
        auto build = [this](tree& t, bool parallel) {
            t.clear();
            if (parallel) {
                t.insert(triangles_.begin(), triangles_.end(), spatial::par);
                t.prepare_rays(spatial::par);
            } else {
                t.insert(triangles_.begin(), triangles_.end());
                t.prepare_rays();
            }
            return static_cast<double>(t.size());
        };
        const double n_tris = static_cast<double>(triangles_.size());
        const auto builds = time_interleaved({{where("bvh", set) + " " + t1 + " build", [&] { return build(one, false); }, n_tris},
                                              {where("bvh", set) + " " + tn + " build", [&] { return build(many, true); }, n_tris}},
                                             0, ctx_.cfg.build_repetitions);
        std::vector<spatial::ray<point3>> rays;
        rays.reserve(set.rays.size());
        for (const auto& r : set.rays) rays.push_back({r.origin, r.direction, T(0)});
        const double checksum = validate_parallel(one, many, rays);
        std::vector<tree::iterator> hits(rays.size());
        std::vector<spatial::intersect_info<point3>> infos(rays.size());
        const auto casts = time_interleaved(
            {{where("bvh", set) + " batched, " + t1, [&] { return batch_checksum(one, rays, hits, infos, false); }, checksum},
             {where("bvh", set) + " batched, " + tn, [&] { return batch_checksum(many, rays, hits, infos, true); }, checksum}},
            1, ctx_.cfg.repetitions);
        const double per_ray_ns = 1e9 / static_cast<double>(rays.size());
        // validate_parallel: the parallel answers against one thread's on every ray and brute
        // force on the sample (the one-thread batch is the same tree code, checked the same way).
        const std::string verified = check::all_of({check::oracle_sample(set.oracle_sample.size()), check::cross_all});
        const row_scope scope = rows().with_check(verified);
        const row_scope built = rows().with_check(check::all_of({check::size, verified}));
        const row_scope ratio = rows().with_check(check::derived);
        add(built.timed("bvh", "aabb", "parallel_build", t1, "build_time", builds[0], "s"));
        add(built.timed("bvh", "aabb", "parallel_build", tn, "build_time", builds[1], "s"));
        add(ratio.figure("bvh", "aabb", "parallel_build", tn, "speedup", builds[0].median_seconds / builds[1].median_seconds, "x"));
        add(scope.timed("bvh", "aabb", "parallel_ray", set.params + ";" + t1, "time_per_op", casts[0], "ns", per_ray_ns));
        add(scope.timed("bvh", "aabb", "parallel_ray", set.params + ";" + tn, "time_per_op", casts[1], "ns", per_ray_ns));
        add(ratio.figure("bvh", "aabb", "parallel_ray", set.params + ";" + tn, "speedup",
                         casts[0].median_seconds / casts[1].median_seconds, "x"));
        std::ostringstream msg;
        msg.precision(3);
        msg << "bvh parallel on " << label_ << " n=" << fmt_n(triangles_.size()) << ", " << threads << " threads: build "
            << builds[0].median_seconds << " -> " << builds[1].median_seconds << " s ("
            << builds[0].median_seconds / builds[1].median_seconds << "x), batched incoherent rays "
            << casts[0].median_seconds * per_ray_ns << " -> " << casts[1].median_seconds * per_ray_ns << " ns/ray ("
            << casts[0].median_seconds / casts[1].median_seconds << "x)";
        ctx_.prog.say(msg.str());
    }
    context& ctx_;
    std::string label_;
    datasets::triangle_mesh mesh_;
    bool sweep_;
    std::vector<triangle3> triangles_;
    datasets::mesh_bounds bounds_;
    double scale_ = 1;
    std::vector<ray_set> sets_;
    std::vector<std::vector<ray_answer>> oracle_;  // per ray set, per oracle sample ray
};

// ---- object workloads: boxes and points (issue 4: Embree user geometry) -------------------
// `boxes`: n axis-aligned boxes, centres uniform in the unit cube, half-sizes log-uniform in
// [0.002, 0.02] (1e5 / n)^(1/3) (so a ray crosses about as many at every n), thin rays.
// `points`: n points uniform in the unit cube cast with thick rays of radius 0.25 n^(-1/3)
// (a quarter of the mean spacing). Incoherent rays as for the meshes. Our containers and
// Embree's user geometry (with our exact double test in its callback) all run the same exact
// object tests, so answers must agree EXACTLY: with brute force on the oracle sample, and with
// the reference (bvh) on every ray; timed repetitions must reproduce the validated checksum.
template <class O>
class object_measurement {
public:
    object_measurement(context& ctx, std::string workload, std::size_t n) : ctx_(ctx), workload_(std::move(workload)), n_(n) {}

    void run() {
        const std::uint64_t seed = datasets::derive_seed(ctx_.opt.seed, datasets::label_stream(workload_ + std::to_string(n_)));
        make_objects(seed);
        thickness_ = std::is_same_v<O, point3> ? 0.25 / std::cbrt(static_cast<double>(n_)) : 0.0;
        datasets::mesh_bounds cube;
        cube.lo = {0, 0, 0};
        cube.hi = {1, 1, 1};
        rays_ = incoherent_rays(cube, ctx_.cfg.incoherent_rays, seed);
        sample_ = random_sample(rays_.size(), ctx_.cfg.oracle_rays, seed);
        params_ = std::is_same_v<O, point3> ? "rays=thick;objects=points" : "rays=incoherent;objects=boxes";
        ctx_.prog.say("== " + workload_ + " n=" + fmt_n(n_) + (thickness_ > 0 ? ", ray radius " + std::to_string(thickness_) : ""));

        spatial::brute_force<O> oracle;
        oracle.insert(objects_.begin(), objects_.end());
        for (std::size_t i : sample_) oracle_.push_back(answer_of(oracle, rays_[i]));

        auto structures = participants();
        if (structures.empty()) return;
        std::vector<timed_work> builds;
        for (auto& st : structures)  // object_ray_index reports no size: the rays validate the build
            builds.push_back({where(st->name()) + " build",
                              [this, &st] {
                                  st->build(objects_, thickness_);
                                  return 0.0;
                              },
                              0.0});
        const auto build_times = time_interleaved(builds, 0, ctx_.cfg.build_repetitions);
        std::vector<timed_work> casts;
        std::vector<std::size_t> hits(structures.size(), 0);
        for (std::size_t i = 0; i < structures.size(); ++i) {
            auto& st = *structures[i];
            const double checksum = validate(st, structures[0]->name(), i == 0, hits[i]);
            casts.push_back({where(st.name()),
                             [this, &st] {
                                 double sum = 0;
                                 for (const auto& r : rays_) sum += checksum_of(cast_object(st, r));
                                 return sum;
                             },
                             checksum});
        }
        const auto ray_times = time_interleaved(casts, 1, ctx_.cfg.repetitions);
        // validate(): brute force on the sample, and every ray against the first structure
        // (which the others then cross-check). The builds are checked by these answers alone.
        const std::string oracle_check =
            sample_.size() == rays_.size() ? check::oracle_all : check::oracle_sample(sample_.size());
        const std::string verified = check::all_of({oracle_check, structures.size() > 1 ? check::cross_all : check::none});
        std::vector<configured_figure> ray_figures, build_figures;
        for (std::size_t i = 0; i < structures.size(); ++i) {
            record(*structures[i], build_times[i], ray_times[i], hits[i], verified);
            const double per_ray_ns = 1e9 / static_cast<double>(rays_.size());
            ray_figures.push_back({structures[i]->name(), "", ray_times[i].median_seconds * per_ray_ns, true});
            build_figures.push_back({structures[i]->name(), "", build_times[i].median_seconds, true});
        }
        // Embree's user geometry has no setting swept: its registry configuration is the peer's.
        add_best_peer_ratio(ctx_, ctx_.scope(workload_, n_), "ray", params_, ray_figures);
        add_best_peer_ratio(ctx_, ctx_.scope(workload_, n_), "build", "", build_figures);
    }

private:
    // n objects, centres uniform in the unit cube (boxes: half-sizes as described above).
    void make_objects(std::uint64_t seed) {
        datasets::random_stream rng(seed);
        const double scale = std::cbrt(1e5 / static_cast<double>(n_));
        for (std::size_t i = 0; i < n_; ++i) {
            point3 c;
            for (std::size_t k = 0; k < 3; ++k) c[k] = rng.uniform01<double>();
            if constexpr (std::is_same_v<O, point3>) {
                objects_.push_back(c);
            } else {
                point3 lo, hi;
                for (std::size_t k = 0; k < 3; ++k) {
                    const double h = 0.002 * std::pow(10.0, rng.uniform01<double>()) * scale;
                    lo[k] = c[k] - h;
                    hi[k] = c[k] + h;
                }
                objects_.emplace_back(lo, hi);
            }
        }
    }

    // The registry's in::raycast_objects structures (not the oracle: it answered the sample
    // above) and Embree's user geometry, as --structure selects.
    std::vector<std::unique_ptr<object_ray_index<O>>> participants() const {
        std::vector<std::unique_ptr<object_ray_index<O>>> structures;
        add_registered<O, in::raycast_objects, container_object_ray_index>(structures, n_, 0);
        std::erase_if(structures, [](const auto& st) { return is_oracle(st->name()); });
#if defined(SPATIAL_HAVE_EMBREE) && SPATIAL_HAVE_EMBREE
        if constexpr (std::is_same_v<O, point3>) structures.push_back(make_embree_point_ray_index());
        else structures.push_back(make_embree_box_ray_index());
#endif
        std::erase_if(structures, [&](const auto& st) { return !ctx_.wants(st->name()); });
        return structures;
    }

    // Every ray once: equal to brute force on the oracle sample, and to the first structure
    // (`reference`, unless this is it) on every ray. Returns the answers' checksum.
    double validate(object_ray_index<O>& st, const std::string& reference, bool is_reference, std::size_t& hits) {
        std::vector<ray_answer> answers;
        double checksum = 0;
        for (const auto& r : rays_) answers.push_back(cast_object(st, r));
        for (const auto& a : answers) checksum += checksum_of(a), hits += a.hit;
        for (std::size_t j = 0; j < sample_.size(); ++j)
            if (!same(answers[sample_[j]], oracle_[j]))
                throw validation_error(where(st.name()) + ": differs from brute force on ray " + std::to_string(sample_[j]));
        if (is_reference) reference_answers_ = answers;
        for (std::size_t k = 0; k < rays_.size(); ++k)
            if (!same(answers[k], reference_answers_[k]))
                throw validation_error(where(st.name()) + ": differs from " + reference + " on ray " + std::to_string(k));
        return checksum;
    }

    void record(const object_ray_index<O>& st, const timing_result& b, const timing_result& t, std::size_t hits,
                const std::string& verified) {
        const row_scope scope = ctx_.scope(workload_, n_).with_check(verified);
        const double per_ray_ns = 1e9 / static_cast<double>(rays_.size());
        const double bytes = static_cast<double>(st.memory_bytes());
        auto add = [&](result_row r) { ctx_.rows.push_back(std::move(r)); };
        add(scope.timed(st.name(), st.bv(), "ray", params_, "time_per_op", t, "ns", per_ray_ns));
        add(scope.figure(st.name(), st.bv(), "ray", params_, "rays", static_cast<double>(rays_.size()), "count"));
        add(scope.figure(st.name(), st.bv(), "ray", params_, "hits", static_cast<double>(hits), "count"));
        add(scope.timed(st.name(), st.bv(), "build", "", "build_time", b, "s"));
        add(scope.figure(st.name(), st.bv(), "build", "", "memory_bytes", bytes, "B"));
        add(scope.figure(st.name(), st.bv(), "build", "", "bytes_per_object", bytes / static_cast<double>(n_), "B"));
        std::ostringstream msg;
        msg.precision(3);
        msg << where(st.name()) << ": build " << b.median_seconds << " s, " << t.median_seconds * per_ray_ns / 1000
            << " us/ray (" << hits << "/" << rays_.size() << " hit)";
        ctx_.prog.say(msg.str());
    }

    std::string where(const std::string& structure) const { return structure + " on " + workload_ + " n=" + fmt_n(n_); }
    static ray_answer cast_object(object_ray_index<O>& st, const ray& r) {
        ray_hit<T> hit;
        if (!st.intersect(r.origin, r.direction, std::numeric_limits<T>::infinity(), hit)) return {};
        return {true, hit.t};
    }
    ray_answer answer_of(const spatial::brute_force<O>& oracle, const ray& r) const {
        spatial::intersect_info<point3> info;
        if (!oracle.intersect(r.origin, r.direction, thickness_, info)) return {};
        return {true, info.hit_time};
    }
    static bool same(const ray_answer& a, const ray_answer& b) { return a.hit == b.hit && (!a.hit || a.t == b.t); }

    context& ctx_;
    std::string workload_;
    std::size_t n_;
    std::vector<O> objects_;
    double thickness_ = 0;
    std::vector<ray> rays_;
    std::vector<std::size_t> sample_;
    std::vector<ray_answer> oracle_;
    std::vector<ray_answer> reference_answers_;
    std::string params_;
};

}  // namespace

namespace {

context make_context(const suite_options& options) {
    context ctx = make_suite_context("raycast", options, preset(options.preset));
    if (!options.sizes.empty()) ctx.cfg.sizes = options.sizes;
    ctx.seeds["rays"] = options.seed;
    return ctx;
}

std::vector<std::filesystem::path> real_mesh_files(const suite_options& options) {
    std::vector<std::filesystem::path> files;
    if (!options.real_data_dir.empty() && std::filesystem::is_directory(options.real_data_dir))
        for (const auto& e : std::filesystem::directory_iterator(options.real_data_dir)) {
            std::string ext = e.path().extension().string();
            for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            const auto supported = supported_mesh_extensions();
            if (std::find(supported.begin(), supported.end(), ext) != supported.end()) files.push_back(e.path());
        }
    std::sort(files.begin(), files.end());
    return files;
}

// The suite's independent cases: each generated mesh, box set and point set at each size,
// then each real mesh.
std::vector<suite_case> raycast_cases(context& ctx) {
    std::vector<std::string> workloads = ctx.opt.workloads;
    if (workloads.empty()) {
        for (auto w : datasets::mesh_workload_names) workloads.emplace_back(w);
        workloads.emplace_back("boxes");
        workloads.emplace_back("points");
    }
    auto is_object_workload = [](const std::string& w) { return w == "boxes" || w == "points"; };
    for (const auto& w : workloads)
        if (!is_object_workload(w)) (void)datasets::generate_mesh(w, 0, 0);  // fail fast on a typo
    std::vector<suite_case> cases;
    const std::uint64_t seed = ctx.opt.seed;
    for (const auto& w : workloads)
        for (std::size_t n : ctx.cfg.sizes) {
            std::function<void()> run;
            if (w == "boxes") run = [&ctx, w, n] { object_measurement<spatial::objects::box<T, 3>>(ctx, w, n).run(); };
            else if (w == "points") run = [&ctx, w, n] { object_measurement<point3>(ctx, w, n).run(); };
            else
                run = [&ctx, w, n, seed] {
                    mesh_measurement(ctx, w, datasets::generate_mesh(w, n, seed), n >= ctx.cfg.sweep_min_n).run();
                };
            // Per triangle or object, every participant at once (memory_budget.hpp): ours, Embree's
            // and CGAL's trees, the mesh and its copies (tables: 100-200 B per triangle each).
            constexpr std::size_t bytes_per_object_all_participants = 512;
            cases.push_back({"raycast/" + w + "/" + case_size(n), std::move(run), n, bytes_per_object_all_participants});
        }
    for (const auto& f : real_mesh_files(ctx.opt)) {
        const std::string label = "real:" + f.filename().string();
        cases.push_back({"raycast/" + label,
                         [&ctx, label, f] { mesh_measurement(ctx, label, load_triangle_mesh(f), true).run(); }});
    }
    return cases;
}

}  // namespace

void run_raycast_suite(const suite_options& options) {
    context ctx = make_context(options);
    const auto real_files = real_mesh_files(options);
    if (!options.real_data_dir.empty() && supported_mesh_extensions().empty())
        ctx.prog.say("real meshes skipped: loading them needs CGAL (-DSPATIAL_WITH_CGAL=ON)");
    else if (!options.real_data_dir.empty() && real_files.empty())
        ctx.prog.say("no meshes in " + options.real_data_dir.string() + " (run scripts/fetch_meshes.sh)");
    ctx.run(raycast_cases(ctx));
    ctx.finish({{"real_meshes", std::to_string(real_files.size()) + " files"}});
}

std::vector<std::string> raycast_case_ids(const suite_options& options) {
    context ctx = make_context(options);
    return ids_of(raycast_cases(ctx), options);
}

}  // namespace harness
