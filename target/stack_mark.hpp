// The stack's high-water mark of a Cortex-M image: the free stack is painted with a pattern before
// the work, and afterwards the lowest word that no longer holds it bounds what the work used
// (main's frames and the semihosting calls included). Issue 12's budget for a small part is
// 4 KiB (tests/target/run_image.sh holds the images to it).
#pragma once

#include <cstdint>

extern "C" std::uint32_t __stack_limit[], __stack_top[];  // mps2.ld

namespace tp::target {

constexpr std::uint32_t kStackPaint = 0x5eed5eedu;

inline void paint_stack() {
  // Everything more than 256 bytes below this frame is free.
  const auto below = reinterpret_cast<std::uintptr_t>(__builtin_frame_address(0)) - 256;
  for (volatile std::uint32_t* p = __stack_limit; reinterpret_cast<std::uintptr_t>(p) < below; ++p)
    *p = kStackPaint;
}

inline std::uint32_t stack_used_bytes() {
  const volatile std::uint32_t* p = __stack_limit;
  while (p < __stack_top && *p == kStackPaint) ++p;
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(__stack_top) -
                                    reinterpret_cast<std::uintptr_t>(p));
}

}  // namespace tp::target
