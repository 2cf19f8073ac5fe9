# tinyphong-draw: one device render, counters only — what scripts/instructions.sh profiles.
# --as-needed keeps OpenImageIO (unused here) out of its dependencies: see draw.cpp.
find_package(CLI11 CONFIG REQUIRED)
add_executable(tinyphong-draw ${CMAKE_CURRENT_LIST_DIR}/draw.cpp)
target_link_libraries(tinyphong-draw PRIVATE tp_driver CLI11::CLI11)
target_link_options(tinyphong-draw PRIVATE -Wl,--as-needed)
