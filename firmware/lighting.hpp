// Blinn-Phong in fixed point, per colour channel c (DESIGN §6, docs/CONVENTIONS.md):
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

// x^n by repeated squaring, x in [0, 1] (q1_30), n >= 1; each product rounded to q1_30.
q1_30 power(q1_30 x, std::uint32_t n);

// Lighting at eye-space point p with unit normal n.
Radiance blinn_phong(const ShadeContext& ctx, const Vec3q16& p, const Vec3u& n);

// Clamp to [0, 1], then round(255 I) (ties away from zero).
std::uint8_t to_level(std::int64_t i_q30);
Rgb8 to_rgb8(const Radiance& r);

}  // namespace tp::fw
