// Plain image containers shared by the reference renderer, the metrics and image I/O.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tp::host {

// Linear RGB, row 0 at the top, 3 floats per pixel.
struct FloatImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  FloatImage() = default;
  FloatImage(int w, int h)
      : width(w),
        height(h),
        rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3, 0.0f) {}
  float* at(int x, int y) {
    return &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)) *
                3];
  }
  const float* at(int x, int y) const {
    return &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)) *
                3];
  }
};

// 8-bit RGB (RGB888), row 0 at the top.
struct Image8 {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  Image8() = default;
  Image8(int w, int h)
      : width(w),
        height(h),
        rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3, 0) {}
  std::uint8_t* at(int x, int y) {
    return &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)) *
                3];
  }
  const std::uint8_t* at(int x, int y) const {
    return &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)) *
                3];
  }
};

// One byte per pixel, 1 = covered by some triangle, 0 = background.
using Mask = std::vector<std::uint8_t>;

}  // namespace tp::host
