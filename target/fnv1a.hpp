// FNV-1a 64 over bytes: the framebuffer hash that the Cortex-M images print and that
// `tinyphong replay --hash` prints for the same stream on the host. Header-only, and beyond the
// device's own header free of the standard library but <cstdint>, so that the bare-metal images
// can use it as it is.
#pragma once

#include <cstddef>
#include <cstdint>

#include "firmware/device.hpp"

namespace tp::target {

inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
inline constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

// Continues hash `h` over n bytes (start with kFnvOffset).
inline std::uint64_t fnv1a(std::uint64_t h, const std::uint8_t* bytes, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= bytes[i];
    h *= kFnvPrime;
  }
  return h;
}

// The colour bytes of a framebuffer, row by row, without any stride padding.
inline std::uint64_t framebuffer_fnv1a(const std::uint8_t* data, std::uint32_t height,
                                       std::size_t stride, std::size_t row_bytes) {
  std::uint64_t h = kFnvOffset;
  for (std::uint32_t y = 0; y < height; ++y)
    h = fnv1a(h, data + std::size_t{y} * stride, row_bytes);
  return h;
}

// The same for the device's framebuffer: 3 bytes per pixel in RGB888, 2 in RGB565.
inline std::uint64_t framebuffer_fnv1a(const fw::FramebufferView& fb) {
  return framebuffer_fnv1a(fb.data, fb.height, fb.stride,
                           fw::bytes_per_pixel(fb.format) * fb.width);
}

}  // namespace tp::target
