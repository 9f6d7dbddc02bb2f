// The scene runner (harness/scene_runner.hpp). One step:
//   1. motion   each MOVING set is advanced (datasets/scene_motion.hpp);
//   2. churn    erases then inserts in the churn set (if the scene has churn);
//   3. update   each queried set whose objects changed updates its structure (bvh: the
//               scene's strategy through bvh::update(first, last, strategy); the others:
//               their own incremental path, or a rebuild when the strategy says so);
//   4. effects  collide, raycast, nearest, range — each only if present. Collide: a set's
//               self pairs are the structure's own pair query with the scene's filter (for
//               `exact` its narrow phase runs inside, as a simulation would call it); pairs
//               between two sets come from box queries on the first set's structure, then
//               the runner's narrow phase (double dispatch over the object types) when
//               `exact`; then the pairs that appeared and disappeared since the last step
//               (collide/pair_changes.hpp). Each is a timed stage: collide_pairs,
//               collide_narrow_phase, collide_pair_changes.
// Objects live in the runner's arrays (index = object id within its set; churn erases by
// swap-and-pop, mirrored in the structure's handle array), so every answer is mapped to
// (set, index). What is compared: exact pairs with brute force (every object of small sets,
// else 64 sampled objects per step) and across structures at every step; rays, nearest and
// range queries with brute force on about 16 sampled queries per step (their answers are not
// compared across structures). Each row's `check` column says which (run.check_of).

#include "harness/scene_runner.hpp"
#include "harness/structure_registry.hpp"

namespace harness {
namespace scene_detail {
// Defined in scene_runner_impl.hpp, instantiated in scene_runner_<D>d_<T>.cpp.
template <class T, std::size_t D>
std::vector<result_row> run_typed(const datasets::scene_description& scene, const scene_run_options& opt,
                                  scene_counters& k);
}  // namespace scene_detail

std::vector<std::string> scene_structure_names() {
    std::vector<std::string> out;
    for (const auto& s : registered_structures())
        if (s.takes_part_in(in::scenes)) out.push_back(s.name);
    return out;
}

std::vector<result_row> run_scene(const datasets::scene_description& scene, const scene_run_options& options,
                                  scene_counters& counters) {
    const bool is_float = scene.scalar == datasets::scalar_kind::float32;
    if (scene.dimension == 2)
        return is_float ? scene_detail::run_typed<float, 2>(scene, options, counters)
                        : scene_detail::run_typed<double, 2>(scene, options, counters);
    return is_float ? scene_detail::run_typed<float, 3>(scene, options, counters)
                    : scene_detail::run_typed<double, 3>(scene, options, counters);
}

}  // namespace harness
