#pragma once
// Progress display for long runs: one line per finished step on stderr, with elapsed time
// and the step's headline figure, so a 15-minute suite is never silent.

#include <chrono>
#include <cstdio>
#include <string>

namespace harness {

class progress {
public:
    explicit progress(bool quiet = false) : quiet_(quiet), start_(std::chrono::steady_clock::now()) {}
    void say(const std::string& line) const {
        if (quiet_) return;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        std::fprintf(stderr, "[%7.1fs] %s\n", s, line.c_str());
        std::fflush(stderr);
    }
    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    bool quiet_;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace harness
