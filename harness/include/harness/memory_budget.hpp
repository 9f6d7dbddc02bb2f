#pragma once
// harness::require_memory — a clear error BEFORE a run allocates more than the machine has,
// instead of an OOM kill halfway (a scene with count = 4e9 boxes, `--n 4000000000`).
//
// The need is estimated as objects x bytes per object, the bytes per object standing for every
// copy a case keeps alive at once (the input, each participant's structure, the oracle's): the
// suites give a figure per object of their kind from the memory the tables measure (at 1e6
// uniform points the knn suite's kd_tree, nanoflann and CGAL take 40-52 B per point each;
// about 10 participants and the harness's own copies come to a few hundred bytes). It is an
// estimate: a request it refuses could not have fit; one it lets through can still run out of
// memory if the estimate is low, and then the run journal (run_journal.hpp) keeps what was done.
//
// Available memory is the least of /proc/meminfo's MemAvailable, the cgroup's (v2) memory.max
// minus memory.current, and RLIMIT_AS. SPATIALBENCH_AVAILABLE_MEMORY=<bytes> overrides it (the
// tests use it to refuse a modest request on any machine).

#include <cstdint>
#include <stdexcept>
#include <string>

namespace harness {

// Too much asked of this machine (exit status 1, as bad input).
class resource_error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct available_memory {
    std::uint64_t bytes = 0;
    std::string source;  // which limit it is, for the message: "MemAvailable", "cgroup memory.max", ...
};
available_memory memory_available();

// Throws resource_error saying what was asked (`what`, objects x bytes each, the total) and
// what is available, when objects * bytes_per_object exceeds it. Does nothing for objects = 0.
void require_memory(const std::string& what, std::uint64_t objects, std::uint64_t bytes_per_object);

// "1.5 GB" style (decimal units).
std::string human_bytes(long double bytes);

}  // namespace harness
