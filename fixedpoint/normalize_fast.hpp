// Sample-grade normalisation: the direction of a 64-bit integer vector as a Q1.30 unit vector,
// from a seed and two Newton steps in 64-bit products (normalize() takes four Newton steps in
// 128-bit products, for correct rounding that kb-adaptive's samples do not need).
//
//   normalize_fast(x, y, z)  components of any common scale (only the direction matters);
//                            the zero vector gives the zero vector.
//   rsqrt_fast(s)            1/√s of a positive integer, as a mantissa and a shift (the same
//                            seed and Newton steps), for a cosine divided by a length.
//
// How: the components are cut to 30 bits (as firmware/vecmath.hpp's normalize_wide does), the
// squared length s (exact, < 3·2^60) is brought to t = s·2^-e in [2^30, 2^32) with e even, and
// 1/sqrt(t / 2^32) in (1, 2] is taken from the interpolated seed of fixedpoint/sqrt.hpp
// (relative error < 2^-11.4) and two Newton steps r' = r (3 − T r²) / 2 in 64-bit products
// (error < 2^-30 after them, below the products' truncation).
// Precondition: |x|, |y|, |z| < 2^62.
// Measured against the double-precision direction over 1,000,000 random vectors of every
// magnitude (tests/fixedpoint/test_vec3.cpp, NormalizeFast): at most 1.725 LSB of Q1.30 per
// component (1.6·10^-9), pinned at 2.5.
#pragma once

#include <cstdint>

#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/vec3.hpp"

namespace tp::fx {

// 1/√s of an integer 0 < s < 2^62 as a Q2.30 mantissa r in (2^30, 2^31] and a shift >= 1: for
// an integer c of the units that s squares, (c·r) >> shift is c/√s in Q1.30 (|c·r| < 2^63 is
// the caller's to keep). The seed and two Newton steps of normalize_fast: relative error < 2^-28.
struct RsqrtFast {
  std::int64_t r = 0;
  int shift = 0;
};
inline RsqrtFast rsqrt_fast(detail::u64 s) {
  using detail::u64;
  int e = bit_width(s) - 32;  // t = s·2^-e in [2^31, 2^32) ...
  e += e & 1;                 // ... or [2^30, 2^31) for an even e
  const u64 t = e >= 0 ? s >> e : s << -e;
  u64 r = u64{detail::rsqrt_seed(static_cast<std::uint32_t>(t))} << 15;  // Q.15 -> Q2.30
  for (int it = 0; it < 2; ++it) {
    const u64 r2 = (r * r) >> 30;            // Q.30, <= 2^32
    const u64 tr2 = (t * r2) >> 32;          // T r² in Q.30, ~2^30 (t < 2^32, t·r2 ~ 2^62)
    r = (r * ((u64{3} << 30) - tr2)) >> 31;  // r (3 − T r²) / 2, Q2.30
  }
  // 1/√s = r·2^-30 · 2^-(16 + e/2) · 2^30: c·r >> (16 + e/2), >= 1 since e >= -30.
  return RsqrtFast{static_cast<std::int64_t>(r), 16 + e / 2};
}

inline Vec3<q1_30> normalize_fast(std::int64_t x, std::int64_t y, std::int64_t z) {
  using detail::u64;
  const auto mag = [](std::int64_t v) { return static_cast<u64>(v < 0 ? -v : v); };
  const int w = bit_width(mag(x) | mag(y) | mag(z));
  // Cut to 30 bits, rounding half up (the direction alone matters, so the rounding need not be
  // symmetric); |c| <= 2^30.
  const int cut = w > 30 ? w - 30 : 0;
  const std::int64_t bias = cut > 0 ? std::int64_t{1} << (cut - 1) : 0;
  const std::int64_t cx = (x + bias) >> cut, cy = (y + bias) >> cut, cz = (z + bias) >> cut;
  const u64 s = static_cast<u64>(cx * cx) + static_cast<u64>(cy * cy) + static_cast<u64>(cz * cz);
  if (s == 0) return Vec3<q1_30>{q1_30::zero(), q1_30::zero(), q1_30::zero()};
  // |component·r| <= 2^61; the result is within 2^30 (1 + 2^-28): no saturation.
  const RsqrtFast inv = rsqrt_fast(s);
  const std::int64_t half = std::int64_t{1} << (inv.shift - 1);
  const auto unit = [&](std::int64_t c) {
    return q1_30::from_raw(static_cast<std::int32_t>((c * inv.r + half) >> inv.shift));
  };
  return Vec3<q1_30>{unit(cx), unit(cy), unit(cz)};
}

}  // namespace tp::fx
