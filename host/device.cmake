# The host's driver of the device (scene -> commands) and the command-line tool.
find_package(CLI11 CONFIG REQUIRED)
add_library(tp_driver STATIC ${CMAKE_CURRENT_LIST_DIR}/device_renderer.cpp
                             ${CMAKE_CURRENT_LIST_DIR}/command_stream.cpp)
# The numerical stress suite of `tinyphong stress` (docs/STABILITY.md).
add_library(tp_stress STATIC ${CMAKE_CURRENT_LIST_DIR}/stress.cpp
                             ${CMAKE_CURRENT_LIST_DIR}/stress_cases.cpp
                             ${CMAKE_CURRENT_LIST_DIR}/stress_bounds.cpp)
target_link_libraries(tp_stress PUBLIC tp_driver)
target_link_libraries(tp_driver PUBLIC tp_host tp_firmware)
add_executable(tinyphong ${CMAKE_CURRENT_LIST_DIR}/tinyphong.cpp)
target_link_libraries(tinyphong PRIVATE tp_driver tp_stress CLI11::CLI11)
