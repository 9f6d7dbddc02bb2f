# Library tests: header-only, no peers (fast to build, run under sanitizers).
spatial_add_test(container_contract_test container_contract_test.cpp)
# The ready-made objects: box, sphere, triangle (watertight ray test).
spatial_add_test(objects_test objects_test.cpp)
spatial_add_test(property_test property_test.cpp)
spatial_add_test(kd_tree_test kd_tree_test.cpp)
spatial_add_test(bv_test bv_test.cpp)
# Bounding volumes, one test file per type (bv_test: aabb and sphere).
spatial_add_test(obb_test obb_test.cpp)
spatial_add_test(kdop_test kdop_test.cpp)
spatial_add_test(ellipsoid_test ellipsoid_test.cpp)
spatial_add_test(convex_hull_test convex_hull_test.cpp)
