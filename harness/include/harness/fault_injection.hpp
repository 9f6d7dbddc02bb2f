#pragma once
// harness::injected_fault — the hook behind the fail-closed tests (tests/check_fail_closed.sh).
// With SPATIALBENCH_INJECT_FAULT=<name> in the environment, the participant of that name (a
// structure, a peer, or in the bv suite a volume type) gets one of its answers corrupted
// after it answered and BEFORE validation, in the way each suite's answers can be wrong:
// a kNN answer reports one point twice (a dynamic structure's contents lose a point), ray
// hits move, a pair goes missing, an overlap test says "disjoint" where the volumes meet
// (`<structure>@timed`: a pair goes missing in a scene's timed pass only, where the answers
// are compared with the validated pass's instead of brute force). The
// run must then stop with exit status 2 and leave every table it would have written as it
// was. Unset, it costs one string compare per validated answer set, outside every timed region.

#include <csignal>
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

// The hook behind the interrupted-run tests (tests/check_resume.sh): with
// SPATIALBENCH_INTERRUPT_AFTER_CASES=<k>:<INT|TERM|KILL>, the run sends itself that signal
// once it has completed (and journaled) k cases in this process, as Ctrl-C, a scheduler's
// SIGTERM or the OOM killer would at that moment. Unset, it does nothing.
inline void injected_interrupt(std::size_t cases_completed_here) {
    static const char* v = std::getenv("SPATIALBENCH_INTERRUPT_AFTER_CASES");
    if (!v) return;
    const std::string spec(v);
    const auto colon = spec.find(':');
    if (colon == std::string::npos || std::stoul(spec.substr(0, colon)) != cases_completed_here) return;
    const std::string sig = spec.substr(colon + 1);
    std::raise(sig == "KILL" ? SIGKILL : sig == "TERM" ? SIGTERM : SIGINT);
}

}  // namespace harness
