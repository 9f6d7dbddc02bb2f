#pragma once
// The JSON sidecar of a run: what was measured, where and how, so a CSV row's run_id leads
// to the commit, compiler, flags, CPU and seeds that produced it.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace harness {

// The wall time one case of a run took (validation and timed repetitions together; a scene
// file for the scene runner): the sidecar lists them so that a preset's time budget can be
// checked case by case.
struct case_time {
    std::string id;
    double seconds = 0;
};

struct run_info {
    std::string run_id;
    std::string suite, preset;
    std::map<std::string, std::uint64_t> seeds;
    std::map<std::string, std::string> extra;
    // Each case run and its wall time, in the order run (the sidecar's "case_seconds").
    std::vector<case_time> case_seconds;
};

// A fresh run id: <suite>-<preset>-<UTC timestamp>-<short commit>, then -<shard> for a
// sharded run (suite_options::shard_label). Inside a Slurm job array the timestamp is
// "slurm<SLURM_ARRAY_JOB_ID>", so the shards of one submission share one run id family.
std::string make_run_id(const std::string& suite, const std::string& preset, const std::string& shard = "");
// This machine's host name (the sidecar's `host`: merged shards name every machine).
std::string host_name();
std::string git_commit();
std::string cpu_model();
// The process's peak resident memory so far in bytes (getrusage), 0 where unknown: the
// sidecar's `peak_rss_bytes`, what a run at scale needed of the machine, recorded rather than
// read off a monitor by hand.
std::uint64_t peak_resident_bytes();
// Writes results/runs/<run_id>.json atomically.
void write_run_sidecar(const std::filesystem::path& results_dir, const run_info& info, double wall_seconds);

}  // namespace harness
