#pragma once
// harness::merge_results — the tables of a run split across machines (shards: disjoint sets of
// cases, `spatialbench run --case ...` on each) joined into one (`spatialbench merge DIR...`;
// docs/harness.md, "Comparing runs").
//
// The result is the union of the shards' rows, each keeping its run_id (so each row still
// names the sidecar of the machine that measured it), sorted by key (result_key.hpp: suite,
// structure, bv, workload, n, dim, scalar, operation, params, metric), rows of one key in
// their shard's order: the same shards give the same table in any order. A key found in two
// shards is an error naming it: shards hold disjoint cases, so two shards measuring one figure
// means the split went wrong, and keeping either would silently drop a measurement. (Repeated
// rows of a key within one shard, a shard's own repeated runs, are kept.)
//
// Repeated runs (`spatialbench merge --repeated-runs`): the same cases measured again, in
// another process or at another time, to show the spread between runs (issue 20: one table per
// suite and preset, its runs told apart by run_id, not numbered files). Then a key may be in
// several folders, each row keeping its run_id; the same (key, run_id) in two folders is the
// error (one run given twice would count its figures twice).

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "harness/csv_writer.hpp"

namespace harness {

enum class merge_kind {
    shards,         // disjoint cases: a key in two inputs is an error
    repeated_runs,  // the same cases again: a key in several inputs, a (key, run_id) in one
};

// Errors name the shards "shard 1", "shard 2", ... in the order given.
std::vector<result_row> merge_results(const std::vector<std::vector<result_row>>& shards);
// The same, errors naming the shards by `shard_names` (one per shard; say their files).
std::vector<result_row> merge_results(const std::vector<std::vector<result_row>>& shards,
                                      const std::vector<std::string>& shard_names, merge_kind kind = merge_kind::shards);

// Shard folders merged table by table: each table name (result_table_names) found in any of
// them maps to the merge of that table from the folders that have it. Reads with
// read_results_csv (table_error on a malformed table); errors name the tables' paths.
std::map<std::string, std::vector<result_row>> merge_result_folders(const std::vector<std::filesystem::path>& dirs,
                                                                   merge_kind kind = merge_kind::shards);

}  // namespace harness
