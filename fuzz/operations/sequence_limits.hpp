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

#include <cstddef>

namespace spatial_fuzz {

struct sequence_limits {
    std::size_t max_steps;
    std::size_t max_size;  // per container: an insertion beyond it is skipped
    // A chosen clear or erase(first, last) runs one time in this many (1: always). With 1 the
    // choice reads no byte, so a fuzzing input means what it meant before this existed.
    std::size_t wholesale_removal_one_in;
};

// What a sequence did within its limits (the soak reports both).
struct sequence_summary {
    std::size_t operations = 0;  // applied: the steps minus those skipped
    std::size_t largest = 0;     // the most objects either container held after a mutation
};

inline constexpr sequence_limits fuzzing_limits{2000, 300, 1};
inline constexpr sequence_limits soak_limits{5000, 300, 16};

}  // namespace spatial_fuzz
