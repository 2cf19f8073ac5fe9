# tinyphong-kb-bench: the Kuijk-Blake time / error / setup-share tables of docs/KUIJK-BLAKE.md.
find_package(CLI11 CONFIG REQUIRED)
add_executable(tinyphong-kb-bench ${CMAKE_CURRENT_LIST_DIR}/kb_bench.cpp)
target_link_libraries(tinyphong-kb-bench PRIVATE tp_driver CLI11::CLI11)
# It drives KbOneVectorMethod objects directly; the firmware has no RTTI, so under the sanitizers
# UBSan's vptr check (which needs typeinfo) is left out.
if(TP_SANITIZE)
  target_compile_options(tinyphong-kb-bench PRIVATE -fno-sanitize=vptr)
endif()
