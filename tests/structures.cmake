# Library tests: header-only, no peers (fast to build, run under sanitizers).
spatial_add_test(container_contract_test container_contract_test.cpp)
spatial_add_test(property_test property_test.cpp)
spatial_add_test(kd_tree_test kd_tree_test.cpp)
spatial_add_test(bv_test bv_test.cpp)
