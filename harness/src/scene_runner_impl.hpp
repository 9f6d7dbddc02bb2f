#pragma once
// The scene runner's implementation (see scene_runner.cpp for the step pipeline), included by
// the four translation units that instantiate it for (float | double) x (2D | 3D): one TU per
// combination compiles in parallel (a single TU took 3 minutes of CI's build).
#include "harness/scene_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "datasets/scene_motion.hpp"
#include "datasets/scene_objects.hpp"
#include "datasets/scene_queries.hpp"
#include "harness/answer_digest.hpp"
#include "harness/memory_budget.hpp"
#include "harness/mesh_loading.hpp"
#include "harness/progress.hpp"
#include "harness/fault_injection.hpp"
#include "harness/row_scope.hpp"
#include "harness/structure_registry.hpp"
#include "harness/timing.hpp"
#include "harness/validation.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/collide/narrow_phase.hpp"
#include "spatial/collide/pair_changes.hpp"

namespace harness {
namespace {

using pair32 = std::pair<std::uint32_t, std::uint32_t>;
constexpr std::size_t large_scene_objects = 20000;

// ---- one structure over one set's objects ----------------------------------------------

template <class O>
struct structure_iface {
    using T = typename O::scalar_type;
    using P = spatial::point_type_of<O>;
    virtual ~structure_iface() = default;
    virtual void build(const std::vector<O>& objects) = 0;
    // objects[i] changed for every i in `changed` (same count); restore the structure.
    virtual void update(const std::vector<O>& objects, const std::vector<std::uint32_t>& changed,
                        spatial::motion_strategy strategy) = 0;
    virtual void erase_swap_pop(std::uint32_t index) = 0;  // as the runner's array does
    virtual void append(const O& x) = 0;
    // The structure's own self-pair query with `filter` (pairs.hpp), as object indices (i < j),
    // in any order, into `out` (cleared first; its capacity is reused step after step).
    virtual void self_pairs(spatial::pair_filter filter, std::vector<pair32>& out) = 0;
    virtual std::vector<std::uint32_t> in_box(const P& lo, const P& hi) = 0;
    virtual std::optional<std::pair<std::uint32_t, T>> first_hit(const spatial::ray<P>& r) = 0;
    virtual std::vector<T> nearest_distances(const P& q, std::size_t k, const std::vector<O>& objects) = 0;
    virtual bool answers_queries() const = 0;  // rays, kNN, ranges
};

template <class C>
class structure_impl final : public structure_iface<typename C::value_type> {
public:
    using O = typename C::value_type;
    using T = typename O::scalar_type;
    using P = spatial::point_type_of<O>;
    static constexpr bool queries = requires(const C& c, P p, spatial::intersect_info<P> info) {
        c.intersect_object(p, p, T(0), info);
        c.find_nearest(p, std::size_t(1));
    };

    void build(const std::vector<O>& objects) override {
        c_.clear();
        handles_.clear();
        if constexpr (spatial::single_motion<C> || !queries) {
            for (const O& x : objects) handles_.push_back(c_.insert(x));  // handle containers: O(1) each
        } else {
            c_.insert(objects.begin(), objects.end());
            map_by_value(objects);
        }
        remap();
    }
    void update(const std::vector<O>& objects, const std::vector<std::uint32_t>& changed,
                spatial::motion_strategy strategy) override {
        if constexpr (spatial::motion_with_strategy<C>) {
            moves_.clear();
            for (std::uint32_t i : changed) moves_.emplace_back(handles_[i], objects[i]);
            c_.update(moves_.begin(), moves_.end(), strategy);
        } else if constexpr (spatial::single_motion<C>) {
            for (std::uint32_t i : changed) c_.update(handles_[i], objects[i]);
        } else {
            if (strategy == spatial::motion_strategy::rebuild) {
                build(objects);
                return;
            }
            for (std::uint32_t i : changed) {
                c_.erase(handles_[i]);
                handles_[i] = c_.insert(objects[i]);
            }
            remap();
        }
    }
    void erase_swap_pop(std::uint32_t index) override {
        c_.erase(handles_[index]);
        handles_[index] = handles_.back();
        handles_.pop_back();
        remap();
    }
    void append(const O& x) override {
        handles_.push_back(c_.insert(x));
        remap();
    }
    void self_pairs(spatial::pair_filter filter, std::vector<pair32>& out) override {
        out.clear();
        auto add = [&](const auto& a, const auto& b) {
            const std::uint32_t i = identity_ ? static_cast<std::uint32_t>(a.slot()) : index_[a.slot()];
            const std::uint32_t j = identity_ ? static_cast<std::uint32_t>(b.slot()) : index_[b.slot()];
            out.emplace_back(std::min(i, j), std::max(i, j));
        };
        // Unsorted when the structure offers it (collision_grid): the pair tracker sorts.
        if constexpr (spatial::streamed_self_pairs<C>)
            c_.for_each_self_pair(filter, add);
        else
            for (const auto& [a, b] : c_.self_pairs(filter)) add(a, b);
    }
    std::vector<std::uint32_t> in_box(const P& lo, const P& hi) override {
        std::vector<std::uint32_t> out;
        for (const auto& it : c_.find_in_box(lo, hi)) out.push_back(index_[it.slot()]);
        return out;
    }
    std::optional<std::pair<std::uint32_t, T>> first_hit(const spatial::ray<P>& r) override {
        if constexpr (queries) {
            spatial::intersect_info<P> info;
            const auto it = c_.intersect_object(r.origin, r.direction, r.thickness, info);
            if (it == c_.end()) return std::nullopt;
            return std::pair(index_[it.slot()], info.hit_time);
        } else {
            throw std::logic_error("no ray casts on this structure");
        }
    }
    std::vector<T> nearest_distances(const P& q, std::size_t k, const std::vector<O>& objects) override {
        if constexpr (queries) {
            std::vector<T> out;
            for (const auto& it : c_.find_nearest(q, k)) out.push_back(spatial::object_squared_distance(objects[index_[it.slot()]], q));
            return out;
        } else {
            throw std::logic_error("no nearest-neighbour queries on this structure");
        }
    }
    bool answers_queries() const override { return queries; }

private:
    // Containers whose bulk insert does not keep insertion order (kd_tree): handles matched
    // to objects by position in the iteration, checked by value.
    void map_by_value(const std::vector<O>& objects) {
        for (auto it = c_.begin(); it != c_.end(); ++it) handles_.push_back(it);
        bool in_order = handles_.size() == objects.size();
        for (std::size_t i = 0; i < objects.size() && in_order; ++i) in_order = *handles_[i] == objects[i];
        if (in_order) return;
        // Fall back to one insert per object (keeps handles exact; duplicates stay distinct).
        c_.clear();
        handles_.clear();
        for (const O& x : objects) handles_.push_back(c_.insert(x));
    }
    void remap() {
        std::uint32_t top = 0;
        for (const auto& h : handles_) top = std::max(top, static_cast<std::uint32_t>(h.slot()));
        index_.assign(static_cast<std::size_t>(top) + 1, 0);
        identity_ = true;
        for (std::uint32_t i = 0; i < handles_.size(); ++i) {
            index_[handles_[i].slot()] = i;
            identity_ &= handles_[i].slot() == i;
        }
    }

    C c_;
    std::vector<typename C::iterator> handles_;
    std::vector<std::uint32_t> index_;  // object index of each slot
    bool identity_ = false;             // slot i holds object i for every i (no lookup needed)
    std::vector<std::pair<typename C::iterator, O>> moves_;
};

// The registry's scene structure called `name` (harness/structure_registry.hpp).
template <class O>
std::unique_ptr<structure_iface<O>> make_structure(const std::string& name) {
    std::unique_ptr<structure_iface<O>> made;
    for_each_structure<O, in::scenes>([&]<class E>() {
        if (!made && E::info().name == name) made = std::make_unique<structure_impl<typename E::template container<O>>>();
    });
    if (made) return made;
    std::string known;
    for (const auto& s : scene_structure_names()) known += s + ", ";
    throw std::invalid_argument("unknown structure '" + name + "' (expected " + known + "or all)");
}

// Whether the scene structure `name` answers rays, kNN and range queries (collision_grid
// answers pairs only) and has its own batched motion (the large-scene choice of 'all').
template <class O>
std::pair<bool, bool> scene_structure_traits(const std::string& name) {
    std::pair<bool, bool> traits{false, false};
    for_each_structure<O, in::scenes>([&]<class E>() {
        using C = typename E::template container<O>;
        if (E::info().name == name) traits = {structure_impl<C>::queries, spatial::batched_motion<C>};
    });
    return traits;
}

// ---- one object set --------------------------------------------------------------------------

template <class T, std::size_t D>
struct set_base {
    using P = spatial::point<T, D>;
    virtual ~set_base() = default;
    virtual std::size_t size() const = 0;
    virtual bool moves() const = 0;
    virtual void step_motion(double dt) = 0;
    virtual void churn(const datasets::scene_description& scene, std::size_t step, scene_counters& k) = 0;
    virtual void build(scene_counters& k) = 0;
    virtual void update(spatial::motion_strategy strategy, scene_counters& k) = 0;
    virtual bool indexed() const = 0;
    virtual void make_index(const std::string& structure) = 0;
    virtual bool answers_queries() const = 0;
    virtual void self_pairs(spatial::pair_filter filter, std::vector<pair32>& out) = 0;  // (i < j), any order
    virtual std::vector<std::uint32_t> in_box(const P& lo, const P& hi) = 0;
    virtual std::vector<std::uint32_t> brute_in_box(const P& lo, const P& hi) const = 0;
    virtual void box_of(std::uint32_t i, P& lo, P& hi) const = 0;
    virtual std::optional<std::pair<std::uint32_t, T>> first_hit(const spatial::ray<P>& r) = 0;
    virtual std::optional<T> brute_first_hit(const spatial::ray<P>& r) const = 0;
    virtual std::vector<T> nearest_distances(const P& q, std::size_t k) = 0;
    virtual std::vector<T> brute_nearest_distances(const P& q, std::size_t k) const = 0;
    // Narrow phase by double dispatch: narrow(i, other, j) asks other to test its object j
    // against this set's object i, whatever the two object types.
    virtual bool narrow(std::uint32_t i, const set_base& other, std::uint32_t j) const = 0;
    virtual bool narrow_with(std::uint32_t j, const spatial::point<T, D>& x) const = 0;
    virtual bool narrow_with(std::uint32_t j, const spatial::objects::box<T, D>& x) const = 0;
    virtual bool narrow_with(std::uint32_t j, const spatial::objects::sphere<T, D>& x) const = 0;
    virtual bool narrow_with(std::uint32_t j, const spatial::objects::triangle<T, D>& x) const = 0;
};

template <class O>
class set_state final : public set_base<typename O::scalar_type, O::dimension> {
public:
    using T = typename O::scalar_type;
    static constexpr std::size_t D = O::dimension;
    using P = spatial::point<T, D>;

    set_state(const datasets::scene_description& scene, std::size_t index, std::vector<O> objects)
        : objects_(std::move(objects)), motion_(scene, index, objects_.size()) {}

    std::size_t size() const override { return objects_.size(); }
    bool moves() const override { return motion_.moves(); }
    void step_motion(double dt) override {
        motion_.step(std::span<O>(objects_), dt);
        changed_all_ = true;
    }
    void churn(const datasets::scene_description& scene, std::size_t step, scene_counters& k) override {
        for (std::size_t i : datasets::churn_erase_indices(scene, step, objects_.size())) {
            objects_[i] = objects_.back();
            objects_.pop_back();
            motion_.erase(i);
            if (index_) index_->erase_swap_pop(static_cast<std::uint32_t>(i));
            ++k.churn_erases;
        }
        for (const O& x : datasets::generate_churn_objects<O>(scene, step)) {
            objects_.push_back(x);
            motion_.insert(1);
            if (index_) index_->append(x);
            ++k.churn_inserts;
        }
    }
    bool indexed() const override { return index_ != nullptr; }
    void make_index(const std::string& structure) override { index_ = make_structure<O>(structure); }
    bool answers_queries() const override { return index_ && index_->answers_queries(); }
    void build(scene_counters& k) override {
        index_->build(objects_);
        changed_all_ = false;
        ++k.index_builds;
    }
    void update(spatial::motion_strategy strategy, scene_counters& k) override {
        if (!changed_all_) return;
        changed_.resize(objects_.size());
        for (std::uint32_t i = 0; i < changed_.size(); ++i) changed_[i] = i;
        index_->update(objects_, changed_, strategy);
        changed_all_ = false;
        ++k.index_updates;
    }
    void self_pairs(spatial::pair_filter filter, std::vector<pair32>& out) override { index_->self_pairs(filter, out); }
    std::vector<std::uint32_t> in_box(const P& lo, const P& hi) override { return index_->in_box(lo, hi); }
    std::vector<std::uint32_t> brute_in_box(const P& lo, const P& hi) const override {
        std::vector<std::uint32_t> out;
        for (std::uint32_t i = 0; i < objects_.size(); ++i)
            if (spatial::object_overlaps_box(objects_[i], lo, hi)) out.push_back(i);
        return out;
    }
    void box_of(std::uint32_t i, P& lo, P& hi) const override {
        for (std::size_t a = 0; a < D; ++a) lo[a] = spatial::object_lower(objects_[i], a), hi[a] = spatial::object_upper(objects_[i], a);
    }
    std::optional<std::pair<std::uint32_t, T>> first_hit(const spatial::ray<P>& r) override { return index_->first_hit(r); }
    std::optional<T> brute_first_hit(const spatial::ray<P>& r) const override {
        spatial::brute_force<O> b(objects_.begin(), objects_.end());
        spatial::intersect_info<P> info;
        if (b.intersect_object(r.origin, r.direction, r.thickness, info) == b.end()) return std::nullopt;
        return info.hit_time;
    }
    std::vector<T> nearest_distances(const P& q, std::size_t k) override { return index_->nearest_distances(q, k, objects_); }
    std::vector<T> brute_nearest_distances(const P& q, std::size_t k) const override {
        std::vector<T> d;
        for (const O& x : objects_) d.push_back(spatial::object_squared_distance(x, q));
        std::sort(d.begin(), d.end());
        d.resize(std::min(k, d.size()));
        return d;
    }
    bool narrow(std::uint32_t i, const set_base<T, D>& other, std::uint32_t j) const override {
        return other.narrow_with(j, objects_[i]);
    }
    bool narrow_with(std::uint32_t j, const spatial::point<T, D>& x) const override { return test(x, j); }
    bool narrow_with(std::uint32_t j, const spatial::objects::box<T, D>& x) const override { return test(x, j); }
    bool narrow_with(std::uint32_t j, const spatial::objects::sphere<T, D>& x) const override { return test(x, j); }
    bool narrow_with(std::uint32_t j, const spatial::objects::triangle<T, D>& x) const override { return test(x, j); }

private:
    template <class X>
    bool test(const X& x, std::uint32_t j) const {
        return spatial::collide::narrow_phase(x, objects_[j]);
    }

    std::vector<O> objects_;
    datasets::scene_motion<O> motion_;
    std::unique_ptr<structure_iface<O>> index_;
    bool changed_all_ = false;
    std::vector<std::uint32_t> changed_;
};

// ---- the run -------------------------------------------------------------------------------

spatial::motion_strategy to_motion(datasets::update_strategy s) {
    switch (s) {
        case datasets::update_strategy::refit: return spatial::motion_strategy::refit;
        case datasets::update_strategy::rebuild: return spatial::motion_strategy::rebuild;
        case datasets::update_strategy::reinsert: return spatial::motion_strategy::reinsert;
        case datasets::update_strategy::automatic: break;
    }
    return spatial::motion_strategy::automatic;
}

struct stage_times {
    std::map<std::string, std::vector<double>> seconds;
    std::map<std::string, std::vector<double>> counts;
};

template <class T, std::size_t D>
class scene_run {
public:
    using P = spatial::point<T, D>;
    // `validated`: every step's answers are checked against brute force as they come (the
    // validated pass); otherwise none is, and the answers are only logged (the timed pass,
    // whose log must then equal the validated pass's: first_different_step).
    scene_run(const datasets::scene_description& scene, std::string structure, std::size_t steps, scene_counters& k,
              const progress& prog, bool validated = true)
        : scene_(scene), structure_(std::move(structure)), steps_(steps), k_(k), prog_(prog), validated_(validated) {}

    // Per-stage seconds of every step, and a digest of the answers of every step in order
    // (answer_digest.hpp: 8 bytes a step, not the answers): the pair sets (sorted; also
    // compared across structures), each ray's first hit, each nearest query's distances,
    // each range query's objects.
    stage_times times;
    std::vector<std::uint64_t> pair_log, ray_log, nearest_log, range_log;

    // The first step (from 1) whose answers differ from `other`'s, or 0 when every step's
    // agree. Object sets are deterministic and a structure answers the same state the same
    // way, so two passes of one structure over one scene log the same answers.
    std::size_t first_different_step(const scene_run& other) const {
        std::size_t step = 0;
        for (const std::size_t s : {first_different_step(pair_log, other.pair_log, pair_entries_per_step(scene_)),
                                    first_different_step(ray_log, other.ray_log, 1),
                                    first_different_step(nearest_log, other.nearest_log, 1),
                                    first_different_step(range_log, other.range_log, 1)})
            if (s != 0 && (step == 0 || s < step)) step = s;
        return step;
    }
    // The first step (from 1) at which two logs of `per_step` digests a step differ, or 0.
    static std::size_t first_different_step(const std::vector<std::uint64_t>& x, const std::vector<std::uint64_t>& y,
                                            std::size_t per_step) {
        if (x == y) return 0;
        const auto at = std::mismatch(x.begin(), x.end(), y.begin(), y.end());
        return static_cast<std::size_t>(at.first - x.begin()) / per_step + 1;
    }
    // Pair sets logged per step: one per collide entry.
    static std::size_t pair_entries_per_step(const datasets::scene_description& scene) {
        return scene.collide ? std::max<std::size_t>(1, scene.collide->between.size()) : 1;
    }
    // Frees the structures and objects once the pass has run (its times and answers stay).
    void release_sets() {
        objects_at_end_ = object_count();
        sets_.clear();
    }
    std::size_t objects_at_end() const { return objects_at_end_; }

    // What checked the answers behind a stage's or a count's rows (check.hpp): the pair stages
    // by the pair check (plus `pairs_cross`, when they also equal another structure's), each
    // query stage by its own, and the stages every query depends on (build, motion, churn,
    // update, the whole step) by all the checks the scene ran.
    std::string check_of(const std::string& what, const std::string& pairs_cross) const {
        auto word = [&](const std::string& kind) {
            const auto it = checked_.find(kind);
            if (it == checked_.end() || it->second.checked == 0) return check::none;
            const std::string name = kind == "candidate_pairs" ? "superset" : "oracle";
            return it->second.checked == it->second.total ? name + ":all"
                                                          : name + ":sample=" + std::to_string(it->second.checked);
        };
        const std::string pairs = check::all_of({word("pairs"), word("candidate_pairs"), pairs_cross});
        if (what.rfind("collide_", 0) == 0 || what == "pairs" || what == "pairs_changed") return pairs;
        if (what == "raycast" || what == "ray_hits") return word("rays");
        if (what == "nearest") return word("nearest");
        if (what == "range" || what == "range_results") return word("range");
        return check::all_of({pairs, word("rays"), word("nearest"), word("range")});
    }

    void run() {
        load_sets();
        const bool any_queries = scene_.raycast || scene_.nearest || scene_.range;
        std::vector<bool> queried(sets_.size(), false);
        if (scene_.collide)
            for (auto [a, b] : scene_.collide->between) queried[a] = queried[b] = true;
        if (scene_.raycast)
            for (std::size_t t : scene_.raycast->targets) queried[t] = true;
        if (scene_.nearest) queried[scene_.nearest->target] = true;
        if (scene_.range) queried[scene_.range->target] = true;
        for (std::size_t s = 0; s < sets_.size(); ++s) {
            if (!queried[s]) continue;  // no index for queries nobody makes
            sets_[s]->make_index(structure_);
            if (any_queries && !sets_[s]->answers_queries() && !only_collide_target(s))
                throw std::invalid_argument(structure_ + " answers pair queries only; scene " + scene_.name +
                                            " also casts rays or asks nearest/range queries (choose bvh, kd_tree, octree, uniform_grid or brute_force)");
            const auto t0 = std::chrono::steady_clock::now();
            sets_[s]->build(k_);
            times.seconds["build"].push_back(seconds_since(t0));
        }
        const auto strategy = scene_.collide ? to_motion(scene_.collide->strategy) : spatial::motion_strategy::automatic;
        std::vector<spatial::collide::pair_set_tracker<std::uint32_t>> trackers(scene_.collide ? scene_.collide->between.size() : 0);
        for (std::size_t step = 0; step < steps_; ++step) {
            step_seconds_ = 0;  // the sum of this step's timed stages (validation excluded)
            if (scene_.moves()) {
                const auto t0 = std::chrono::steady_clock::now();
                for (auto& s : sets_)
                    if (s->moves()) {
                        s->step_motion(scene_.time_step);
                        ++k_.motion_steps;
                    }
                record("motion", seconds_since(t0));
            }
            if (scene_.churn) {
                const auto t0 = std::chrono::steady_clock::now();
                sets_[scene_.churn->target]->churn(scene_, step, k_);
                record("churn", seconds_since(t0));
            }
            if (scene_.moves()) {
                const auto t0 = std::chrono::steady_clock::now();
                for (auto& s : sets_)
                    if (s->indexed() && s->moves()) s->update(strategy, k_);
                record("update", seconds_since(t0));
            }
            if (scene_.collide) collide_step(step, trackers);
            if (scene_.raycast) raycast_step(step);
            if (scene_.nearest) nearest_step(step);
            if (scene_.range) range_step(step);
            times.seconds["step"].push_back(step_seconds_);
            if ((step + 1) % std::max<std::size_t>(1, steps_ / 5) == 0 || step + 1 == steps_)
                prog_.say("scene " + scene_.name + " [" + structure_ + "] " + (validated_ ? "" : "timed ") + "step " +
                          std::to_string(step + 1) + "/" + std::to_string(steps_));
        }
    }
    std::size_t object_count() const {
        std::size_t n = 0;
        for (const auto& s : sets_) n += s->size();
        return n;
    }

private:
    void record(const std::string& stage, double seconds) {
        times.seconds[stage].push_back(seconds);
        step_seconds_ += seconds;
    }
    bool only_collide_target(std::size_t s) const {
        if (scene_.raycast && std::find(scene_.raycast->targets.begin(), scene_.raycast->targets.end(), s) != scene_.raycast->targets.end())
            return false;
        if (scene_.nearest && scene_.nearest->target == s) return false;
        if (scene_.range && scene_.range->target == s) return false;
        return true;
    }
    void load_sets() {
        for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
            const auto& set = scene_.objects[i];
            datasets::with_object_type<T, D>(set.kind, [&](auto type) {
                using O = typename decltype(type)::type;
                std::vector<O> objects;
                if constexpr (std::is_same_v<O, spatial::objects::triangle<T, 3>>) {
                    if (set.mesh && set.mesh->from == datasets::mesh_source::origin::file) {
                        try {
                            objects = datasets::mesh_objects<T>(load_triangle_mesh(set.mesh->file), *set.mesh);
                        } catch (const std::exception& e) {
                            throw std::invalid_argument(scene_.file + ":" + std::to_string(set.position.line) + ": set '" +
                                                        set.name + "': cannot load mesh " + set.mesh->file.string() + ": " + e.what());
                        }
                    }
                }
                if (objects.empty()) objects = datasets::generate_objects<O>(scene_, i);
                sets_.push_back(std::make_unique<set_state<O>>(scene_, i, std::move(objects)));
                return 0;
            });
        }
    }

    // One collide step per `between` entry: the pairs (collide_pairs), for pairs between two
    // sets the runner's narrow phase (collide_narrow_phase), then the pairs that appeared and
    // disappeared since the last step (collide_pair_changes): the whole of what a simulation
    // step asks of collision detection. Validation (untimed) sits between the stages.
    void collide_step(std::size_t step, std::vector<spatial::collide::pair_set_tracker<std::uint32_t>>& trackers) {
        const bool exact = scene_.collide->filter == datasets::collide_filter::exact;
        double query = 0, narrow = 0, changes = 0;
        bool narrow_ran = false;
        std::size_t total = 0, changed = 0;
        for (std::size_t e = 0; e < scene_.collide->between.size(); ++e) {
            const auto [a, b] = scene_.collide->between[e];
            auto t0 = std::chrono::steady_clock::now();
            std::vector<pair32>& pairs = pairs_;
            if (a == b) {
                // The structure's own query: with `exact`, its narrow phase runs inside it
                // (collide::narrow_phase, the same test as the runner's), so a structure that
                // can skip it for boxes (whose box test is the exact test) does.
                sets_[a]->self_pairs(exact ? spatial::pair_filter::exact : spatial::pair_filter::candidates, pairs);
                if (exact) ++k_.exact_self_pair_queries;
            } else {
                // Bipartite: each object of b against a's structure, by its box. The box query
                // reports objects that meet the box by each object's own (floating-point) test,
                // e.g. triangle-box; grown by a relative 2^-20 it cannot miss an object that
                // truly touches the box, and the exact box filter below keeps the candidate
                // set the same for every structure (boxes overlap).
                pairs.clear();
                P lo, hi;
                for (std::uint32_t j = 0; j < sets_[b]->size(); ++j) {
                    sets_[b]->box_of(j, lo, hi);
                    P glo = lo, ghi = hi;
                    for (std::size_t d = 0; d < D; ++d) {
                        const T m = std::max({std::abs(lo[d]), std::abs(hi[d]), hi[d] - lo[d]}) * T(0x1p-20);
                        glo[d] -= m;
                        ghi[d] += m;
                    }
                    for (std::uint32_t i : sets_[a]->in_box(glo, ghi)) {
                        P alo, ahi;
                        sets_[a]->box_of(i, alo, ahi);
                        bool overlap = true;  // candidates: boxes overlap (the same rule as self pairs)
                        for (std::size_t d = 0; d < D; ++d) overlap &= !(ahi[d] < lo[d] || hi[d] < alo[d]);
                        if (overlap) pairs.emplace_back(i, j);
                    }
                }
            }
            ++k_.pair_queries;
            query += seconds_since(t0);
            if (exact && a != b) {
                t0 = std::chrono::steady_clock::now();
                std::erase_if(pairs, [&](const pair32& p) {
                    ++k_.narrow_phase_tests;
                    return !sets_[a]->narrow(p.first, *sets_[b], p.second);
                });
                narrow += seconds_since(t0);
                narrow_ran = true;
            }
            // The timed pass's own fault (`<structure>@timed`) is caught by comparing its
            // answers with the validated pass's, the only check it has.
            if (!pairs.empty() && injected_fault(validated_ ? structure_ : structure_ + "@timed")) pairs.pop_back();
            if (validated_) validate_pairs(a, b, pairs, step, exact);
            t0 = std::chrono::steady_clock::now();
            // Object indices are ids except across churn (swap-and-pop renames the last
            // object): the pairs changed figure then also counts the renamed ones.
            changed += trackers[e].step(pairs);
            changes += seconds_since(t0);
            total += trackers[e].pairs().size();
            pair_log.push_back(digest_of(trackers[e].pairs()));  // sorted: compared across structures
        }
        record("collide_pairs", query);
        if (narrow_ran) record("collide_narrow_phase", narrow);
        record("collide_pair_changes", changes);
        times.counts["pairs"].push_back(static_cast<double>(total));
        times.counts["pairs_changed"].push_back(static_cast<double>(changed));
    }
    // Against brute force's exact pairs, for every object of small sets, else for a sample:
    // exact pairs must be equal; candidate pairs (each structure's own broad phase, so they
    // differ between structures) must contain them.
    void validate_pairs(std::size_t a, std::size_t b, const std::vector<pair32>& pairs, std::size_t step,
                        bool exact) {
        const std::size_t na = sets_[a]->size(), nb = sets_[b]->size();
        const std::size_t sample = na * nb <= 4000000 ? na : 64;
        note_checked(exact ? "pairs" : "candidate_pairs", std::min(sample, na), na);
        // The partners of the sampled objects only: one list per sample, not one per object
        // (a hundred thousand small vectors allocated and freed at every step of a large scene
        // made the validation slow and churned the heap between the timed stages).
        std::vector<std::uint32_t> sampled(sample);
        std::vector<std::uint32_t> sample_of(na, std::numeric_limits<std::uint32_t>::max());
        for (std::size_t s = 0; s < sample; ++s) {
            sampled[s] = static_cast<std::uint32_t>(sample == na ? s : (s * 2654435761u + step) % na);
            sample_of[sampled[s]] = static_cast<std::uint32_t>(s);  // a repeated object keeps its last sample
        }
        std::vector<std::vector<std::uint32_t>> got(sample);
        for (const auto& [i, j] : pairs) {
            if (sample_of[i] != std::numeric_limits<std::uint32_t>::max()) got[sample_of[i]].push_back(j);
            if (a == b && sample_of[j] != std::numeric_limits<std::uint32_t>::max()) got[sample_of[j]].push_back(i);
        }
        for (std::size_t s = 0; s < sample; ++s) {
            const std::uint32_t i = sampled[s];
            std::vector<std::uint32_t> want;
            for (std::uint32_t j = 0; j < nb; ++j)
                if ((a != b || j != i) && sets_[a]->narrow(i, *sets_[b], j)) want.push_back(j);
            auto g = got[sample_of[i]];
            std::sort(g.begin(), g.end());
            g.erase(std::unique(g.begin(), g.end()), g.end());
            if (exact ? g != want : !std::includes(g.begin(), g.end(), want.begin(), want.end()))
                throw validation_error("scene " + scene_.name + " [" + structure_ + "] step " + std::to_string(step + 1) +
                                       ": object " + std::to_string(i) + " of set '" + scene_.objects[a].name + "' has " +
                                       std::to_string(g.size()) + " partners, brute force finds " + std::to_string(want.size()));
        }
    }
    void raycast_step(std::size_t step) {
        const auto rays = datasets::generate_rays<T, D>(scene_, step);
        const auto t0 = std::chrono::steady_clock::now();
        std::size_t hits = 0;
        std::vector<std::optional<T>> first(rays.size());
        for (std::size_t r = 0; r < rays.size(); ++r) {
            for (std::size_t t : scene_.raycast->targets) {
                const auto h = sets_[t]->first_hit(rays[r]);
                if (h && (!first[r] || h->second < *first[r])) first[r] = h->second;
            }
            hits += first[r].has_value();
            ++k_.rays_cast;
        }
        record("raycast", seconds_since(t0));
        times.counts["ray_hits"].push_back(static_cast<double>(hits));
        ray_log.push_back(digest_of(first));
        if (!validated_) return;
        note_checked("rays", 0, rays.size());
        for (std::size_t r = step % 7; r < rays.size(); r += std::max<std::size_t>(1, rays.size() / 16)) {  // sampled check
            note_checked("rays", 1, 0);
            std::optional<T> want;
            for (std::size_t t : scene_.raycast->targets) {
                const auto h = sets_[t]->brute_first_hit(rays[r]);
                if (h && (!want || *h < *want)) want = h;
            }
            if (want.has_value() != first[r].has_value() || (want && !same_distance(*want, *first[r])))
                throw validation_error("scene " + scene_.name + " [" + structure_ + "] step " + std::to_string(step + 1) +
                                       ": ray " + std::to_string(r) + " disagrees with brute force");
        }
    }
    void nearest_step(std::size_t step) {
        const auto queries = datasets::generate_nearest_queries<T, D>(scene_, step);
        auto& set = *sets_[scene_.nearest->target];
        const std::size_t k = scene_.nearest->k;
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::vector<T>> got;
        for (const auto& q : queries) {
            got.push_back(set.nearest_distances(q, k));
            ++k_.nearest_queries;
        }
        record("nearest", seconds_since(t0));
        nearest_log.push_back(digest_of(got));
        if (!validated_) return;
        note_checked("nearest", 0, queries.size());
        for (std::size_t q = step % 5; q < queries.size(); q += std::max<std::size_t>(1, queries.size() / 16)) {
            note_checked("nearest", 1, 0);
            const auto want = set.brute_nearest_distances(queries[q], k);
            bool ok = want.size() == got[q].size();
            for (std::size_t i = 0; ok && i < want.size(); ++i) ok = same_distance(want[i], got[q][i]);
            if (!ok)
                throw validation_error("scene " + scene_.name + " [" + structure_ + "] step " + std::to_string(step + 1) +
                                       ": nearest query " + std::to_string(q) + " disagrees with brute force");
        }
    }
    void range_step(std::size_t step) {
        const auto boxes = datasets::generate_range_queries<T, D>(scene_, step);
        auto& set = *sets_[scene_.range->target];
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::vector<std::uint32_t>> got;
        std::size_t found = 0;
        for (const auto& b : boxes) {
            P lo, hi;
            for (std::size_t d = 0; d < D; ++d) lo[d] = b.lo[d], hi[d] = b.hi[d];
            got.push_back(set.in_box(lo, hi));
            found += got.back().size();
            ++k_.range_queries;
        }
        record("range", seconds_since(t0));
        times.counts["range_results"].push_back(static_cast<double>(found));
        range_log.push_back(digest_of(got));
        if (!validated_) return;
        note_checked("range", 0, boxes.size());
        for (std::size_t q = step % 5; q < boxes.size(); q += std::max<std::size_t>(1, boxes.size() / 16)) {
            note_checked("range", 1, 0);
            P lo, hi;
            for (std::size_t d = 0; d < D; ++d) lo[d] = boxes[q].lo[d], hi[d] = boxes[q].hi[d];
            auto g = got[q];
            std::sort(g.begin(), g.end());
            if (g != set.brute_in_box(lo, hi))
                throw validation_error("scene " + scene_.name + " [" + structure_ + "] step " + std::to_string(step + 1) +
                                       ": range query " + std::to_string(q) + " disagrees with brute force");
        }
    }

    // How many answers of a kind were checked against brute force, of how many given.
    struct checked_count {
        std::size_t checked = 0, total = 0;
    };
    void note_checked(const std::string& kind, std::size_t checked, std::size_t total) {
        checked_[kind].checked += checked;
        checked_[kind].total += total;
    }

    std::map<std::string, checked_count> checked_;
    const datasets::scene_description& scene_;
    std::string structure_;
    std::size_t steps_;
    scene_counters& k_;
    std::vector<pair32> pairs_;  // one collide entry's pairs (capacity kept across steps)
    const progress& prog_;
    std::vector<std::unique_ptr<set_base<T, D>>> sets_;
    double step_seconds_ = 0;
    bool validated_;
    std::size_t objects_at_end_ = 0;
};

}  // namespace

namespace scene_detail {

// One scene in scalar T and dimension D (explicitly instantiated in scene_runner_<D>d_<T>.cpp).
template <class T, std::size_t D>
std::vector<result_row> run_typed(const datasets::scene_description& scene, const scene_run_options& opt,
                                  scene_counters& k) {
    progress prog(opt.quiet);
    std::size_t objects = 0;
    for (const auto& set : scene.objects) objects += set.generator ? set.generator->count : 0;
    // Before anything is allocated (memory_budget.hpp): per object, the scene's own state
    // (positions, velocities, ids), the structure's copy, and the pair lists of a step.
    constexpr std::size_t bytes_per_scene_object = 256;
    require_memory("scene " + scene.name, objects, bytes_per_scene_object);
    std::vector<std::string> structures = opt.structures;
    if (structures.empty()) structures = {"bvh"};
    if (structures.size() == 1 && structures[0] == "all") {
        using O = spatial::objects::box<T, D>;  // the traits do not depend on the object type
        structures = scene_structure_names();
        if (scene.raycast || scene.nearest || scene.range)  // structures that answer pairs only
            std::erase_if(structures, [](const std::string& s) { return !scene_structure_traits<O>(s).first; });
        if (objects > large_scene_objects) {
            // brute_force is O(n^2) per step; structures without batched motion follow it by
            // erasing and inserting every moved object: minutes per large scene. 'all' keeps
            // the structures with a dedicated path for moving scenes.
            std::erase_if(structures, [](const std::string& s) { return !scene_structure_traits<O>(s).second; });
            std::string kept;
            for (const auto& s : structures) kept += (kept.empty() ? "" : " and ") + s;
            prog.say("scene " + scene.name + ": 'all' means " + kept + " above " + std::to_string(large_scene_objects) +
                     " objects (" + std::to_string(objects) + " here)");
        }
    }
    const std::size_t steps = opt.steps ? opt.steps : scene.steps;
    std::vector<result_row> rows;
    std::vector<std::uint64_t> reference_pairs;  // the first structure's pair digests
    std::string reference_name;
    for (const auto& name : structures) {
        // Two passes (docs/collisions.md, "Scenes and the runner"): the validated
        // pass checks every step's answers against brute force as they come; the timed pass
        // replays the scene without the checks, and its answers must equal the validated
        // pass's at every step. The rows carry the timed pass's times: checks between the
        // stages had left the caches cold for the next stage (a 50 ms pause between steps
        // made the next step of boxes_100k 1.3 to 1.4 times slower on this VM;
        // results/checks/scene_step), so the times depended on how long the checks took.
        scene_run<T, D> run(scene, name, steps, k, prog);
        run.run();
        run.release_sets();
        scene_counters replay_counters;  // the counters say what the validated pass did
        scene_run<T, D> timed(scene, name, steps, replay_counters, prog, false);
        timed.run();
        timed.release_sets();
        if (const std::size_t s = timed.first_different_step(run))
            throw validation_error("scene " + scene.name + " [" + name + "] step " + std::to_string(s) + ": the answers of the timed pass (" +
                                   name + "@timed) differ from the validated pass's");
        const bool exact = scene.collide && scene.collide->filter == datasets::collide_filter::exact;
        if (reference_name.empty()) {
            reference_name = name;
            reference_pairs = run.pair_log;
        } else if (exact && run.pair_log != reference_pairs) {
            const std::size_t step = scene_run<T, D>::first_different_step(run.pair_log, reference_pairs,
                                                                           scene_run<T, D>::pair_entries_per_step(scene));
            throw validation_error("scene " + scene.name + " step " + std::to_string(step) + ": " + name + " and " +
                                   reference_name + " report different pair sets");
        }
        const structure_info* info = find_structure(name);
        const std::string bv = info && !info->bv.empty() ? info->bv : "-";
        const std::string params = "steps=" + std::to_string(steps) +
                                   (scene.collide ? ";strategy=" + std::string(datasets::to_string(scene.collide->strategy)) +
                                                        ";filter=" + std::string(datasets::to_string(scene.collide->filter))
                                                  : "");
        const row_scope scope{"scenes", opt.run_id, scene.name, run.objects_at_end(), D,
                              std::is_same_v<T, float> ? "float" : "double"};
        // Exact pairs equal to the first structure's at every step: cross-checked as well.
        const std::string cross = exact && name != reference_name ? check::cross_all : check::none;
        auto checked = [&](const std::string& what) { return scope.with_check(run.check_of(what, cross)); };
        for (const auto& [stage, secs] : timed.times.seconds)
            rows.push_back(checked(stage).timed(name, bv, stage, params, "time", summarize(secs), "s"));
        for (const auto& [what, counts] : timed.times.counts)
            rows.push_back(checked(what).figure(name, bv, "step", params, what, summarize(counts).median_seconds, "count"));
        const auto& step_s = timed.times.seconds["step"];
        double total = 0;
        for (double s : step_s) total += s;
        if (total > 0)
            rows.push_back(checked("step").figure(name, bv, "step", params, "steps_per_second",
                                                  static_cast<double>(step_s.size()) / total, "1/s"));
    }
    return rows;
}

}  // namespace scene_detail

}  // namespace harness
