// Memory needs against what the machine has (see memory_budget.hpp).

#include "harness/memory_budget.hpp"

#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace harness {

namespace {

// The first number of `file` after `key` (or at its start when key is empty); 0 when absent.
std::uint64_t number_in(const char* file, const std::string& key) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
        if (!key.empty() && line.rfind(key, 0) != 0) continue;
        std::istringstream s(key.empty() ? line : line.substr(key.size()));
        std::uint64_t v = 0;
        if (s >> v) return v;
        return 0;  // "max": no limit
    }
    return 0;
}

void take_least(available_memory& a, std::uint64_t bytes, const char* source) {
    if (bytes > 0 && (a.bytes == 0 || bytes < a.bytes)) a = {bytes, source};
}

}  // namespace

available_memory memory_available() {
    if (const char* v = std::getenv("SPATIALBENCH_AVAILABLE_MEMORY"))
        return {std::strtoull(v, nullptr, 10), "SPATIALBENCH_AVAILABLE_MEMORY"};
    available_memory a;
    take_least(a, number_in("/proc/meminfo", "MemAvailable:") * 1024, "MemAvailable");
    const std::uint64_t cgroup_max = number_in("/sys/fs/cgroup/memory.max", "");
    const std::uint64_t cgroup_used = number_in("/sys/fs/cgroup/memory.current", "");
    if (cgroup_max > cgroup_used) take_least(a, cgroup_max - cgroup_used, "cgroup memory.max");
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) take_least(a, as.rlim_cur, "RLIMIT_AS");
    return a;
}

std::string human_bytes(long double bytes) {
    const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
    int u = 0;
    while (bytes >= 1000 && u < 6) bytes /= 1000, ++u;
    char buf[32];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0Lf %s" : "%.1Lf %s", bytes, units[u]);
    return buf;
}

void require_memory(const std::string& what, std::uint64_t objects, std::uint64_t bytes_per_object) {
    if (objects == 0) return;
    const available_memory have = memory_available();
    if (have.bytes == 0) return;  // nothing says: let the run try
    // In long double: objects x bytes can overflow 64 bits for absurd requests.
    const long double need = static_cast<long double>(objects) * static_cast<long double>(bytes_per_object);
    if (need <= static_cast<long double>(have.bytes)) return;
    throw resource_error(what + " needs about " + human_bytes(need) + " (" + std::to_string(objects) + " objects x about " +
                         std::to_string(bytes_per_object) + " B for every copy a case keeps), but " +
                         human_bytes(have.bytes) + " is available (" + have.source + "); ask for fewer objects");
}

}  // namespace harness
