#pragma once
// Where the operations fuzzer is when a check fails: the structure under test, the step of the
// operation sequence and the operation. Every check goes through require(), so a finding
// names all three (the input that reproduces it is libFuzzer's crash-<sha1> file).
// With SPATIAL_FUZZ_TRACE set in the environment, every operation is printed with its
// arguments as it runs (trace()), which turns a minimised crash input into a regression test.

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "../common/finding.hpp"

namespace spatial_fuzz {

class operation_log {
public:
    explicit operation_log(std::string_view structure) : structure_(structure) {}

    void begin(std::size_t step, std::string_view operation) {
        step_ = step;
        operation_ = operation;
    }
    // Prints "step N operation: describe()" when tracing (describe() is only called then).
    template <class Describe>
    void trace(Describe&& describe) const {
        if (!tracing_) return;
        const std::string what = describe();
        std::fprintf(stderr, "step %zu %.*s: %s\n", step_, static_cast<int>(operation_.size()), operation_.data(),
                     what.c_str());
    }
    void require(bool ok, std::string_view what) const {
        if (!ok) fail(what);
    }
    [[noreturn]] void fail(std::string_view what) const {
        finding("operations", what,
                "structure " + structure_ + ", step " + std::to_string(step_) + ", operation " + std::string(operation_));
    }

private:
    std::string structure_;
    std::size_t step_ = 0;
    std::string_view operation_ = "setup";
    bool tracing_ = std::getenv("SPATIAL_FUZZ_TRACE") != nullptr;
};

}  // namespace spatial_fuzz
