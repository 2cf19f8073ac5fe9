# CORDIC arctangent table and gain constant -> ${TP_GENERATED_DIR}/tables/cordic_atan.hpp,
# included by fixedpoint/cordic.hpp.
add_executable(gen_cordic_atan ${CMAKE_CURRENT_LIST_DIR}/gen_cordic_atan.cpp)
add_custom_command(
  OUTPUT ${TP_GENERATED_DIR}/tables/cordic_atan.hpp
  COMMAND gen_cordic_atan ${TP_GENERATED_DIR}/tables/cordic_atan.hpp
  DEPENDS gen_cordic_atan
  COMMENT "Generating tables/cordic_atan.hpp")
add_custom_target(tp_table_cordic_atan DEPENDS ${TP_GENERATED_DIR}/tables/cordic_atan.hpp)
add_dependencies(tp_tables tp_table_cordic_atan)
