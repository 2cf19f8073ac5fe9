# CMake toolchain file for Debian's bare-metal Arm toolchain (gcc-arm-none-eabi, newlib):
#   cmake -S target -B build/target -DCMAKE_TOOLCHAIN_FILE=target/toolchain-arm-none-eabi.cmake
# The CPU flags (-mcpu=cortex-m3 / cortex-m7, -mthumb, -mfloat-abi=soft) are per image, set in
# target/CMakeLists.txt, so that one configured tree builds both cores.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_SIZE arm-none-eabi-size)

# No hosted runtime to link a test program against: try_compile builds a static library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# Headers and libraries come from the cross sysroot; programs (the host's) from the host.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
