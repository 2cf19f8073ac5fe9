// Blinn-Phong in fixed point, per colour channel c (docs/CONVENTIONS.md):
//   I_c = ka O_c + sum_lights Il_c [ kd O_c max(0, N.L) + ks max(0, N.H)^n ],  H = norm(L + V)
// (specular not gated by N.L). Ia = 1. Shared by flat, Gouraud and Phong.
//
// Formats: dot products and powers in q1_30 (each rounded once); the sum over lights in a
// 64-bit Q.30 accumulator: at most 16 lights x intensity 16 x (1 + 1) < 2^10, far inside.
#pragma once

#include <cstdint>

#include "firmware/method.hpp"

namespace tp::fw {

struct Radiance {
  std::int64_t c[3];  // I_c, Q.30, not yet clamped
};

// x^n by repeated squaring, x in [0, 1] (q1_30; every caller clamps, a dot of unit vectors may
// exceed 1 by a few LSB), n >= 1; each product rounded to q1_30, half up. For such x that is the
// rounding of fx::mul_sat (ties away from zero = half up for non-negative values) without its
// saturation, which no product reaches (x^n < 2). Inline: kb-adaptive takes it at every sample
// and exact pixel (kb/kb_sample.hpp).
//
// The first product of the result, 1·x^(2^k), is exact ((2^30·b + 2^29) >> 30 = b), so it is
// taken as is: the same value with one multiplication and test less.
inline q1_30 power(q1_30 x, std::uint32_t n) {
  const auto mul = [](std::int64_t a, std::int64_t b) { return (a * b + (std::int64_t{1} << 29)) >> 30; };
  if (n == 0) return q1_30::one();
  std::int64_t base = x.raw();
  for (; (n & 1u) == 0; n >>= 1) base = mul(base, base);
  std::int64_t result = base;
  for (n >>= 1; n != 0; n >>= 1) {
    base = mul(base, base);
    if ((n & 1u) != 0) result = mul(result, base);
  }
  return q1_30::from_raw(static_cast<std::int32_t>(result));
}

// Lighting at eye-space point p with unit normal n.
Radiance blinn_phong(const ShadeContext& ctx, const Vec3q16& p, const Vec3u& n);

// Clamp to [0, 1], then round(255 I) (ties away from zero).
std::uint8_t to_level(std::int64_t i_q30);
Rgb8 to_rgb8(const Radiance& r);

}  // namespace tp::fw
