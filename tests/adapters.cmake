# Adapter tests: every peer adapter against a brute-force oracle written in the test.
# The test includes only harness/adapters.hpp; peers come in through spatial_adapters
# (whichever of spatial_adapter_nanoflann / spatial_adapter_cgal were configured).
spatial_add_test(adapters_test ${CMAKE_CURRENT_LIST_DIR}/adapters_test.cpp)
target_link_libraries(adapters_test PRIVATE spatial_adapters spatial_harness_interface)

# Bounding volumes against CGAL (harness/bv_oracles.hpp; CGAL itself stays in the adapter).
spatial_add_test(bv_oracle_test ${CMAKE_CURRENT_LIST_DIR}/bv_oracle_test.cpp)
target_link_libraries(bv_oracle_test PRIVATE spatial_adapters spatial_harness_interface spatial::datasets)

# Ray casting: mesh generators, CGAL mesh loading, Embree and CGAL AABB_tree against
# spatial::brute_force<triangle> (harness/ray_adapters.hpp, harness/ray_validation.hpp).
spatial_add_test(adapters_raycast_test ${CMAKE_CURRENT_LIST_DIR}/adapters_raycast_test.cpp)
target_link_libraries(adapters_raycast_test PRIVATE spatial_adapters spatial_harness_interface spatial::datasets)
target_compile_definitions(adapters_raycast_test PRIVATE
  SPATIAL_DATASETS_SAMPLES_DIR="${PROJECT_SOURCE_DIR}/datasets/samples"
  SPATIAL_DATASETS_REAL_DIR="${PROJECT_SOURCE_DIR}/datasets/real")

# Embree user geometry over boxes and points (harness/object_ray_index.hpp) against
# spatial::brute_force: exact hit times.
spatial_add_test(embree_user_geometry_test ${CMAKE_CURRENT_LIST_DIR}/embree_user_geometry_test.cpp)
target_link_libraries(embree_user_geometry_test PRIVATE spatial_adapters spatial_harness_interface)

# Collision peers (harness/collide_adapters.hpp: CGAL box_intersection_d, FCL's broad-phase
# managers, Embree rtcCollide) against a brute-force closed-box oracle: identical pair sets.
spatial_add_test(adapters_collide_test ${CMAKE_CURRENT_LIST_DIR}/adapters_collide_test.cpp)
target_link_libraries(adapters_collide_test PRIVATE spatial_adapters spatial_harness_interface)

# The scene runner (harness/scene_runner.hpp): pipeline composition proved by call counters,
# identical pairs across structures, and every shipped scene (datasets/scenes/*.toml).
spatial_add_test(scene_runner_test ${CMAKE_CURRENT_LIST_DIR}/scene_runner_test.cpp)
target_link_libraries(scene_runner_test PRIVATE spatial_harness)
target_compile_definitions(scene_runner_test PRIVATE SPATIAL_SCENES_DIR="${PROJECT_SOURCE_DIR}/datasets/scenes")
