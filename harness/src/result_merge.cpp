#include "harness/result_merge.hpp"

#include <algorithm>
#include <cstddef>
#include <map>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "harness/result_key.hpp"
#include "harness/result_table.hpp"

namespace harness {

std::vector<result_row> merge_results(const std::vector<std::vector<result_row>>& shards) {
    std::vector<std::string> names;
    for (std::size_t s = 0; s < shards.size(); ++s) names.push_back("shard " + std::to_string(s + 1));
    return merge_results(shards, names);
}

std::vector<result_row> merge_results(const std::vector<std::vector<result_row>>& shards,
                                      const std::vector<std::string>& shard_names, merge_kind kind) {
    if (shard_names.size() != shards.size()) throw std::invalid_argument("merge_results: one name per shard");
    std::vector<result_row> rows;
    std::vector<result_key> keys;
    // The input that first held each key (for repeated runs: each key of each run; the run_id
    // is empty for shards), and its row (for the message).
    std::map<std::pair<result_key, std::string>, std::pair<std::size_t, const result_row*>> owner;
    auto where = [&](std::size_t shard, const result_row& r) { return shard_names[shard] + " (run " + r.run_id + ")"; };
    for (std::size_t s = 0; s < shards.size(); ++s)
        for (const result_row& r : shards[s]) {
            result_key key = key_of(r);
            const auto [it, fresh] =
                owner.try_emplace({key, kind == merge_kind::repeated_runs ? r.run_id : std::string()}, s, &r);
            if (!fresh && it->second.first != s)
                throw std::runtime_error("key " + to_string(key) + " is in " +
                                         where(it->second.first, *it->second.second) + " and in " + where(s, r) +
                                         (kind == merge_kind::shards ? ": shards must hold disjoint cases"
                                                                     : ": one run given twice"));
            rows.push_back(r);
            keys.push_back(std::move(key));
        }
    std::vector<std::size_t> order(rows.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return keys[x] < keys[y]; });
    std::vector<result_row> out;
    out.reserve(rows.size());
    for (std::size_t i : order) out.push_back(std::move(rows[i]));
    return out;
}

std::map<std::string, std::vector<result_row>> merge_result_folders(const std::vector<std::filesystem::path>& dirs,
                                                                   merge_kind kind) {
    // Per table name: the shards that have it, and their paths (which the errors name).
    std::map<std::string, std::pair<std::vector<std::vector<result_row>>, std::vector<std::string>>> tables;
    for (const auto& dir : dirs)
        for (const std::string& name : result_table_names(dir)) {
            auto& [shards, paths] = tables[name];
            shards.push_back(read_results_csv(dir / name));
            paths.push_back((dir / name).string());
        }
    std::map<std::string, std::vector<result_row>> out;
    for (const auto& [name, shards] : tables) out.emplace(name, merge_results(shards.first, shards.second, kind));
    return out;
}

}  // namespace harness
