# Library tests: header-only, no peers (fast to build, run under sanitizers).
spatial_add_test(container_contract_test container_contract_test.cpp)
# The element store behind every container: bulk append (one core and every core), its undo.
spatial_add_test(slot_storage_test slot_storage_test.cpp)
# The ready-made objects: box, sphere, triangle (watertight ray test).
spatial_add_test(objects_test objects_test.cpp)
spatial_add_test(property_test OPTIMIZED property_test.cpp)
spatial_add_test(kd_tree_test kd_tree_test.cpp)
# kd_tree's bulk build on every core: the same tree as the sequential build, node for node.
spatial_add_test(kd_tree_parallel_test kd_tree_parallel_test.cpp)
# Batched kNN (find_nearest_batch) in both query orders and on several threads; the Morton order.
spatial_add_test(knn_batch_test knn_batch_test.cpp)
# The k-best set every kNN search fills, on both sides of its inline array's limit.
spatial_add_test(knn_result_set_test knn_result_set_test.cpp)
spatial_add_test(bv_test bv_test.cpp)
# Bounding volumes, one test file per type (bv_test: aabb and sphere).
spatial_add_test(obb_test obb_test.cpp)
spatial_add_test(kdop_test kdop_test.cpp)
spatial_add_test(ellipsoid_test ellipsoid_test.cpp)
spatial_add_test(convex_hull_test convex_hull_test.cpp)
# Bounding volume hierarchy: part 1 (aabb, sphere, kdop; hard cases), part 2 (obb, ellipsoid, hull,
# spheres, triangles), part 3 (2D, float), the contract suite.
spatial_add_test(bvh_test bvh_test.cpp)
spatial_add_test(bvh_volumes_test bvh_volumes_test.cpp)
spatial_add_test(bvh_2d_float_test bvh_2d_float_test.cpp)
spatial_add_test(bvh_contract_test bvh_contract_test.cpp)
# Loose/classic octree and the uniform and hashed grids (shared hard cases: octree_grid_checks.hpp).
spatial_add_test(octree_test octree_test.cpp)
# The octree's own broad phase (self_pairs / pairs_with descents) against brute force.
spatial_add_test(tree_pairs_test OPTIMIZED tree_pairs_test.cpp)
spatial_add_test(grid_test grid_test.cpp)
# kd_tree over objects with extent (skd-tree): contract suite and hard cases; differential tests.
spatial_add_test(kd_tree_objects_test kd_tree_objects_test.cpp)
spatial_add_test(kd_tree_objects_differential_test OPTIMIZED kd_tree_objects_differential_test.cpp)
spatial_add_test(bvh_ray_fast_path_test OPTIMIZED bvh_ray_fast_path_test.cpp)
# It forces the 8-wide layout even where AVX is off (the sanitizer build has no -march=native):
# GCC then notes that 32-byte vector arguments change the ABI, which cannot matter for the
# layout's inline helpers (never called across a library boundary).
target_compile_options(bvh_ray_fast_path_test PRIVATE -Wno-psabi)
spatial_add_test(bvh_parallel_test OPTIMIZED bvh_parallel_test.cpp)

# Exact segment/triangle intersection (collide/), with CGAL as the differential oracle when
# the harness's CGAL adapter is built (not in the sanitizer build, which still runs the rest).
spatial_add_test(exact_intersection_test exact_intersection_test.cpp)
if(TARGET spatial_adapters AND TARGET spatial_harness_interface)
  target_link_libraries(exact_intersection_test PRIVATE spatial_adapters spatial_harness_interface)
endif()
spatial_add_test(collide_pairs_test collide_pairs_test.cpp)
spatial_add_test(narrow_phase_test narrow_phase_test.cpp)
spatial_add_test(collide_motion_test collide_motion_test.cpp)

# Scene files (datasets/scene.hpp): parsing and errors with their lines, generation, motion,
# churn and query draws; every scene in datasets/scenes parses and generates.
spatial_add_test(scene_file_test scene_file_test.cpp)
target_link_libraries(scene_file_test PRIVATE spatial::datasets)
target_compile_definitions(scene_file_test PRIVATE SPATIAL_SCENES_DIR="${PROJECT_SOURCE_DIR}/datasets/scenes")

# Structures outside the library (examples/): the contract suite and the differential tests,
# exactly as for the library's own structures.
spatial_add_test(example_structures_test example_structures_test.cpp)
target_link_libraries(example_structures_test PRIVATE spatial::examples)
# The capability concepts hold for exactly their documented models; the shared container base
# (statistics, error names, ray thickness).
spatial_add_test(capabilities_test capabilities_test.cpp)
# What the operations fuzzer found (fuzz/operations, docs/fuzzing.md): one test per finding, on
# every structure over points and boxes, against brute_force.
spatial_add_test(fuzz_findings_test fuzz_findings_test.cpp)
# Exception safety under allocation failure: every structure's mutations, failing at each of
# their allocations in turn (a replaced global operator new: failing_allocation.cpp).
spatial_add_test(allocation_failure_test allocation_failure_test.cpp failing_allocation.cpp)

# The library in another project: installed into a fresh prefix, found by a consumer project
# with find_package(spatial CONFIG), built and run (README, "Use it in your project").
add_test(NAME spatial_install_and_use_from_another_project
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_install.sh ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/install_check)
set_tests_properties(spatial_install_and_use_from_another_project PROPERTIES TIMEOUT 300)
