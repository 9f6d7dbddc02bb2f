// The interleaved measurement loop (see timing.hpp).

#include "harness/timing.hpp"

#include <sstream>

#include "harness/validation.hpp"

namespace harness {

std::vector<timing_result> time_interleaved(const std::vector<timed_work>& work, std::size_t warmup,
                                            std::size_t repetitions, double long_run) {
    std::vector<std::vector<double>> samples(work.size());
    std::vector<bool> long_runs(work.size(), false);
    for (std::size_t round = 0; round < warmup + repetitions; ++round)
        for (std::size_t i = 0; i < work.size(); ++i) {
            if (long_runs[i]) continue;  // timed once (the run that was long): enough
            const auto t0 = std::chrono::steady_clock::now();
            const double checksum = work[i].run();
            const double seconds = seconds_since(t0);
            if (checksum != work[i].validated) {
                std::ostringstream os;
                os.precision(17);
                os << work[i].where << ": a timed repetition gave different answers than the validated run (checksum "
                   << checksum << ", validated " << work[i].validated << ")";
                throw validation_error(os.str());
            }
            // A long warm-up is its own warm-up: it counts as the timed run.
            if (seconds >= long_run) long_runs[i] = true;
            if (round >= warmup || long_runs[i]) samples[i].push_back(seconds);
        }
    std::vector<timing_result> out;
    out.reserve(work.size());
    for (auto& s : samples) out.push_back(summarize(std::move(s)));
    return out;
}

}  // namespace harness
