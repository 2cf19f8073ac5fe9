# Accuracy table of the fixed-point functions (docs/ACCURACY.md, "Fixed-point functions").
# A plain program: `accuracy_fixedpoint` prints one markdown table over the same input sets as
# tests/fixedpoint (shared through tests/fixedpoint/measure.hpp).
add_executable(accuracy_fixedpoint ${CMAKE_CURRENT_LIST_DIR}/accuracy_fixedpoint.cpp)
target_link_libraries(accuracy_fixedpoint PRIVATE tp_fixedpoint)
target_include_directories(accuracy_fixedpoint PRIVATE ${PROJECT_SOURCE_DIR})
add_dependencies(accuracy_fixedpoint tp_tables)
