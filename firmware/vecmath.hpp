// Small vector helpers on top of fixedpoint/vec3.hpp for wide (64-bit) intermediate vectors.
#pragma once

#include <cstdint>

#include "firmware/types.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/vec3.hpp"

namespace tp::fw {

// normalize(x, y, z) for raw components of any common scale (only the direction matters):
// the components are first rounded down to 30 bits, which keeps fx::normalize's squared length
// exact, and costs at most 2^-29 relative per component. The zero vector stays zero.
inline Vec3u normalize_wide(std::int64_t x, std::int64_t y, std::int64_t z) {
  const auto mag = [](std::int64_t v) {
    return v < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
  };
  const int w = fx::bit_width(mag(x) | mag(y) | mag(z));
  const int s = w > 29 ? w - 29 : 0;
  const auto cut = [s](std::int64_t v) {
    return q1_30::from_raw(static_cast<std::int32_t>(fx::round_shift_right(v, s)));
  };
  return fx::normalize<q1_30>(Vec3u{cut(x), cut(y), cut(z)});
}

}  // namespace tp::fw
