#include "harness/run_info.hpp"

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include <sys/resource.h>
#include <unistd.h>

#include "harness/allocator_policy.hpp"
#include "harness/csv_writer.hpp"
#include "spatial/core/parallel.hpp"

#ifndef SPATIAL_CXX_FLAGS
#define SPATIAL_CXX_FLAGS "unknown"
#endif
#ifndef SPATIAL_BUILD_TYPE
#define SPATIAL_BUILD_TYPE "unknown"
#endif
#ifndef SPATIAL_SOURCE_DIR
#define SPATIAL_SOURCE_DIR "."
#endif

namespace harness {

namespace {
std::string run_command(const std::string& cmd) {
    std::array<char, 256> buf{};
    std::string out;
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    if (!pipe) return "";
    while (fgets(buf.data(), buf.size(), pipe.get())) out += buf.data();
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}
std::string utc_stamp(const char* fmt) {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[64];
    std::strftime(buf, sizeof buf, fmt, &tm);
    return buf;
}
}  // namespace

std::string git_commit() {
    std::string c = run_command("git -C '" SPATIAL_SOURCE_DIR "' rev-parse HEAD 2>/dev/null");
    if (c.empty()) return "unknown";
    // Dirty means the code differs from the commit: the outputs a run itself rewrites
    // (results/, plots/, paper/) do not count, or every sidecar of a main job would say dirty.
    if (!run_command("git -C '" SPATIAL_SOURCE_DIR "' status --porcelain --untracked-files=no -- . "
                     "':(exclude)results' ':(exclude)plots' ':(exclude)paper' 2>/dev/null")
             .empty())
        c += "-dirty";
    return c;
}

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto p = line.find(':');
            return p == std::string::npos ? line : line.substr(p + 2);
        }
    return "unknown";
}

std::string make_run_id(const std::string& suite, const std::string& preset, const std::string& shard) {
    const char* array_job = std::getenv("SLURM_ARRAY_JOB_ID");
    const std::string when = array_job && *array_job ? "slurm" + std::string(array_job) : utc_stamp("%Y%m%dT%H%M%SZ");
    return suite + "-" + preset + "-" + when + "-" + git_commit().substr(0, 7) + (shard.empty() ? "" : "-" + shard);
}

std::string host_name() {
    std::array<char, 256> name{};
    if (gethostname(name.data(), name.size() - 1) != 0) return "unknown";
    return name.data();
}

// Linux reports ru_maxrss in KiB.
std::uint64_t peak_resident_bytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss < 0) return 0;
    return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;
}

void write_run_sidecar(const std::filesystem::path& results_dir, const run_info& info, double wall_seconds) {
    nlohmann::json j;
    j["run_id"] = info.run_id;
    j["suite"] = info.suite;
    j["preset"] = info.preset;
    j["date_utc"] = utc_stamp("%Y-%m-%dT%H:%M:%SZ");
    j["commit"] = git_commit();
    j["compiler"] = std::string("g++ ") + __VERSION__;
    j["build_type"] = SPATIAL_BUILD_TYPE;
    j["cxx_flags"] = SPATIAL_CXX_FLAGS;
    j["host"] = host_name();
    j["cpu"] = cpu_model();
    j["hardware_threads"] = std::thread::hardware_concurrency();
    // Every timed figure runs on one thread except the multi-threaded ones, whose params say
    // threads=N: N is the parallel back end's thread count, recorded here.
    j["threads_used"] = 1;
    j["parallel_threads"] = spatial::detail::parallel_threads();
    j["allocator"] = freed_memory_policy_description();
    j["seeds"] = info.seeds;
    j["extra"] = info.extra;
    j["wall_seconds"] = wall_seconds;
    j["peak_rss_bytes"] = peak_resident_bytes();
    if (!info.case_seconds.empty()) {
        nlohmann::json cases = nlohmann::json::array();
        for (const case_time& c : info.case_seconds) cases.push_back({{"case", c.id}, {"seconds", c.seconds}});
        j["case_seconds"] = std::move(cases);
    }
    write_text_atomically(results_dir / "runs" / (info.run_id + ".json"), j.dump(2) + "\n");
}

}  // namespace harness
