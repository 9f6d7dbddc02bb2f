#pragma once
// Timing — the one place the harness times anything (docs/harness.md, "Methodology").
// Every measurement is: warm-up run(s), then `repetitions` timed runs, the MEDIAN reported
// (robust to the noise of a shared machine) with min and max kept for the CSV's spread
// columns, and every timed run checked against the answers validated before timing began.
//   * time_interleaved: several participants doing the same work, round by round (A, B, C,
//     A, B, C, ...), so that a noisy interval hits all alike and same-run ratios hold;
//   * time_repeated: one participant whose work changes its state (insertions, erasures),
//     with an untimed reset before each run.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace harness {

struct timing_result {
    double median_seconds = 0;
    double min_seconds = 0;
    double max_seconds = 0;
    std::size_t repetitions = 0;
    std::vector<double> samples;  // the timed runs, in the order they ran
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

inline timing_result summarize(std::vector<double> samples) {
    timing_result r;
    if (samples.empty()) return r;
    r.samples = samples;
    std::sort(samples.begin(), samples.end());
    const std::size_t n = samples.size();
    r.median_seconds = n % 2 ? samples[n / 2] : (samples[n / 2 - 1] + samples[n / 2]) / 2;
    r.min_seconds = samples.front();
    r.max_seconds = samples.back();
    r.repetitions = n;
    return r;
}

// A run at least this long is timed once: it averages the machine's noise over its own
// length, and more rounds of it would dominate a suite's time (the convex-hull bvh's rays on
// the 1e5 sphere took 20 s a round: 7 rounds were most of the raycast suite's quick preset;
// CGAL's minimum ellipsoid of 1e5 points takes 2.5 s, five runs of it a bv case's half).
inline constexpr double long_run_seconds = 2.0;

// Two works timed round by round by time_interleaved with no warm-up round (a build and the
// query on what it built): the sum of each round's two samples. Sample r of each is round
// r's, and a work that was long has only round 0's, so the sums run over the rounds both
// were timed in (a long query beside a short build: round 0's build plus its query, never a
// build alone).
inline timing_result summed_rounds(const timing_result& a, const timing_result& b) {
    std::vector<double> total(std::min(a.samples.size(), b.samples.size()));
    for (std::size_t r = 0; r < total.size(); ++r) total[r] = a.samples[r] + b.samples[r];
    return summarize(std::move(total));
}

// Runs body() warmup + repetitions times; `before()` runs untimed before each (e.g. to
// reset state). body() returns a value that is checked by `check(value)` after every run,
// the warm-up included (the answer checksum must equal the validated one). A run that takes
// at least `long_run` seconds ends the measurement, as in time_interleaved: it is its last
// timed run (a warm-up included), so a first run that long is the only one.
template <class Before, class Body, class Check>
timing_result time_repeated(std::size_t warmup, std::size_t repetitions, Before&& before, Body&& body,
                            Check&& check, double long_run = long_run_seconds) {
    std::vector<double> samples;
    for (std::size_t i = 0; i < warmup + repetitions; ++i) {
        before();
        const auto t0 = std::chrono::steady_clock::now();
        auto value = body();
        const double s = seconds_since(t0);
        check(value);
        if (i >= warmup || s >= long_run) samples.push_back(s);
        if (s >= long_run) break;
    }
    return summarize(std::move(samples));
}

// One participant's share of an interleaved measurement.
struct timed_work {
    std::string where;            // names the participant and its work, for the error message
    std::function<double()> run;  // one repetition of the work; returns its answers' checksum
    double validated = 0;         // the checksum of the answers that passed validation
};

// `warmup` untimed rounds, then `repetitions` timed rounds; each round runs every work once,
// in order, except that a work whose run took at least `long_run` seconds is timed by that
// one run, a warm-up included (a run that long warms its own caches; the validated run the
// suites make first has built anything built lazily): its timing_result has repetitions = 1,
// which the CSV's repetitions column shows. A run whose checksum differs from its validated
// one throws validation_error (harness/validation.hpp): a timing is kept only for the
// validated answers. Returns one timing per work, in order.
std::vector<timing_result> time_interleaved(const std::vector<timed_work>& work, std::size_t warmup,
                                            std::size_t repetitions, double long_run = long_run_seconds);

}  // namespace harness
