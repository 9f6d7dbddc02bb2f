# Harness tests: validation helpers, CSV writing, and every suite run end to end at smoke size
# (every structure and peer, answers validated against the oracle before timing, CSV +
# sidecar + registry written).
spatial_add_test(harness_test harness_test.cpp)
target_link_libraries(harness_test PRIVATE spatial_harness)
# fuzz/command_line/vocabulary.hpp, checked against the suite table.
target_include_directories(harness_test PRIVATE ${PROJECT_SOURCE_DIR})

# The allocator policy of run and scene (harness/allocator_policy.hpp): freed memory kept for
# the next timed round, returned between cases; the sidecar names it.
find_package(nlohmann_json REQUIRED)
spatial_add_test(allocator_policy_test allocator_policy_test.cpp)
target_link_libraries(allocator_policy_test PRIVATE spatial_harness nlohmann_json::nlohmann_json)
target_compile_definitions(allocator_policy_test PRIVATE SPATIAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# Result tables read back, compared and merged (the compare and merge commands). Links only the
# table library: no suites, no peers.
spatial_add_test(result_table_test result_table_test.cpp)
target_link_libraries(result_table_test PRIVATE spatial_result_tables)
target_compile_definitions(result_table_test PRIVATE SPATIAL_RESULTS_DIR="${PROJECT_SOURCE_DIR}/results")

# A suite (or a scene) run end to end: `name` runs `spatialbench ARGS...` and must succeed;
# its tables go to ${CMAKE_CURRENT_BINARY_DIR}/<dir>. Part of the smoke_tables fixture that
# the key check below reads.
function(spatialbench_smoke name dir)
  add_test(NAME ${name} COMMAND $<TARGET_FILE:spatialbench> ${ARGN} --quiet --results ${CMAKE_CURRENT_BINARY_DIR}/${dir})
  set_tests_properties(${name} PROPERTIES TIMEOUT 600 FIXTURES_SETUP smoke_tables)
endfunction()
# Bad input: `name` runs `spatialbench ARGS...`, which must stop with the usage-error message
# naming the problem (`message`, a regular expression), not crash or succeed.
function(spatialbench_rejects name message)
  add_test(NAME ${name} COMMAND $<TARGET_FILE:spatialbench> ${ARGN} --quiet --results ${CMAKE_CURRENT_BINARY_DIR}/bad_results)
  set_tests_properties(${name} PROPERTIES PASS_REGULAR_EXPRESSION "spatialbench: error: ${message}")
endfunction()

# knn; bv (every fit checked for containment, overlap tests against the exact reference);
# raycast (generated sphere and soup, every structure against brute force and the reference);
# structures (every structure of the library next to the peers); collide (static, moving and
# triangle pairs); a scene on every structure that answers it.
spatialbench_smoke(spatialbench_smoke_run smoke_results run --suite knn --preset smoke)
spatialbench_smoke(spatialbench_bv_smoke_run bv_smoke_results run --suite bv --preset smoke)
spatialbench_smoke(spatialbench_raycast_smoke_run raycast_smoke_results run --suite raycast --preset smoke)
spatialbench_smoke(spatialbench_structures_smoke_run structures_smoke_results run --suite structures --preset smoke)
spatialbench_smoke(spatialbench_collide_smoke_run collide_smoke_results run --suite collide --preset smoke)
spatialbench_smoke(spatialbench_scenes_smoke_run scenes_smoke_results
                   scene ${PROJECT_SOURCE_DIR}/datasets/scenes/falling_boxes.toml --structure all --steps 3)
spatialbench_rejects(spatialbench_rejects_unknown_workload "unknown point workload \"nosuchworkload\""
                     run --preset smoke --workload nosuchworkload)
spatialbench_rejects(spatialbench_bv_rejects_unknown_shape "unknown shape 'nosuchshape'"
                     run --suite bv --preset smoke --workload nosuchshape)
spatialbench_rejects(spatialbench_raycast_rejects_unknown_workload "unknown mesh workload \"teapot\""
                     run --suite raycast --preset smoke --workload teapot)

# The smoke fixture's tables, which the checks below read.
set(spatial_smoke_tables
    ${CMAKE_CURRENT_BINARY_DIR}/smoke_results/knn.csv
    ${CMAKE_CURRENT_BINARY_DIR}/structures_smoke_results/structures.csv
    ${CMAKE_CURRENT_BINARY_DIR}/bv_smoke_results/bv.csv
    ${CMAKE_CURRENT_BINARY_DIR}/raycast_smoke_results/raycast.csv
    ${CMAKE_CURRENT_BINARY_DIR}/collide_smoke_results/collide.csv
    ${CMAKE_CURRENT_BINARY_DIR}/scenes_smoke_results/scenes.csv)

# The smoke tables keep their keys and our structures' answers (tests/check_table_keys.py):
# every key of tests/data/smoke_table_keys.csv appears again, and every answer figure (pairs,
# hits, recall, tightness, nodes visited, ...) is the same number. Regenerate the reference
# with --write only for a change that is meant to change them, and say why in its commit.
add_test(NAME spatialbench_smoke_tables_keep_keys_and_answers
         COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/check_table_keys.py
                 ${CMAKE_CURRENT_SOURCE_DIR}/data/smoke_table_keys.csv
                 ${spatial_smoke_tables})
set_tests_properties(spatialbench_smoke_tables_keep_keys_and_answers PROPERTIES FIXTURES_REQUIRED smoke_tables)

# docs/adding-a-structure.md, tested: the example structure (examples/) appears with validated
# rows in every suite and in a scene, and in `list` and results/registry.json.
add_test(NAME spatialbench_example_structure_everywhere
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_example_structure.sh $<TARGET_FILE:spatialbench>
                 ${PROJECT_SOURCE_DIR}/datasets/scenes/falling_boxes.toml
                 ${CMAKE_CURRENT_BINARY_DIR}/example_structure_results)
set_tests_properties(spatialbench_example_structure_everywhere PROPERTIES TIMEOUT 600)

# Suites as lists of cases: `list --cases`, `run --case ID`, an unknown id rejected by name.
add_test(NAME spatialbench_case_selection
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_case_selection.sh $<TARGET_FILE:spatialbench>
                 ${CMAKE_CURRENT_BINARY_DIR}/case_selection_results)
set_tests_properties(spatialbench_case_selection PROPERTIES TIMEOUT 300)

# Fail-closed, end to end: a corrupted answer (ours and a peer's, in every suite and a scene)
# stops the run with exit status 2 and leaves the previous table and the folder untouched.
add_test(NAME spatialbench_fails_closed_on_a_wrong_answer
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_fail_closed.sh $<TARGET_FILE:spatialbench>
                 ${PROJECT_SOURCE_DIR}/datasets/scenes/falling_boxes.toml
                 ${CMAKE_CURRENT_BINARY_DIR}/fail_closed_results)
set_tests_properties(spatialbench_fails_closed_on_a_wrong_answer PROPERTIES TIMEOUT 600)

# Asking for more memory than the machine has: a clear error before any allocation, naming
# what was asked and what is available (harness/memory_budget.hpp), for a scene, for --n, and
# for a modest run on a machine said to have 100 kB (SPATIALBENCH_AVAILABLE_MEMORY).
add_test(NAME spatialbench_rejects_a_scene_larger_than_memory
         COMMAND $<TARGET_FILE:spatialbench> scene ${CMAKE_CURRENT_SOURCE_DIR}/data/scene_larger_than_memory.toml
                 --quiet --results ${CMAKE_CURRENT_BINARY_DIR}/bad_results)
set_tests_properties(spatialbench_rejects_a_scene_larger_than_memory PROPERTIES PASS_REGULAR_EXPRESSION
  "spatialbench: error: scene larger_than_memory needs about 1\\.0 TB \\(4000000000 objects x about 256 B.*, but .* is available \\(")
spatialbench_rejects(spatialbench_rejects_n_larger_than_memory
                     "case knn/uniform/n=4000000000/3d/double needs about 6\\.1 TB .* is available"
                     run --suite knn --preset smoke --workload uniform --n 4000000000)
add_test(NAME spatialbench_rejects_a_run_larger_than_the_memory_limit
         COMMAND ${CMAKE_COMMAND} -E env SPATIALBENCH_AVAILABLE_MEMORY=100000
                 $<TARGET_FILE:spatialbench> run --suite collide --preset smoke --quiet --results ${CMAKE_CURRENT_BINARY_DIR}/bad_results)
set_tests_properties(spatialbench_rejects_a_run_larger_than_the_memory_limit PROPERTIES PASS_REGULAR_EXPRESSION
  "spatialbench: error: case collide/boxes/n=1000 needs about [0-9.]+ [kM]B.*but 100\\.0 kB is available \\(SPATIALBENCH_AVAILABLE_MEMORY\\)")
# Static boxes keep every participant's structure alive at once, so the estimate is their sum
# (collide_suite.cpp, estimated_bytes_per_object): four of ours at 256 B a box, plus the case's
# own 128 B. With one flat 256 B a box, a full-preset run at 1e7 boxes with eight participants
# and the tuning sweep passed the check and was killed by the OOM killer at 24 GB; here the
# same check on 1e4 boxes and a 5 MB machine, which the flat figure (2.6 MB) let through.
add_test(NAME spatialbench_collide_estimate_counts_every_live_participant
         COMMAND ${CMAKE_COMMAND} -E env SPATIALBENCH_AVAILABLE_MEMORY=5000000
                 $<TARGET_FILE:spatialbench> run --suite collide --preset smoke --workload boxes --n 10000
                 --structure collision_grid bvh bvh_median uniform_grid --quiet --results ${CMAKE_CURRENT_BINARY_DIR}/bad_results)
set_tests_properties(spatialbench_collide_estimate_counts_every_live_participant PROPERTIES TIMEOUT 120 PASS_REGULAR_EXPRESSION
  "spatialbench: error: case collide/boxes/n=10000 needs about 11\\.5 MB \\(10000 objects x about 1152 B.*but 5\\.0 MB is available")

# Sharded runs (run/scene --shard i/N) joined by `spatialbench merge` give the single run's
# table: the same keys and answers as the smoke fixture's tables, every row validated, every
# run's sidecar (with its host) merged; overlapping shards are refused by name.
add_test(NAME spatialbench_shards_merge_to_the_single_run_table
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_shards.sh $<TARGET_FILE:spatialbench>
                 ${CMAKE_CURRENT_BINARY_DIR}/shard_results
                 ${PROJECT_SOURCE_DIR}/datasets/scenes/falling_boxes.toml
                 ${spatial_smoke_tables})
set_tests_properties(spatialbench_shards_merge_to_the_single_run_table PROPERTIES
                     FIXTURES_REQUIRED smoke_tables TIMEOUT 900)

# The same on a real Slurm (issue 21): a single-node Slurm started on this machine runs the
# smoke preset as a 3-task job array and the dependent merge (scripts/slurm/submit.sh);
# skipped, with the reason printed, where Slurm cannot start (not root, packages missing).
add_test(NAME spatialbench_slurm_job_array_merges_to_the_single_run_table
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_slurm.sh ${CMAKE_CURRENT_BINARY_DIR}/slurm_results
                 ${spatial_smoke_tables})
set_tests_properties(spatialbench_slurm_job_array_merges_to_the_single_run_table PROPERTIES
                     FIXTURES_REQUIRED smoke_tables SKIP_RETURN_CODE 77 TIMEOUT 900 RUN_SERIAL TRUE
                     ENVIRONMENT "SPATIALBENCH=$<TARGET_FILE:spatialbench>")

# The real data (issue 17): knn on every fetched point set and raycast on a fetched mesh, at
# smoke size, validated rows for each. scripts/test.sh fetches the data first; skipped elsewhere.
add_test(NAME spatialbench_real_data_smoke
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_real_data_smoke.sh $<TARGET_FILE:spatialbench>
                 ${PROJECT_SOURCE_DIR}/datasets/real ${CMAKE_CURRENT_BINARY_DIR}/real_data_results)
set_tests_properties(spatialbench_real_data_smoke PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600)

# Interrupted and resumed runs: SIGINT and SIGKILL halfway lose no completed case and leave the
# previous table; --resume finishes the missing cases into the uninterrupted run's table.
add_test(NAME spatialbench_interrupted_run_resumes_without_loss
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_resume.sh $<TARGET_FILE:spatialbench>
                 ${CMAKE_CURRENT_BINARY_DIR}/resume_results
                 ${CMAKE_CURRENT_BINARY_DIR}/raycast_smoke_results/raycast.csv)
set_tests_properties(spatialbench_interrupted_run_resumes_without_loss PROPERTIES
                     FIXTURES_REQUIRED smoke_tables TIMEOUT 600)

# scripts/provenance.py: which run (commit, date, preset, host) produced each table, from the
# tables' run ids and the sidecars; a row naming a run without a sidecar is an error naming it.
add_test(NAME provenance_lists_the_run_of_every_table
         COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/scripts/provenance.py --results ${CMAKE_CURRENT_BINARY_DIR}/smoke_results
                 --output ${CMAKE_CURRENT_BINARY_DIR}/smoke_results/provenance.md)
set_tests_properties(provenance_lists_the_run_of_every_table PROPERTIES FIXTURES_REQUIRED smoke_tables
                     PASS_REGULAR_EXPRESSION "provenance: wrote .*provenance.md")
add_test(NAME provenance_rejects_a_run_without_its_sidecar
         COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/scripts/provenance.py
                 --results ${CMAKE_CURRENT_SOURCE_DIR}/data/provenance_missing_sidecar --output ${CMAKE_CURRENT_BINARY_DIR}/provenance_refused.md)
set_tests_properties(provenance_rejects_a_run_without_its_sidecar PROPERTIES PASS_REGULAR_EXPRESSION
                     "knn.csv: 1 rows name run knn-smoke-nosuchrun, whose sidecar .* is missing")

# scripts/scaling.py: a figure counts at its suite's largest size when its own largest size is
# in the same decade (a generated mesh has about its nominal size).
add_test(NAME scaling_lists_a_figure_at_its_nominal_largest_size
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_scaling.sh $<TARGET_FILE:spatialbench> ${PROJECT_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/scaling_nominal_sizes)
set_tests_properties(scaling_lists_a_figure_at_its_nominal_largest_size PROPERTIES
                     PASS_REGULAR_EXPRESSION "check_scaling: nominal sizes listed at their decade")

# scripts/drop_keys_held_elsewhere.py (run by scripts/main.sh after the knn suite): the main
# table loses exactly the rows whose key a side table holds; a file that is no table is refused.
add_test(NAME results_side_tables_keep_their_keys_and_the_main_table_the_rest
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_drop_keys.sh ${PROJECT_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/drop_keys)
set_tests_properties(results_side_tables_keep_their_keys_and_the_main_table_the_rest PROPERTIES
                     PASS_REGULAR_EXPRESSION "check_drop_keys: side tables' keys taken out, the rest kept")
