// The operations fuzzer's kd-tree instantiations (structure_table.hpp).
#include "operation_sequence.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "structure_table.hpp"

namespace spatial_fuzz {

std::span<const named_structure> kd_tree_structures() {
    static constexpr named_structure table[] = {
        {"kd_tree<point<double, 3>>", &run_operations<spatial::kd_tree<point3>>},
        {"kd_tree<box<double, 3>>", &run_operations<spatial::kd_tree<box3>>},
    };
    return table;
}

}  // namespace spatial_fuzz
