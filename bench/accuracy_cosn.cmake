# Per-n accuracy table of the cos^n (a, b) sources for docs/ACCURACY.md ("Lookup-free cos^n").
add_executable(accuracy_cosn ${CMAKE_CURRENT_SOURCE_DIR}/accuracy_cosn.cpp)
target_link_libraries(accuracy_cosn PRIVATE tp_fixedpoint)
target_compile_options(accuracy_cosn PRIVATE -O2)
add_dependencies(accuracy_cosn tp_tables)
# The fit of the closed form's coefficients (run by hand; prints what firmware/cosn.hpp stores).
add_executable(fit_cosn_closed_form ${CMAKE_CURRENT_SOURCE_DIR}/fit_cosn_closed_form.cpp)
target_include_directories(fit_cosn_closed_form PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(fit_cosn_closed_form PRIVATE tp_fixedpoint)
add_dependencies(fit_cosn_closed_form tp_tables)
target_compile_options(fit_cosn_closed_form PRIVATE -O2)
