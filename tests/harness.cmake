# Harness tests: validation helpers, CSV writing, and a smoke run of the CLI end to end
# (every structure and peer, answers validated against the oracle, CSV + sidecar written).
spatial_add_test(harness_test harness_test.cpp)
target_link_libraries(harness_test PRIVATE spatial_harness)

add_test(NAME spatialbench_smoke_run
         COMMAND ${CMAKE_COMMAND} -E env
                 $<TARGET_FILE:spatialbench> run --suite knn --preset smoke --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/smoke_results)
set_tests_properties(spatialbench_smoke_run PROPERTIES TIMEOUT 300)
add_test(NAME spatialbench_rejects_unknown_workload
         COMMAND $<TARGET_FILE:spatialbench> run --preset smoke --workload nosuchworkload --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/bad_results)
set_tests_properties(spatialbench_rejects_unknown_workload PROPERTIES WILL_FAIL TRUE)

# The bv suite end to end at smoke size (every fit checked for containment, overlap tests
# against the exact reference, CSV + sidecar written), and its rejection of an unknown shape.
add_test(NAME spatialbench_bv_smoke_run
         COMMAND $<TARGET_FILE:spatialbench> run --suite bv --preset smoke --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/bv_smoke_results)
set_tests_properties(spatialbench_bv_smoke_run PROPERTIES TIMEOUT 300)
add_test(NAME spatialbench_bv_rejects_unknown_shape
         COMMAND $<TARGET_FILE:spatialbench> run --suite bv --preset smoke --workload nosuchshape --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/bv_bad_results)
set_tests_properties(spatialbench_bv_rejects_unknown_shape PROPERTIES WILL_FAIL TRUE)

# The raycast suite end to end at smoke size (generated sphere and soup; every structure
# validated against brute force and the reference before timing; CSV + sidecar written), and
# its rejection of an unknown mesh workload.
add_test(NAME spatialbench_raycast_smoke_run
         COMMAND $<TARGET_FILE:spatialbench> run --suite raycast --preset smoke --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/raycast_smoke_results)
set_tests_properties(spatialbench_raycast_smoke_run PROPERTIES TIMEOUT 300)
add_test(NAME spatialbench_raycast_rejects_unknown_workload
         COMMAND $<TARGET_FILE:spatialbench> run --suite raycast --preset smoke --workload teapot --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/raycast_bad_results)
set_tests_properties(spatialbench_raycast_rejects_unknown_workload PROPERTIES WILL_FAIL TRUE)

# The structures suite end to end at smoke size: every structure of the library (kd_tree, bvh,
# octree, uniform and hashed grids) next to the peers, each validated before timing.
add_test(NAME spatialbench_structures_smoke_run
         COMMAND $<TARGET_FILE:spatialbench> run --suite structures --preset smoke --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/structures_smoke_results)
set_tests_properties(spatialbench_structures_smoke_run PROPERTIES TIMEOUT 300)

# docs/adding-a-structure.md, tested: the example structure (examples/) appears with validated
# rows in every suite and in a scene, and in `list` and results/registry.json.
add_test(NAME spatialbench_example_structure_everywhere
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_example_structure.sh $<TARGET_FILE:spatialbench>
                 ${PROJECT_SOURCE_DIR}/datasets/scenes/falling_boxes.toml
                 ${CMAKE_CURRENT_BINARY_DIR}/example_structure_results)
set_tests_properties(spatialbench_example_structure_everywhere PROPERTIES TIMEOUT 600)

# The collide suite and the scenes end to end at smoke size (every structure and peer of each,
# validated before timing).
add_test(NAME spatialbench_collide_smoke_run
         COMMAND $<TARGET_FILE:spatialbench> run --suite collide --preset smoke --quiet
                 --results ${CMAKE_CURRENT_BINARY_DIR}/collide_smoke_results)
set_tests_properties(spatialbench_collide_smoke_run PROPERTIES TIMEOUT 600)
add_test(NAME spatialbench_scenes_smoke_run
         COMMAND $<TARGET_FILE:spatialbench> scene ${PROJECT_SOURCE_DIR}/datasets/scenes/falling_boxes.toml
                 --structure all --steps 3 --quiet --results ${CMAKE_CURRENT_BINARY_DIR}/scenes_smoke_results)
set_tests_properties(spatialbench_scenes_smoke_run PROPERTIES TIMEOUT 600)

# The smoke tables keep their keys and our structures' answers (tests/check_table_keys.py):
# every key of tests/data/smoke_table_keys.csv appears again, and every answer figure (pairs,
# hits, recall, tightness, nodes visited, ...) is the same number. Regenerate the reference
# with --write only for a change that is meant to change them, and say why in its commit.
set_tests_properties(spatialbench_smoke_run spatialbench_structures_smoke_run spatialbench_bv_smoke_run
                     spatialbench_raycast_smoke_run spatialbench_collide_smoke_run spatialbench_scenes_smoke_run
                     PROPERTIES FIXTURES_SETUP smoke_tables)
add_test(NAME spatialbench_smoke_tables_keep_keys_and_answers
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/check_table_keys.py
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/smoke_table_keys.csv
                 ${CMAKE_CURRENT_BINARY_DIR}/smoke_results/knn.csv
                 ${CMAKE_CURRENT_BINARY_DIR}/structures_smoke_results/structures.csv
                 ${CMAKE_CURRENT_BINARY_DIR}/bv_smoke_results/bv.csv
                 ${CMAKE_CURRENT_BINARY_DIR}/raycast_smoke_results/raycast.csv
                 ${CMAKE_CURRENT_BINARY_DIR}/collide_smoke_results/collide.csv
                 ${CMAKE_CURRENT_BINARY_DIR}/scenes_smoke_results/scenes.csv)
set_tests_properties(spatialbench_smoke_tables_keep_keys_and_answers PROPERTIES FIXTURES_REQUIRED smoke_tables)
