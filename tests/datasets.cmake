# datasets module tests (included by tests/CMakeLists.txt).
spatial_add_test(datasets_test datasets_test.cpp)
target_link_libraries(datasets_test PRIVATE spatial::datasets)
# Committed samples, and the fetched real data (tests needing it skip when it is absent).
target_compile_definitions(datasets_test PRIVATE
  SPATIAL_DATASETS_SAMPLES_DIR="${PROJECT_SOURCE_DIR}/datasets/samples"
  SPATIAL_DATASETS_REAL_DIR="${PROJECT_SOURCE_DIR}/datasets/real")
