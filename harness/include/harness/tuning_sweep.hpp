#pragma once
// harness::tuning_sweep — the ONE table of the configurations a tuning sweep runs, for the
// peers and for our own structures, so that every comparison is tuned against tuned (issue 18:
// a peer at its default bucket or leaf size is not the peer at its best).
//
// A structure's default configuration is its registry line's `settings` (structure_registry.hpp,
// peer_registry.hpp); a sweep runs it and each configuration listed here, which names only the
// settings it changes. Rows of a swept configuration carry it in their `params` after the
// operation's own (e.g. `k=10;bucket_size=32;points_cache=on`); the default's rows keep the
// params they have at every size, so the complexity curves stay one series per structure.
// Where the suites sweep (the sizes that decide the targets) is each suite's preset.
//
// Adding a configuration: one line here; the adapter or factory reads the setting from the
// full settings it is given (registry defaults overlaid with the line) and throws
// std::invalid_argument for a value it cannot run. tests/adapters_test.cpp (point peers),
// adapters_raycast_test.cpp and adapters_collide_test.cpp then run it against brute force like
// every other configuration; harness/best_peer.hpp compares ours with the fastest of them.

#include <algorithm>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/peer_registry.hpp"
#include "harness/structure_registry.hpp"

namespace harness {

// The configurations swept besides the default, per structure or peer name (none: not swept).
inline const std::vector<key_values>& tuning_sweep(const std::string& name) {
    // CGAL Kd_tree: bucket size of its Sliding_midpoint splitter, and its points cache
    // (coordinates copied into the leaves; CGAL's docs: faster queries for more memory).
    static const std::vector<key_values> cgal_kd_tree = [] {
        std::vector<key_values> v;
        for (const char* bucket : {"5", "10", "20", "32", "50", "100"})
            for (const char* cache : {"off", "on"})
                if (std::string(bucket) != "10" || std::string(cache) != "off")
                    v.push_back({{"bucket_size", bucket}, {"points_cache", cache}});
        return v;
    }();
    // nanoflann: leaf_max_size of KDTreeSingleIndexAdaptorParams (its docs suggest 10-50).
    static const std::vector<key_values> nanoflann{
        {{"leaf_max_size", "5"}}, {{"leaf_max_size", "20"}}, {{"leaf_max_size", "50"}}};
    // Ours: the kd_tree's leaf capacity (compile-time: harness/our_indexes.hpp instantiates these).
    static const std::vector<key_values> kd_tree{
        {{"leaf_capacity", "8"}}, {{"leaf_capacity", "16"}}, {{"leaf_capacity", "64"}}};
    // Embree's BVH builder (rtcSetSceneBuildQuality, harness/adapters/embree/
    // embree_build_quality.hpp): low builds fastest (for dynamic scenes), medium is its default
    // (SAH binning), high adds spatial splits on triangle meshes (Stich, Friedrich and
    // Dietrich, "Spatial Splits in Bounding Volume Hierarchies", HPG 2009): slower builds for
    // fewer overlapping nodes. embree_robust keeps RTC_SCENE_FLAG_ROBUST in each.
    static const std::vector<key_values> embree{{{"build_quality", "low"}}, {{"build_quality", "high"}}};
    // Embree's rtcCollide: low is the scene at LOW with the geometry at REFIT (the two-level
    // build whose update refits instead of rebuilding), high the SAH builder with splits.
    static const std::vector<key_values> embree_collide{{{"build_quality", "low"}}, {{"build_quality", "high"}}};
    // CGAL box_intersection_d: the cutoff below which the streamed segment tree (Zomorodian and
    // Edelsbrunner, "Fast software for box intersections", SoCG 2000) stops splitting and scans
    // a block pairwise. CGAL's manual names it the algorithm's tuning parameter; its default, 10,
    // is the registry's; larger cutoffs trade recursion for scanning, up to a plain scan.
    static const std::vector<key_values> cgal_box_intersection{{{"cutoff", "100"}},   {{"cutoff", "1000"}},
                                                               {{"cutoff", "3000"}},  {{"cutoff", "10000"}},
                                                               {{"cutoff", "30000"}}, {{"cutoff", "100000"}}};
    static const std::vector<key_values> none;
    if (name == "cgal_kd_tree") return cgal_kd_tree;
    if (name == "nanoflann") return nanoflann;
    if (name == "kd_tree") return kd_tree;
    if (name == "embree" || name == "embree_robust") return embree;
    if (name == "embree_collide") return embree_collide;
    if (name == "cgal_box_intersection") return cgal_box_intersection;
    return none;
}

// `settings` joined as params: "key=value;key=value" in their order ("" when empty).
inline std::string params_of(const key_values& settings) {
    std::string out;
    for (const auto& [key, value] : settings) out += (out.empty() ? "" : ";") + key + "=" + value;
    return out;
}

// Two params strings joined (either may be empty).
inline std::string joined_params(const std::string& a, const std::string& b) {
    return a.empty() ? b : b.empty() ? a : a + ";" + b;
}

// A configuration written out in full: `defaults` (a registry line's settings) with the swept
// ones of `swept` ("bucket_size=32;points_cache=on") in their place, so that a best-peer row
// names every setting of the configuration that won.
inline std::string full_configuration(key_values defaults, const std::string& swept) {
    std::size_t start = 0;
    while (start < swept.size()) {
        const std::size_t end = std::min(swept.find(';', start), swept.size());
        const std::string item = swept.substr(start, end - start);
        const std::size_t eq = item.find('=');
        for (auto& [k, v] : defaults)
            if (k == item.substr(0, eq)) v = item.substr(eq + 1);
        start = end + 1;
    }
    return params_of(defaults);
}

// One configuration to run: the full settings its factory reads, and what its rows append to
// their params ("" for the default).
struct tuned_configuration {
    key_values settings;
    std::string params;
};

// The default configuration of `defaults` (a registry line's settings), then, when `sweep`,
// each configuration of tuning_sweep(name) overlaid on it. A swept key the registry line lacks
// is a mistake in this table, reported here rather than silently run as the default.
inline std::vector<tuned_configuration> configurations(const std::string& name, const key_values& defaults,
                                                       bool sweep) {
    std::vector<tuned_configuration> out{{defaults, ""}};
    if (!sweep) return out;
    for (const key_values& changed : tuning_sweep(name)) {
        key_values full = defaults;
        for (const auto& [key, value] : changed) {
            auto it = full.begin();
            while (it != full.end() && it->first != key) ++it;
            if (it == full.end())
                throw std::logic_error("tuning_sweep: " + name + " has no setting '" + key + "' in its registry line");
            it->second = value;
        }
        out.push_back({full, params_of(changed)});
    }
    return out;
}

// Appends the peer `name` made by `factory` (taking the full settings) in its registry
// configuration and, when `sweep`, in each configuration of its tuning sweep, each labelled
// with what it changes.
template <class Index, class Factory>
void add_peer_configurations(std::vector<std::unique_ptr<Index>>& out, const std::string& name, Factory factory,
                             bool sweep) {
    const structure_info* info = find_peer(name);
    if (!info) throw std::logic_error("add_peer_configurations: no registry line for peer " + name);
    for (auto& c : configurations(name, info->settings, sweep)) {
        out.push_back(factory(c.settings));
        out.back()->set_configuration(std::move(c.params));
    }
}

// The value of `key` in `settings`; std::invalid_argument naming the structure when it is absent.
inline const std::string& setting(const key_values& settings, const std::string& key, const std::string& structure) {
    for (const auto& [k, v] : settings)
        if (k == key) return v;
    throw std::invalid_argument(structure + ": no setting '" + key + "'");
}

// A setting read as a positive count (a leaf or bucket size); std::invalid_argument otherwise.
inline std::size_t count_setting(const key_values& settings, const std::string& key, const std::string& structure) {
    const std::string& v = setting(settings, key, structure);
    std::size_t used = 0;
    unsigned long long x = 0;
    try {
        x = std::stoull(v, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != v.size() || x == 0 || v.front() == '-')
        throw std::invalid_argument(structure + ": setting " + key + "=" + v + " is not a positive count");
    return static_cast<std::size_t>(x);
}

// A setting read as on/off; std::invalid_argument otherwise.
inline bool switch_setting(const key_values& settings, const std::string& key, const std::string& structure) {
    const std::string& v = setting(settings, key, structure);
    if (v == "on") return true;
    if (v == "off") return false;
    throw std::invalid_argument(structure + ": setting " + key + "=" + v + " is neither on nor off");
}

}  // namespace harness
