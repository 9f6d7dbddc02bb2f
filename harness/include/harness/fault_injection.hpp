#pragma once
// harness::injected_fault — the hook behind the fail-closed tests (tests/check_fail_closed.sh).
// With SPATIALBENCH_INJECT_FAULT=<name> in the environment, the participant of that name (a
// structure, a peer, or in the bv suite a volume type) gets one of its answers corrupted
// after it answered and BEFORE validation, in the way each suite's answers can be wrong:
// a kNN answer reports one point twice, ray hits move, a pair goes missing, an overlap test
// says "disjoint" where the volumes meet. The run must then stop with exit status 2 and
// leave every table it would have written as it was. Unset, it costs one string compare
// per validated answer set, outside every timed region.

#include <cstdlib>
#include <string>

namespace harness {

// Whether the answers of `participant` are to be corrupted in this run.
inline bool injected_fault(const std::string& participant) {
    static const std::string target = [] {
        const char* v = std::getenv("SPATIALBENCH_INJECT_FAULT");
        return std::string(v ? v : "");
    }();
    return !target.empty() && target == participant;
}

}  // namespace harness
