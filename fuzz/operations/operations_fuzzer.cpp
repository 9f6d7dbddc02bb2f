// Fuzz target: operation sequences on the in-house structures, every answer compared with
// spatial::brute_force (operation_sequence.hpp). The first byte picks the structure
// (structure_table.hpp), the rest is read as operations. A wrong answer, a rejected input
// that was accepted or changed the structure, a sanitizer report, a hang or an exception other
// than the contract's std::invalid_argument is a finding.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_input.hpp"
#include "structure_table.hpp"

namespace {

const std::vector<spatial_fuzz::named_structure>& structures() {
    static const std::vector<spatial_fuzz::named_structure> all = [] {
        std::vector<spatial_fuzz::named_structure> v;
        for (auto family : {spatial_fuzz::kd_tree_structures, spatial_fuzz::octree_structures,
                            spatial_fuzz::grid_structures, spatial_fuzz::bvh_point_structures,
                            spatial_fuzz::bvh_box_structures, spatial_fuzz::collide_structures})
            for (const auto& s : family()) v.push_back(s);
        return v;
    }();
    return all;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const auto& structure = structures()[data[0] % structures().size()];
    spatial_fuzz::fuzz_input in(data + 1, size - 1);
    structure.run(in, structure.name);
    return 0;
}
