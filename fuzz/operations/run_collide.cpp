// The operations fuzzer's pair-search structures (structure_table.hpp): no kNN, ball or ray
// queries; insert, erase, motion, box queries and pairs.
#include "operation_sequence.hpp"
#include "spatial/collide/collision_grid.hpp"
#include "spatial/collide/sweep_and_prune.hpp"
#include "structure_table.hpp"

namespace spatial_fuzz {

std::span<const named_structure> collide_structures() {
    static constexpr named_structure table[] = {
        {"collision_grid<box<double, 3>>", &run_operations<spatial::collision_grid<box3>>},
        {"sweep_and_prune<box<double, 3>>", &run_operations<spatial::sweep_and_prune<box3>>},
#if SPATIAL_FUZZ_FULL_MATRIX
        {"collision_grid<point<double, 3>>", &run_operations<spatial::collision_grid<point3>>},
        {"sweep_and_prune<point<double, 3>>", &run_operations<spatial::sweep_and_prune<point3>>},
#endif
    };
    return table;
}

}  // namespace spatial_fuzz
