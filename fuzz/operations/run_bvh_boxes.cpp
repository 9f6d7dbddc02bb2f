// The operations fuzzer's bvh instantiations over boxes, one per bounding-volume type
// (structure_table.hpp).
#include "operation_sequence.hpp"
#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/ellipsoid.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"
#include "spatial/bvh/bvh.hpp"
#include "structure_table.hpp"

namespace spatial_fuzz {

std::span<const named_structure> bvh_box_structures() {
    using T = box3;
    static constexpr named_structure table[] = {
        {"bvh<box<double, 3>, aabb>", &run_operations<spatial::bvh<T>>},
#if SPATIAL_FUZZ_FULL_MATRIX
        {"bvh<box<double, 3>, obb>", &run_operations<spatial::bvh<T, spatial::obb<double, 3>>>},
        {"bvh<box<double, 3>, sphere>", &run_operations<spatial::bvh<T, spatial::sphere<double, 3>>>},
        {"bvh<box<double, 3>, kdop<26>>", &run_operations<spatial::bvh<T, spatial::kdop<double, 3, 26>>>},
        {"bvh<box<double, 3>, ellipsoid>", &run_operations<spatial::bvh<T, spatial::ellipsoid<double, 3>>>},
        {"bvh<box<double, 3>, convex_hull>", &run_operations<spatial::bvh<T, spatial::convex_hull<double, 3>>>},
#endif
    };
    return table;
}

}  // namespace spatial_fuzz
