#pragma once
// harness::structure_registry — the ONE list of the structures the harness measures: every
// in-house structure (and the example structure of examples/), each with its name, how to
// construct it for any object type, the suites it takes part in, its size class, its
// settings and its complexity. Suites, the scene runner, `spatialbench list`, the help text
// and the plots' metadata (results/registry.json) all read this list; no suite names a
// structure. The peers' list is peer_registry.hpp (their construction lives in their
// adapters, so a build without a peer library still compiles this one).
//
// Adding a structure is ONE line below (docs/adding-a-structure.md):
//     entry<my_structure, in::knn | in::every, [] { return structure_info{"my_structure", ...}; }>,
// where my_structure<O> is a template over the stored object type that models
// spatial::spatial_container. A variant with other template arguments (a bvh with another
// bounding volume) is an alias template in the "variants" block, then its line.
//
// Compile-time because each suite instantiates the same entry for its own object type
// (points of four scalar/dimension combinations, triangles, boxes, scene objects): the suite
// calls for_each_structure<O>(in::raycast, f) and gets f.template operator()<Entry>() for
// each entry in that suite whose container<O> is a spatial_container.

#include <cstddef>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "examples/morton_array.hpp"
#include "spatial/brute/brute_force.hpp"
#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/ellipsoid.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/sweep_and_prune.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/motion.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/octree/octree.hpp"

namespace harness {

// The suites, and parts of suites, a structure takes part in (structure_info::suites).
namespace in {
inline constexpr unsigned knn = 1u << 0;              // knn suite: static and dynamic point queries
inline constexpr unsigned structures = 1u << 1;       // structures suite: knn's static part, every structure
inline constexpr unsigned raycast = 1u << 2;          // raycast suite: triangle meshes
inline constexpr unsigned raycast_objects = 1u << 3;  // raycast suite: boxes and points
inline constexpr unsigned collide_static = 1u << 4;   // collide suite: static boxes
inline constexpr unsigned collide_moving = 1u << 5;   // collide suite: moving boxes, per step
inline constexpr unsigned collide_bv = 1u << 6;       // collide suite: triangles per bvh volume type
inline constexpr unsigned scenes = 1u << 7;           // spatialbench scene
inline constexpr unsigned bv = 1u << 8;               // bv suite (fits: ours and CGAL's)
// Every suite an in-house structure of the library can take part in beside knn.
inline constexpr unsigned every = structures | raycast | raycast_objects | collide_static | collide_moving | scenes;
}  // namespace in

// How far a suite times a structure: `any` at every size of the preset; `slow` up to the
// preset's limit for structures whose cost makes the largest sizes take minutes; `oracle` up
// to the brute-force limit (quadratic pair search, linear queries).
enum class size_class { any, slow, oracle };

using key_values = std::vector<std::pair<std::string, std::string>>;

struct structure_info {
    std::string name;         // the CSV `structure` column
    std::string family;       // groups variants in the plots (bvh_obb, bvh_refit: bvh)
    std::string bv;           // the CSV `bv` column ("" when the structure has no volume type)
    std::string kind;         // library | oracle | example | peer
    std::string library;      // who wrote it (spatialbench, or a peer library and version)
    std::string description;  // one line, for `spatialbench list` and the plots
    size_class limit = size_class::any;
    std::size_t max_n = 0;    // timed up to this many objects in every suite (0: no cap)
    // How the collide suite and the scene runner move its objects (its update strategy).
    spatial::motion_strategy motion = spatial::motion_strategy::automatic;
    key_values settings;    // its configuration (leaf size, builder, ...), for the tables' readers
    key_values complexity;  // operation -> "1" | "log n" | "n" | "n log n" | "n^2"; "*" for the rest
    unsigned suites = 0;    // in:: bits (a registry line gives them as the entry's argument)
    // A point peer's capabilities in harness::point_index terms (capability_names(), e.g.
    // "knn", "radius", "dynamic"): what its adapter must report, checked by adapters_test.
    std::vector<std::string> capabilities{};
    // Other names of its rows in the tables (see bv_study_name).
    std::vector<std::string> aliases{};

    bool takes_part_in(unsigned suite_bits) const { return (suites & suite_bits) != 0; }
};

// Complexities by shape of structure, in the plots' terms (the theory line drawn next to the
// measured curve; docs/contract.md and docs/structures/ have the tables).
namespace complexity_of {
inline key_values tree() {
    return {{"*", "log n"},       {"build", "n log n"}, {"insert_hinted", "1"}, {"collide", "n log n"},
            {"build_and_self_pairs", "n log n"}, {"fit", "n"}};
}
// The cell join of a grid is linear on spread data.
inline key_values grid() {
    return {{"*", "log n"},       {"build", "n log n"}, {"insert_hinted", "1"}, {"collide", "n log n"},
            {"build_and_self_pairs", "n"}, {"fit", "n"}};
}
inline key_values linear_scan() {
    return {{"*", "n"},           {"build", "n"},        {"insert", "1"},          {"insert_loop", "1"},
            {"insert_bulk", "1"}, {"insert_hinted", "1"}, {"collide", "n^2"},      {"build_and_self_pairs", "n^2"},
            {"fit", "n"}};
}
}  // namespace complexity_of

// The collide suite's per-volume study (in::collide_bv) names each row family_bv
// ("bvh_aabb", "bvh_obb"), so a structure whose own name differs (the plain bvh) has that
// name as an alias.
inline std::string bv_study_name(const structure_info& s) { return s.family + "_" + s.bv; }

// One registry line: the container template, the suites it takes part in (a compile-time
// constant, so that a suite instantiates only its own structures: a bvh of 14-DOPs exists in
// 3D only), and a captureless lambda that describes it.
template <template <class> class Container, unsigned Suites, auto Describe>
struct entry {
    template <class O>
    using container = Container<O>;
    static constexpr unsigned suites = Suites;
    static structure_info info() {
        structure_info i = Describe();
        i.suites = Suites;
        if ((Suites & in::collide_bv) && bv_study_name(i) != i.name) i.aliases.push_back(bv_study_name(i));
        return i;
    }
};

// ---- variants: structures with template arguments other than the defaults ----------------
namespace variants {
template <class O>
using scalar_of = typename O::scalar_type;
template <class O>
using bvh_median = spatial::bvh<O, spatial::aabb<scalar_of<O>, O::dimension>, spatial::bvh_median_config<>>;
// The wide ray layout's leaves testing the stored objects in place, leaves of up to 8
// triangles and the build's arrays fitted exactly: memory against time (a tree built to cast
// rays, not to be updated). Leaves of 8 against 4 and 6: results/checks/in_place_leaf_size.
struct bvh_in_place_config : spatial::bvh_config<8> {
    static constexpr spatial::bvh_ray_leaves ray_leaves = spatial::bvh_ray_leaves::in_place;
    static constexpr bool build_headroom = false;
};
template <class O>
using bvh_in_place = spatial::bvh<O, spatial::aabb<scalar_of<O>, O::dimension>, bvh_in_place_config>;
template <class O>
using bvh_sphere = spatial::bvh<O, spatial::sphere<scalar_of<O>, O::dimension>>;
template <class O>
using bvh_obb = spatial::bvh<O, spatial::obb<scalar_of<O>, O::dimension>>;
template <class O>
using bvh_kdop14 = spatial::bvh<O, spatial::kdop<scalar_of<O>, O::dimension, 14>>;
template <class O>
using bvh_kdop26 = spatial::bvh<O, spatial::kdop<scalar_of<O>, O::dimension, 26>>;
template <class O>
using bvh_ellipsoid = spatial::bvh<O, spatial::ellipsoid<scalar_of<O>, O::dimension>>;
template <class O>
using bvh_convex_hull = spatial::bvh<O, spatial::convex_hull<scalar_of<O>, O::dimension>>;
// Points have no extent, so the loose octree's larger cells only cost: points get the
// classic octree (loose factor 1), objects with extent the loose one (docs/structures).
template <class O>
using octree = spatial::octree<O, std::conditional_t<spatial::bounded_object<O>, spatial::loose_octree_config,
                                                     spatial::classic_octree_config>>;
}  // namespace variants

// ---- the registry ---------------------------------------------------------------------------
// Order: the order suites run and report them in; the first structure of a suite that answers
// is the one the others' answers are compared with after its own check against brute force.
using spatial::motion_strategy;
using structure_registry = std::tuple<
    entry<spatial::kd_tree, in::knn | in::every, [] { return structure_info{"kd_tree", "kd_tree", "", "library", "spatialbench", "dynamic bucket kd-tree (scapegoat-balanced; skd-tree for objects)", size_class::slow, 0, motion_strategy::reinsert, {{"leaf_capacity", std::to_string(spatial::kd_tree_config<>::leaf_capacity)}, {"splitter", "median_of_widest_spread"}}, complexity_of::tree()}; }>,
    entry<spatial::bvh, (in::every & ~in::collide_moving) | in::collide_bv, [] { return structure_info{"bvh", "bvh", "aabb", "library", "spatialbench", "bounding volume hierarchy, binned SAH, 8-wide ray layout", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"leaf_size", "8 for points, 4 otherwise"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_median, in::raycast | in::raycast_objects | in::collide_static, [] { return structure_info{"bvh_median", "bvh", "aabb", "library", "spatialbench", "bounding volume hierarchy, median split", size_class::any, 0, motion_strategy::automatic, {{"builder", "median"}, {"leaf_size", "4"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_in_place, in::raycast, [] { return structure_info{"bvh_in_place", "bvh", "aabb", "library", "spatialbench", "bvh whose 8-wide ray layout tests the stored triangles in place (no copies), arrays fitted exactly", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"leaf_size", "8"}, {"ray_leaves", "in_place"}, {"build_headroom", "none"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_sphere, in::raycast | in::collide_bv, [] { return structure_info{"bvh_sphere", "bvh", "sphere", "library", "spatialbench", "bvh of bounding spheres", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"bv", "sphere"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_obb, in::raycast | in::collide_bv, [] { return structure_info{"bvh_obb", "bvh", "obb", "library", "spatialbench", "bvh of oriented boxes", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"bv", "obb"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_kdop14, in::raycast | in::collide_bv, [] { return structure_info{"bvh_kdop14", "bvh", "kdop14", "library", "spatialbench", "bvh of 14-DOPs", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"bv", "kdop14"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_kdop26, in::raycast | in::collide_bv, [] { return structure_info{"bvh_kdop26", "bvh", "kdop26", "library", "spatialbench", "bvh of 26-DOPs", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"bv", "kdop26"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_ellipsoid, in::raycast | in::collide_bv, [] { return structure_info{"bvh_ellipsoid", "bvh", "ellipsoid", "library", "spatialbench", "bvh of ellipsoids", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"bv", "ellipsoid"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_convex_hull, in::raycast | in::collide_bv, [] { return structure_info{"bvh_convex_hull", "bvh", "convex_hull", "library", "spatialbench", "bvh of convex hulls", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"bv", "convex_hull"}}, complexity_of::tree()}; }>,
    entry<spatial::bvh, in::collide_moving, [] { return structure_info{"bvh_refit", "bvh", "aabb", "library", "spatialbench", "bvh moved by refitting", size_class::any, 0, motion_strategy::refit, {{"builder", "sah"}, {"strategy", "refit"}}, complexity_of::tree()}; }>,
    entry<spatial::bvh, in::collide_moving, [] { return structure_info{"bvh_rebuild", "bvh", "aabb", "library", "spatialbench", "bvh rebuilt after each motion", size_class::any, 0, motion_strategy::rebuild, {{"builder", "sah"}, {"strategy", "rebuild"}}, complexity_of::tree()}; }>,
    entry<spatial::bvh, in::collide_moving, [] { return structure_info{"bvh_reinsert", "bvh", "aabb", "library", "spatialbench", "bvh moved by reinsertion", size_class::any, 0, motion_strategy::reinsert, {{"builder", "sah"}, {"strategy", "reinsert"}}, complexity_of::tree()}; }>,
    entry<spatial::bvh, in::collide_moving, [] { return structure_info{"bvh_automatic", "bvh", "aabb", "library", "spatialbench", "bvh choosing refit, reinsert or rebuild", size_class::any, 0, motion_strategy::automatic, {{"builder", "sah"}, {"strategy", "automatic"}}, complexity_of::tree()}; }>,
    entry<variants::bvh_median, in::collide_moving, [] { return structure_info{"bvh_median_refit", "bvh", "aabb", "library", "spatialbench", "median-split bvh moved by refitting", size_class::any, 0, motion_strategy::refit, {{"builder", "median"}, {"strategy", "refit"}}, complexity_of::tree()}; }>,
    entry<variants::octree, in::every, [] { return structure_info{"octree", "octree", "", "library", "spatialbench", "octree (classic for points, loose for objects)", size_class::slow, 0, motion_strategy::reinsert, {{"leaf_capacity", "8"}}, complexity_of::tree()}; }>,
    entry<spatial::uniform_grid, in::every, [] { return structure_info{"uniform_grid", "uniform_grid", "", "library", "spatialbench", "uniform grid, dense cells", size_class::any, 0, motion_strategy::reinsert, {{"objects_per_cell", "2"}}, complexity_of::grid()}; }>,
    entry<spatial::hashed_grid, in::every & ~in::scenes, [] { return structure_info{"hashed_grid", "hashed_grid", "", "library", "spatialbench", "hashed grid, sparse cells", size_class::slow, 0, motion_strategy::reinsert, {{"objects_per_cell", "2"}}, complexity_of::grid()}; }>,
    entry<spatial::collision_grid, in::collide_static | in::collide_moving | in::scenes, [] { return structure_info{"collision_grid", "collision_grid", "", "library", "spatialbench", "grid rebuilt by counting sort at each pair query", size_class::any, 0, motion_strategy::automatic, {}, complexity_of::grid()}; }>,
    entry<spatial::sweep_and_prune, in::collide_static | in::collide_moving, [] { return structure_info{"sweep_and_prune", "sweep_and_prune", "", "library", "spatialbench", "sort and sweep along one axis", size_class::slow, 0, motion_strategy::automatic, {}, complexity_of::tree()}; }>,
    entry<examples::morton_array, in::knn | in::every, [] { return structure_info{"morton_array", "morton_array", "", "example", "examples/", "Morton-ordered array of leaf blocks (the adding-a-structure example)", size_class::slow, 10000, motion_strategy::reinsert, {{"block", "16"}}, complexity_of::tree()}; }>,
    entry<spatial::brute_force, in::knn | in::every, [] { return structure_info{"brute_force", "brute_force", "", "oracle", "spatialbench", "linear scan: the oracle", size_class::oracle, 0, motion_strategy::reinsert, {}, complexity_of::linear_scan()}; }>>;

// Calls f.template operator()<Entry>() for each registry entry taking part in one of the
// suite parts `Part` (in:: bits), in registry order. Only those entries are instantiated over
// O. Each must be a spatial container over it, except in the collide parts and the scenes,
// where a pair search is enough (collision_grid and sweep_and_prune answer only pairs).
template <class O, unsigned Part, class F>
void for_each_structure(F&& f) {
    [&]<class... E>(std::tuple<E...>*) {
        (
            [&] {
                if constexpr ((E::suites & Part) != 0) {
                    using C = typename E::template container<O>;
                    constexpr bool pairs_only = (Part & ~(in::collide_static | in::collide_moving | in::scenes)) == 0;
                    static_assert(spatial::spatial_container<C> || (pairs_only && spatial::pair_search<C>),
                                  "a registered structure must model spatial::spatial_container");
                    f.template operator()<E>();
                }
            }(),
            ...);
    }(static_cast<structure_registry*>(nullptr));
}

// True for a structure in a suite bit set that may be timed at n objects, given the suite's
// limits for slow structures and for the oracle (0: no limit).
inline bool within_limits(const structure_info& s, std::size_t n, std::size_t slow_max_n, std::size_t oracle_max_n) {
    if (s.max_n && n > s.max_n) return false;
    if (s.limit == size_class::slow && slow_max_n && n > slow_max_n) return false;
    if (s.limit == size_class::oracle && oracle_max_n && n > oracle_max_n) return false;
    return true;
}

// Every in-house structure's description, in registry order.
inline const std::vector<structure_info>& registered_structures() {
    static const std::vector<structure_info> all = [] {
        std::vector<structure_info> out;
        [&]<class... E>(std::tuple<E...>*) { (out.push_back(E::info()), ...); }(static_cast<structure_registry*>(nullptr));
        return out;
    }();
    return all;
}

// The registry's description of the structure called `name` (nullptr when none is).
inline const structure_info* find_structure(const std::string& name) {
    for (const auto& s : registered_structures())
        if (s.name == name) return &s;
    return nullptr;
}
inline bool is_oracle(const std::string& name) {
    const structure_info* s = find_structure(name);
    return s && s->kind == "oracle";
}

}  // namespace harness
