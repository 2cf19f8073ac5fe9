// Trigonometry by CORDIC (Volder), with the arctangent table from tables/gen_cordic_atan.cpp.
//
//   sin_cos(θ)     rotation mode, gain pre-compensated (x0 = 1/K), any θ in angle_t's range
//                  [-4, 4): |θ| > π/2 is first reduced by ±π (the result then changes sign).
//   atan2(y, x)    vectoring mode, result in [-π, π]; atan2(0, 0) = 0 (documented, tested);
//                  atan2(0, x < 0) = +π.
//   to_polar(x, y) vectoring: |(x, y)| (gain-compensated, rounded into T, saturated) + angle.
//   acos_unit(c)   angle in [0, π] of a cosine: atan2(sqrt(1 - c^2), c); c is clamped to
//                  [-1, 1] (so acos_unit(c > 1) = 0, acos_unit(c < -1) = π).
//
// Working precision: x, y, z in int64 with 60 fractional bits and kIterations = 40 steps, so
// the residual angle (< 2^-39) and the per-step rounding (40 * 2^-61) are far below the output
// LSB (2^-30 for sin/cos, 2^-29 for angles): results are within 0.5 LSB + a tiny residue of
// the exact value (measured figures in docs/ACCURACY.md).
#pragma once

#include <bit>
#include <cstdint>

#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/wide.hpp"
#include "tables/cordic_atan.hpp"

namespace tp::fx {

using angle_t = Q<2, 29, std::int32_t>;  // radians, |θ| < 4 covers ±π

struct SinCos {
  q1_30 sin, cos;
};

template <QType T>
struct Polar {
  T magnitude;
  angle_t angle;
};

namespace detail {

inline constexpr int kCordicIterations = 40;
static_assert(kCordicIterations <= tables::cordic_entries);
inline constexpr wide_t kPiQ60 = tables::pi_q60;
inline constexpr wide_t kHalfPiQ60 = tables::pi_q60 / 2;

// A Q60 angle (|z| <= π) into angle_t, rounded.
constexpr angle_t angle_from_q60(wide_t z) { return angle_t::from_raw_sat(round_shift_right(z, 31)); }

// Vectoring mode on (y, x), |x|, |y| <= 2^62: returns the angle in Q60 and x_final (the
// magnitude times the CORDIC gain K, scaled by 2^shift relative to the inputs).
struct Vectored {
  wide_t angle_q60 = 0;
  wide_t x_scaled = 0;
  int shift = 0;
};
constexpr Vectored cordic_vectoring(wide_t y, wide_t x) {
  Vectored v;
  if (x == 0 && y == 0) return v;  // atan2(0, 0) = 0 by convention
  // Scale so the larger component has its top bit at 2^58: the rotated vector grows by at most
  // K * sqrt(2) < 2.33, staying below 2^61 (and round_shift_right's 2^62 limit).
  const u64 m = magnitude(x) > magnitude(y) ? magnitude(x) : magnitude(y);
  v.shift = 59 - (64 - std::countl_zero(m));
  if (v.shift >= 0) {
    x *= wide_t{1} << v.shift;
    y *= wide_t{1} << v.shift;
  } else {
    x = round_shift_right(x, -v.shift);
    y = round_shift_right(y, -v.shift);
  }
  wide_t z = 0;
  if (x < 0) {  // rotate by π into the right half-plane, where vectoring converges
    z = y >= 0 ? kPiQ60 : -kPiQ60;
    x = -x;
    y = -y;
  }
  for (int i = 0; i < kCordicIterations; ++i) {
    const wide_t xs = round_shift_right(x, i), ys = round_shift_right(y, i);
    const wide_t a = tables::cordic_atan_q60[static_cast<std::size_t>(i)];
    if (y >= 0) {  // rotate clockwise: drive y to zero
      x += ys;
      y -= xs;
      z += a;
    } else {
      x -= ys;
      y += xs;
      z -= a;
    }
  }
  v.angle_q60 = z;
  v.x_scaled = x;
  return v;
}

}  // namespace detail

constexpr SinCos sin_cos(angle_t theta) {
  // angle_t raw * 2^31 -> Q60; |raw| <= 2^31 so |z| <= 2^62.
  detail::wide_t z = detail::wide_t{theta.raw()} * (detail::wide_t{1} << 31);
  bool flip = false;
  if (z > detail::kHalfPiQ60) {
    z -= detail::kPiQ60;
    flip = true;
  } else if (z < -detail::kHalfPiQ60) {
    z += detail::kPiQ60;
    flip = true;
  }
  detail::wide_t x = tables::cordic_gain_inv_q60, y = 0;  // gain compensated up front
  for (int i = 0; i < detail::kCordicIterations; ++i) {
    const detail::wide_t xs = detail::round_shift_right(x, i), ys = detail::round_shift_right(y, i);
    const detail::wide_t a = tables::cordic_atan_q60[static_cast<std::size_t>(i)];
    if (z >= 0) {  // rotate counter-clockwise toward z = 0
      x -= ys;
      y += xs;
      z -= a;
    } else {
      x += ys;
      y -= xs;
      z += a;
    }
  }
  if (flip) {
    x = -x;
    y = -y;
  }
  return SinCos{q1_30::from_raw_sat(detail::round_shift_right(y, 30)),
                q1_30::from_raw_sat(detail::round_shift_right(x, 30))};
}

template <QType T>
constexpr angle_t atan2(T y, T x) {
  return detail::angle_from_q60(detail::cordic_vectoring(y.raw(), x.raw()).angle_q60);
}

template <QType T>
constexpr Polar<T> to_polar(T x, T y) {
  const detail::Vectored v = detail::cordic_vectoring(y.raw(), x.raw());
  // magnitude raw = x_final * (1/K) / 2^(60 + shift); x_final >= 0 after vectoring.
  const detail::U128 p =
      detail::mul_u64(detail::magnitude(v.x_scaled), static_cast<detail::u64>(tables::cordic_gain_inv_q60));
  bool over = false;
  const detail::u64 m = detail::round_shr(p, 60 + v.shift, over);
  return Polar<T>{detail::from_sign_mag<T>(false, m, over), detail::angle_from_q60(v.angle_q60)};
}

constexpr angle_t acos_unit(q1_30 c) {
  constexpr detail::wide_t one = detail::wide_t{1} << 30;
  const detail::wide_t cr = detail::clamp(c.raw(), -one, one);
  // sin = sqrt(1 - c^2), exactly rounded in Q58: radicand (2^60 - c^2) is Q60, times 2^56.
  const auto radicand = static_cast<detail::u64>((one * one) - cr * cr);
  const detail::RootResult s = detail::isqrt_shifted(radicand, 56, detail::u64{1} << 59);
  const auto s58 = static_cast<detail::wide_t>(s.root + (s.round_up ? 1u : 0u));
  return detail::angle_from_q60(detail::cordic_vectoring(s58, cr * (detail::wide_t{1} << 28)).angle_q60);
}

}  // namespace tp::fx
