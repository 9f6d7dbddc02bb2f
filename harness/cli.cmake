# The spatialbench CLI and its support library.
find_package(CLI11 REQUIRED)
find_package(nlohmann_json REQUIRED)

# Result tables, apart from the suites: only the standard library, so what writes and reads
# tables builds, and is tested, without the structures' suites and the peers.
add_library(spatial_result_tables STATIC src/csv_writer.cpp src/result_table.cpp src/result_compare.cpp
                                   src/result_merge.cpp)
target_include_directories(spatial_result_tables PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
target_compile_options(spatial_result_tables PRIVATE ${SPATIAL_WARNINGS})

# The command line's options and checks (harness/command_line.hpp), apart from what runs them:
# the command-line fuzz target (fuzz/command_line/) parses without building a suite.
add_library(spatial_command_line STATIC src/command_line.cpp src/suite_options.cpp)
target_include_directories(spatial_command_line PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
target_link_libraries(spatial_command_line PUBLIC CLI11::CLI11 spatial::datasets)
target_compile_options(spatial_command_line PRIVATE ${SPATIAL_WARNINGS})

add_library(spatial_harness STATIC src/run_info.cpp src/timing.cpp src/knn_suite.cpp src/bv_suite.cpp
                            src/raycast_suite.cpp src/collide_suite.cpp
                            src/scene_runner.cpp src/suite_table.cpp src/suite_cases.cpp src/run_journal.cpp src/memory_budget.cpp src/allocator_policy.cpp
                            src/scene_runner_2d_float.cpp src/scene_runner_2d_double.cpp
                            src/scene_runner_3d_float.cpp src/scene_runner_3d_double.cpp)
target_include_directories(spatial_harness PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
target_link_libraries(spatial_harness PUBLIC spatial_result_tables spatial_command_line spatial_harness_interface spatial::datasets spatial_adapters
                      PRIVATE nlohmann_json::nlohmann_json)
target_compile_options(spatial_harness PRIVATE ${SPATIAL_WARNINGS})
# Recorded in each run's JSON sidecar.
string(TOUPPER "${CMAKE_BUILD_TYPE}" _bt)
target_compile_definitions(spatial_harness PRIVATE
  SPATIAL_CXX_FLAGS="${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${_bt}}"
  SPATIAL_BUILD_TYPE="${CMAKE_BUILD_TYPE}"
  SPATIAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

add_executable(spatialbench src/main.cpp)
target_link_libraries(spatialbench PRIVATE spatial_harness CLI11::CLI11)
target_compile_options(spatialbench PRIVATE ${SPATIAL_WARNINGS})
