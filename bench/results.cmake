# tinyphong-results: the per-scene, per-method error and time-ratio tables of docs/RESULTS.md.
find_package(CLI11 CONFIG REQUIRED)
add_executable(tinyphong-results ${CMAKE_CURRENT_LIST_DIR}/results.cpp)
target_link_libraries(tinyphong-results PRIVATE tp_driver tp_llvmpipe CLI11::CLI11)
