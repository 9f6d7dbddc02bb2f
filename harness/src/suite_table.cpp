// The suite table and results/registry.json (see suite_table.hpp).

#include "harness/suite_table.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "harness/bv_suite.hpp"
#include "harness/collide_suite.hpp"
#include "harness/knn_suite.hpp"
#include "harness/peer_registry.hpp"
#include "harness/raycast_suite.hpp"
#include "harness/run_info.hpp"
#include "harness/structure_registry.hpp"

namespace harness {

namespace {

// The structures suite is the knn suite's static part on every structure of the library.
suite_options structures_options(const suite_options& options) {
    suite_options opt = options;
    opt.all_structures = true;
    opt.dynamic = false;  // dynamic workloads: the knn suite
    return opt;
}
void run_structures_suite(const suite_options& options) { run_knn_suite(structures_options(options)); }
std::vector<std::string> structures_case_ids(const suite_options& options) {
    return knn_case_ids(structures_options(options));
}

}  // namespace

const std::vector<suite_entry>& suite_table() {
    static const std::vector<suite_entry> suites{
        {"knn", "knn.csv", "k-nearest, radius and approximate kNN queries on point sets, static and dynamic",
         "kd_tree", {}, {}, {}, "", {}, &run_knn_suite, &knn_case_ids},
        {"structures", "structures.csv", "the knn suite's static queries on every structure of the library, with the peers",
         "kd_tree", {}, {}, {}, "", {}, &run_structures_suite, &structures_case_ids},
        {"bv", "bv.csv", "bounding-volume fits and tests: fit time, tightness, test time, false positives", "", {},
         {"method"}, {}, "", {}, &run_bv_suite, &bv_case_ids},
        {"raycast", "raycast.csv", "first-hit ray casting on triangle meshes, boxes and points", "embree", {}, {}, {}, "", {},
         &run_raycast_suite, &raycast_case_ids},
        {"collide", "collide.csv", "all intersecting pairs: static and moving boxes, triangles per BVH volume type",
         "cgal_box_intersection",
         {{"speedup", "collision_grid", "boxes", 1000000, 5.0, ">= 5x CGAL at 1e6"},
          {"steps_per_second", "", "moving_boxes", 100000, 60.0, ">= 60 steps/s at 1e5"}},
         {}, {}, "", {}, &run_collide_suite, &collide_case_ids},
        {"scenes", "scenes.csv", "scene pipelines (TOML scenes): per-step stage times", "", {}, {},
         {"motion", "churn", "update", "collide_pairs", "collide_narrow_phase", "collide_pair_changes", "raycast", "nearest",
          "range"},
         "step", {"build"}, nullptr},
    };
    return suites;
}

const suite_entry* find_suite(const std::string& name) {
    for (const auto& s : suite_table())
        if (s.name == name) return &s;
    return nullptr;
}

namespace {

nlohmann::ordered_json pairs_object(const key_values& kv) {
    nlohmann::ordered_json o = nlohmann::ordered_json::object();
    for (const auto& [k, v] : kv) o[k] = v;
    return o;
}

std::vector<std::string> suite_names_of(unsigned bits) {
    static const std::pair<unsigned, const char*> parts[] = {
        {in::knn, "knn"},         {in::structures, "structures"},  {in::raycast | in::raycast_objects, "raycast"},
        {in::collide_static | in::collide_moving | in::collide_bv, "collide"}, {in::scenes, "scenes"}, {in::bv, "bv"}};
    std::vector<std::string> out;
    for (const auto& [mask, name] : parts)
        if (bits & mask) out.push_back(name);
    return out;
}

nlohmann::ordered_json structure_json(const structure_info& s) {
    nlohmann::ordered_json j;
    j["name"] = s.name;
    j["family"] = s.family;
    j["bv"] = s.bv;
    j["kind"] = s.kind;
    j["library"] = s.library;
    j["description"] = s.description;
    j["suites"] = suite_names_of(s.suites);
    j["size_class"] = s.limit == size_class::slow ? "slow" : s.limit == size_class::oracle ? "oracle" : "any";
    j["max_n"] = s.max_n;
    j["settings"] = pairs_object(s.settings);
    j["complexity"] = pairs_object(s.complexity);
    if (!s.capabilities.empty()) j["capabilities"] = s.capabilities;
    return j;
}

// A structure and, for each of its aliases, the same description under that name.
void add_structure(nlohmann::ordered_json& list, const structure_info& s) {
    list.push_back(structure_json(s));
    for (const auto& alias : s.aliases) {
        nlohmann::ordered_json j = structure_json(s);
        j["name"] = alias;
        j["alias_of"] = s.name;
        list.push_back(j);
    }
}

}  // namespace

std::string registry_json() {
    nlohmann::ordered_json root;
    root["schema_version"] = 1;
    root["generator"] = "spatialbench (commit " + git_commit() + ")";
    root["suites"] = nlohmann::ordered_json::array();
    for (const auto& s : suite_table()) {
        nlohmann::ordered_json j;
        j["name"] = s.name;
        j["table"] = s.table;
        j["description"] = s.description;
        j["baseline"] = s.baseline;
        j["targets"] = nlohmann::ordered_json::array();
        for (const auto& t : s.targets)
            j["targets"].push_back({{"metric", t.metric}, {"structure", t.structure}, {"workload", t.workload},
                                    {"n", t.n}, {"value", t.value}, {"label", t.label}});
        if (!s.series_params.empty()) j["series_params"] = s.series_params;
        if (!s.stages.empty()) {
            j["stages"] = s.stages;
            j["total_stage"] = s.total_stage;
            j["once_stages"] = s.once_stages;
        }
        root["suites"].push_back(j);
    }
    root["structures"] = nlohmann::ordered_json::array();
    for (const auto& s : registered_structures()) add_structure(root["structures"], s);
    for (const auto& p : registered_peers()) add_structure(root["structures"], p);
    return root.dump(2) + "\n";
}

void write_registry_json(const std::filesystem::path& results_dir) {
    std::filesystem::create_directories(results_dir);
    const auto file = results_dir / "registry.json";
    const auto tmp = results_dir / "registry.json.tmp";
    {
        std::ofstream out(tmp);
        out << registry_json();
        if (!out) throw std::runtime_error("cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, file);
}

}  // namespace harness
