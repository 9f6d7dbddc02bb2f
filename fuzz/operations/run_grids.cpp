// The operations fuzzer's grid instantiations (structure_table.hpp).
#include "operation_sequence.hpp"
#include "spatial/grid/hashed_grid.hpp"
#include "spatial/grid/uniform_grid.hpp"
#include "structure_table.hpp"

namespace spatial_fuzz {

std::span<const named_structure> grid_structures() {
    static constexpr named_structure table[] = {
        {"uniform_grid<point<double, 3>>", &run_operations<spatial::uniform_grid<point3>>},
        {"hashed_grid<box<double, 3>>", &run_operations<spatial::hashed_grid<box3>>},
#if SPATIAL_FUZZ_FULL_MATRIX
        {"uniform_grid<box<double, 3>>", &run_operations<spatial::uniform_grid<box3>>},
        {"hashed_grid<point<double, 3>>", &run_operations<spatial::hashed_grid<point3>>},
#endif
    };
    return table;
}

}  // namespace spatial_fuzz
