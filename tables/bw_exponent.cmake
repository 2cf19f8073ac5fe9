# Bishop-Weimer exponentiation tables (1 KiB for n <= 20, 8 KiB for n <= 164).
add_executable(gen_bw_exponent ${CMAKE_CURRENT_SOURCE_DIR}/gen_bw_exponent.cpp)
add_custom_command(
  OUTPUT ${TP_GENERATED_DIR}/tables/bw_exponent.hpp
  COMMAND gen_bw_exponent ${TP_GENERATED_DIR}/tables/bw_exponent.hpp
  DEPENDS gen_bw_exponent
  COMMENT "Generating Bishop-Weimer exponent tables")
add_custom_target(tp_table_bw_exponent DEPENDS ${TP_GENERATED_DIR}/tables/bw_exponent.hpp)
add_dependencies(tp_tables tp_table_bw_exponent)
