// The scene runner for double scenes in 3D (see scene_runner_impl.hpp).
#include "scene_runner_impl.hpp"

namespace harness::scene_detail {
template std::vector<result_row> run_typed<double, 3>(const datasets::scene_description&, const scene_run_options&,
                                                   scene_counters&);
}  // namespace harness::scene_detail
