# The host's driver of the device (scene -> commands) and the command-line tool.
find_package(CLI11 CONFIG REQUIRED)
# The command stream (.tpcmd words, running them, the framebuffer hash) on its own: no scene and
# no image files, so that a small tool links it with a firmware build of its choice (the target
# tests' host hashes, tests/target). An object library, so that its objects come before each user's
# firmware on the link line.
add_library(tp_command_stream OBJECT ${CMAKE_CURRENT_LIST_DIR}/command_stream.cpp)
target_link_libraries(tp_command_stream PUBLIC tp_fixedpoint)
target_include_directories(tp_command_stream PUBLIC ${PROJECT_SOURCE_DIR})
add_dependencies(tp_command_stream tp_tables)
add_library(tp_driver STATIC ${CMAKE_CURRENT_LIST_DIR}/device_renderer.cpp)
# The numerical stress suite of `tinyphong stress` (docs/STABILITY.md).
add_library(tp_stress STATIC ${CMAKE_CURRENT_LIST_DIR}/stress.cpp
                             ${CMAKE_CURRENT_LIST_DIR}/stress_cases.cpp
                             ${CMAKE_CURRENT_LIST_DIR}/stress_bounds.cpp)
target_link_libraries(tp_stress PUBLIC tp_driver)
target_link_libraries(tp_driver PUBLIC tp_host tp_command_stream tp_firmware)
add_executable(tinyphong ${CMAKE_CURRENT_LIST_DIR}/tinyphong.cpp
                         ${CMAKE_CURRENT_LIST_DIR}/stress_command.cpp)
target_link_libraries(tinyphong PRIVATE tp_driver tp_stress CLI11::CLI11)
