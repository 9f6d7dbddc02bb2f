// The operations fuzzer's octree instantiations (structure_table.hpp).
#include "operation_sequence.hpp"
#include "spatial/octree/octree.hpp"
#include "structure_table.hpp"

namespace spatial_fuzz {

std::span<const named_structure> octree_structures() {
    static constexpr named_structure table[] = {
        {"octree<box<double, 3>>", &run_operations<spatial::octree<box3>>},
#if SPATIAL_FUZZ_FULL_MATRIX
        {"octree<point<double, 3>>", &run_operations<spatial::octree<point3>>},
#endif
    };
    return table;
}

}  // namespace spatial_fuzz
