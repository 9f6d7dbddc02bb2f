// Fuzz target: operation sequences on the in-house structures, every answer compared with
// spatial::brute_force (operation_sequence.hpp). The first byte picks the structure
// (structure_table.hpp), the rest is read as operations. A wrong answer, a rejected input
// that was accepted or changed the structure, a sanitizer report, a hang or an exception other
// than the contract's std::invalid_argument is a finding.
// An input with the soak tool's header (soak_file.hpp) is a sequence the soak found failing:
// its structure is named, and it is read with the soak's limits.

#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "fuzz_input.hpp"
#include "soak_file.hpp"
#include "structure_table.hpp"

namespace {

void replay_soak_sequence(const spatial_fuzz::soak_sequence& sequence) {
    for (const auto& structure : spatial_fuzz::all_structures())
        if (structure.name == sequence.structure) {
            spatial_fuzz::fuzz_input in(sequence.data, sequence.size);
            structure.run(in, structure.name, spatial_fuzz::soak_limits);
            return;
        }
    // Not a finding: the fuzzer may write such a header by chance; a replay needs the full matrix.
    std::fprintf(stderr, "operations: soak sequence for '%.*s', a structure this build does not have "
                         "(SPATIAL_FUZZ_FULL_MATRIX=ON builds all of them)\n",
                 static_cast<int>(sequence.structure.size()), sequence.structure.data());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    if (const auto sequence = spatial_fuzz::read_soak_file(data, size)) {
        replay_soak_sequence(*sequence);
        return 0;
    }
    const auto& structures = spatial_fuzz::all_structures();
    const auto& structure = structures[data[0] % structures.size()];
    spatial_fuzz::fuzz_input in(data + 1, size - 1);
    structure.run(in, structure.name, spatial_fuzz::fuzzing_limits);
    return 0;
}
