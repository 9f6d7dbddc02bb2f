#pragma once
// How a fuzz target reports a finding that no sanitizer sees: a wrong answer, a broken
// round trip, an exception of a type the code under test does not document. It prints what
// went wrong and aborts; libFuzzer treats the abort as a crash, saves the input as
// crash-<sha1> and stops (libFuzzer docs, "Options": a crash ends the run unless
// -fork / -ignore_crashes). An undocumented exception needs no call here: it escapes
// LLVMFuzzerTestOneInput, std::terminate aborts, and libFuzzer reports "deadly signal".
// The soak tool (fuzz/soak/) counts findings and goes on with its next sequence: it asks for a
// finding_report to be thrown instead of the abort.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace spatial_fuzz {

// Not a std::exception: no handler in the code under test or the checks can take it for its own.
struct finding_report {
    std::string what;
};
// Set by the soak tool: finding() throws a finding_report instead of aborting.
inline bool& findings_throw() {
    static bool on = false;
    return on;
}

[[noreturn]] inline void finding(std::string_view target, std::string_view what, std::string_view detail = {}) {
    std::fprintf(stderr, "\n==== %.*s: FINDING: %.*s\n", static_cast<int>(target.size()), target.data(),
                 static_cast<int>(what.size()), what.data());
    if (!detail.empty()) std::fprintf(stderr, "%.*s\n", static_cast<int>(detail.size()), detail.data());
    std::fflush(stderr);
    if (findings_throw()) throw finding_report{std::string(what) + (detail.empty() ? "" : "; " + std::string(detail))};
    std::abort();
}

}  // namespace spatial_fuzz
