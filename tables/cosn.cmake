# Kuijk-Blake (a, b) fits for cos^n (least squares and minimax), see gen_cosn_fits.cpp.
add_executable(gen_cosn_fits ${CMAKE_CURRENT_SOURCE_DIR}/gen_cosn_fits.cpp)
target_include_directories(gen_cosn_fits PRIVATE ${PROJECT_SOURCE_DIR})
target_compile_options(gen_cosn_fits PRIVATE -O2)
add_custom_command(
  OUTPUT ${TP_GENERATED_DIR}/tables/cosn_fits.hpp
  COMMAND gen_cosn_fits ${TP_GENERATED_DIR}/tables/cosn_fits.hpp
  DEPENDS gen_cosn_fits
  COMMENT "Fitting cos^n parameters (a, b) for n = 1..10000")
add_custom_target(tp_table_cosn_fits DEPENDS ${TP_GENERATED_DIR}/tables/cosn_fits.hpp)
add_dependencies(tp_tables tp_table_cosn_fits)
