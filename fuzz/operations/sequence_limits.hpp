#pragma once
// How long an operation sequence runs and how large its containers grow: the one difference
// between a fuzzing input and a soak sequence (fuzz/soak/), which share the interpreter
// (operation_sequence.hpp).
//
// Fuzzing wants many short, cheap inputs: 300 objects keep the oracle's O(n^2) pairs cheap,
// and every chosen clear or range erase runs. Read that way, uniformly random bytes (the soak's)
// keep the containers at a few dozen objects: one operation in 19 is a clear and one in 19 a
// range erase of a third of the objects on average. The soak's limits let a clear or a range
// erase run only one time in 16 when chosen, so a sequence grows its containers to the size
// cap and works on hundreds of objects for most of its thousands of steps.
//
// Validation: the fuzz target (and a replayed soak finding) compares every answer with the
// oracle. A long soak may compare one step in `validate_one_in` (the oracle still applies every
// mutation, so the next validated step compares against the true contents): that step's query
// answer, the invariants after its mutation, and every 16 * validate_one_in steps both
// containers' full contents. The other queries run on the structure alone, with the checks that
// need no oracle. Which steps are validated depends on the step number only, never on an input
// byte, so a sequence means the same at every interval, and a finding of a periodic run is found
// again by replaying its sequence with every step validated.

#include <cstddef>

namespace spatial_fuzz {

struct sequence_limits {
    std::size_t max_steps;
    std::size_t max_size;  // per container: an insertion beyond it is skipped
    // A chosen clear or erase(first, last) runs one time in this many (1: always). With 1 the
    // choice reads no byte, so a fuzzing input means what it meant before this existed.
    std::size_t wholesale_removal_one_in;
    // Compare with the oracle at one step in this many (1: every step; see above).
    std::size_t validate_one_in = 1;
};

// What a sequence did within its limits (the soak reports both).
struct sequence_summary {
    std::size_t operations = 0;  // applied: the steps minus those skipped
    std::size_t largest = 0;     // the most objects either container held after a mutation
};

inline constexpr sequence_limits fuzzing_limits{2000, 300, 1, 1};
// The soak's sequences; the soak tool sets validate_one_in from its --validate-every.
inline constexpr sequence_limits soak_limits{5000, 300, 16, 1};

}  // namespace spatial_fuzz
