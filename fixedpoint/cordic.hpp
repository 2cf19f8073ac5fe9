// Trigonometry by CORDIC (Volder), with the arctangent table from tables/gen_cordic_atan.cpp.
//
//   sin_cos(θ)     rotation mode, gain pre-compensated (x0 = 1/K), any θ in angle_t's range
//                  [-4, 4): |θ| > π/2 is first reduced by ±π (the result then changes sign).
//   atan2(y, x)    vectoring mode, result in [-π, π]; atan2(0, 0) = 0 (documented, tested);
//                  atan2(0, x < 0) = +π.
//   to_polar(x, y) vectoring: |(x, y)| (gain-compensated, rounded into T, saturated) + angle.
//   acos_unit(c)   angle in [0, π] of a cosine: atan2(sqrt(1 - c^2), c); c is clamped to
//                  [-1, 1] (so acos_unit(c > 1) = 0, acos_unit(c < -1) = π).
//   atan2_fast, sin_cos_fast: the same results from the first 8 CORDIC steps only, the
//                  residual angle (below atan 2^-7) finished in closed form (atan t = t − t³/3,
//                  sin/cos by their Taylor series), for the Kuijk-Blake span setup. The
//                  truncated series and working roundings add < 2^-36 rad; measured max error
//                  in tests/fixedpoint/test_cordic.cpp (CordicFast).
//
// Working precision: x, y, z in int64 with 60 fractional bits and kIterations = 40 steps, so
// the residual angle (< 2^-39) and the per-step rounding (40 * 2^-61) are far below the output
// LSB (2^-30 for sin/cos, 2^-29 for angles): results are within 0.5 LSB + a tiny residue of
// the exact value (measured figures in docs/ACCURACY.md).
#pragma once

#include <array>
#include <cstdint>

#include "fixedpoint/divide.hpp"
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

// π and π/2 in angle_t, and 2π in angle_t's raw units (2π is beyond angle_t's range; sums of
// angles are wrapped with it), each rounded from the generated table's π in Q60.
constexpr angle_t pi() { return angle_t::from_raw(tables::pi_q2_29); }
constexpr angle_t half_pi() {
  return angle_t::from_raw(static_cast<std::int32_t>(round_shift_right(tables::pi_q60, 32)));
}
constexpr std::int64_t two_pi_raw() { return round_shift_right(tables::pi_q60, 30); }

namespace detail {

inline constexpr int kCordicIterations = 40;
static_assert(kCordicIterations <= tables::cordic_entries);
inline constexpr wide_t kPiQ60 = tables::pi_q60;
inline constexpr wide_t kHalfPiQ60 = tables::pi_q60 / 2;

// A Q60 angle (|z| <= π) into angle_t, rounded.
constexpr angle_t angle_from_q60(wide_t z) {
  return angle_t::from_raw_sat(round_shift_right(z, 31));
}

// Vectoring mode on (y, x), |x|, |y| <= 2^62: returns the angle in Q60 and x_final (the
// magnitude times the CORDIC gain K, scaled by 2^shift relative to the inputs).
struct Vectored {
  wide_t angle_q60 = 0;
  wide_t x_scaled = 0;
  int shift = 0;
};
// Scales (x, y) so that the larger component has its top bit at 2^58 (the rotated vector grows
// by at most K·√2 < 2.33, staying below 2^61 and round_shift_right's 2^62 limit), then rotates by
// π into the right half-plane, where vectoring converges. Returns the scale shift; z gets ±π or 0.
constexpr int prepare_vectoring(wide_t& x, wide_t& y, wide_t& z) {
  const u64 m = magnitude(x) > magnitude(y) ? magnitude(x) : magnitude(y);
  const int shift = 59 - bit_width(m);
  if (shift >= 0) {
    x *= wide_t{1} << shift;
    y *= wide_t{1} << shift;
  } else {
    x = round_shift_right(x, -shift);
    y = round_shift_right(y, -shift);
  }
  z = 0;
  if (x < 0) {
    z = y >= 0 ? kPiQ60 : -kPiQ60;
    x = -x;
    y = -y;
  }
  return shift;
}

// CORDIC steps 0 … n−1: vectoring drives y to zero (z collects the angle), rotation drives z to
// zero (x, y turn by it). Rounded shifts for the full-precision functions; floor shifts (a bias
// of 2^-60 per step) for the setup-grade ones, whose residual is finished in closed form.
template <bool kRounded>
constexpr wide_t step_shift(wide_t v, int i) {
  if constexpr (kRounded)
    return round_shift_right(v, i);
  else
    return v >> i;
}

// atan(2^-i) in Q60. From step kAtanTabled on, atan t = t − t³/3 + … rounds to t itself
// (2^(60−3i)/3 < 1/2), so those steps take 2^(60−i) and only the first kAtanTabled entries of
// the generated table are linked (160 bytes of read-only data instead of 496: docs/TARGET.md,
// "Footprint"); the static_assert holds the rule to every entry the steps use.
inline constexpr int kAtanTabled = 20;
inline constexpr std::array<wide_t, kAtanTabled> kAtanHead = [] {
  std::array<wide_t, kAtanTabled> a{};
  for (int i = 0; i < kAtanTabled; ++i)
    a[static_cast<std::size_t>(i)] = tables::cordic_atan_q60[static_cast<std::size_t>(i)];
  return a;
}();
constexpr bool atan_tail_is_a_shift() {
  for (int i = kAtanTabled; i < kCordicIterations; ++i)
    if (tables::cordic_atan_q60[static_cast<std::size_t>(i)] != wide_t{1} << (60 - i)) return false;
  return true;
}
static_assert(atan_tail_is_a_shift(), "atan(2^-i) rounds to 2^-i in Q60 from kAtanTabled on");

// The table's entry below kAtanTabled, the shift from there on. Inline also in size builds: a
// call per CORDIC step cost more time than the copy in the size build's one step loop costs code.
TP_FX_INLINE constexpr wide_t atan_q60(int i) {
  return i < kAtanTabled ? kAtanHead[static_cast<std::size_t>(i)] : wide_t{1} << (60 - i);
}

// Size builds keep one out-of-line loop for the four kinds of steps below (vectoring or rotation,
// rounded or floor shifts), chosen at run time: the same steps, 430 bytes less on a Cortex-M3.
#if TP_SIZE_BUILD
TP_FX_OUTLINE constexpr void cordic_steps(wide_t& x_io, wide_t& y_io, wide_t& z_io, int n,
                                          bool rounded, bool vectoring) {
  wide_t x = x_io, y = y_io, z = z_io;  // in registers, not through the references, per step
  for (int i = 0; i < n; ++i) {
    const wide_t xs = rounded ? round_shift_right(x, i) : x >> i;
    const wide_t ys = rounded ? round_shift_right(y, i) : y >> i;
    const wide_t a = atan_q60(i);
    if (vectoring ? y >= 0 : z < 0) {  // vectoring's and rotation's turns, as below
      x += ys;
      y -= xs;
      z += a;
    } else {
      x -= ys;
      y += xs;
      z -= a;
    }
  }
  x_io = x;
  y_io = y;
  z_io = z;
}
#endif

template <bool kRounded>
constexpr void vectoring_steps(wide_t& x, wide_t& y, wide_t& z, int n) {
#if TP_SIZE_BUILD
  cordic_steps(x, y, z, n, kRounded, true);
#else
  for (int i = 0; i < n; ++i) {
    const wide_t xs = step_shift<kRounded>(x, i), ys = step_shift<kRounded>(y, i);
    const wide_t a = atan_q60(i);
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
#endif
}
template <bool kRounded>
constexpr void rotation_steps(wide_t& x, wide_t& y, wide_t& z, int n) {
#if TP_SIZE_BUILD
  cordic_steps(x, y, z, n, kRounded, false);
#else
  for (int i = 0; i < n; ++i) {
    const wide_t xs = step_shift<kRounded>(x, i), ys = step_shift<kRounded>(y, i);
    const wide_t a = atan_q60(i);
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
#endif
}

// An angle_t in Q60 (|z| <= 2^62) reduced to [−π/2, π/2] by ±π; true if it was (the rotated
// vector is then negated).
constexpr bool reduce_to_half_pi(wide_t& z) {
  if (z > kHalfPiQ60) {
    z -= kPiQ60;
    return true;
  }
  if (z < -kHalfPiQ60) {
    z += kPiQ60;
    return true;
  }
  return false;
}

constexpr Vectored cordic_vectoring(wide_t y, wide_t x) {
  Vectored v;
  if (x == 0 && y == 0) return v;  // atan2(0, 0) = 0 by convention
  wide_t z = 0;
  v.shift = prepare_vectoring(x, y, z);
  vectoring_steps<true>(x, y, z, kCordicIterations);
  v.angle_q60 = z;
  v.x_scaled = x;
  return v;
}

inline constexpr int kFastIterations = tables::cordic_fast_iterations;
static_assert(kFastIterations == 8, "the residual bounds below assume 8 steps");

// sin_cos_fast's rotation steps: rotation_steps<false>(x, y, z, kFastIterations). Size builds
// give them a loop of their own beside the shared cordic_steps: kb-exact turns by sin_cos_fast
// twice per pixel and term, and with the bound fixed the loop shifts by i < 8 word by word and
// reads the angles without a branch (docs/TARGET.md, "Footprint").
#if TP_SIZE_BUILD
// v >> i for 0 <= i < 32, word by word: GCC's 64-bit shift also covers i >= 32, in twice the
// instructions on a 32-bit core. (hi << 1) << (31 − i) is hi << (32 − i) without a shift by 32
// at i = 0.
TP_FX_INLINE constexpr wide_t shift_right_below_32(wide_t v, int i) {
  const auto lo = static_cast<std::uint32_t>(v);
  const auto hi = static_cast<std::int32_t>(v >> 32);
  const std::uint32_t low = (lo >> i) | ((static_cast<std::uint32_t>(hi) << 1) << (31 - i));
  return static_cast<wide_t>((static_cast<u64>(static_cast<std::uint32_t>(hi >> i)) << 32) | low);
}
TP_FX_OUTLINE constexpr void fast_rotation_steps(wide_t& x_io, wide_t& y_io, wide_t& z_io) {
  wide_t x = x_io, y = y_io, z = z_io;
  for (int i = 0; i < kFastIterations; ++i) {
    const wide_t xs = shift_right_below_32(x, i), ys = shift_right_below_32(y, i);
    const wide_t a = kAtanHead[static_cast<std::size_t>(i)];
    if (z >= 0) {  // rotation_steps' turn, repeated: sharing it moves the -O2 and -Os code
      x -= ys;
      y += xs;
      z -= a;
    } else {
      x += ys;
      y -= xs;
      z += a;
    }
  }
  x_io = x;
  y_io = y;
  z_io = z;
}
#else
constexpr void fast_rotation_steps(wide_t& x, wide_t& y, wide_t& z) {
  rotation_steps<false>(x, y, z, kFastIterations);
}
#endif
static_assert(kFastIterations <= kAtanTabled);

// (u · v) / 6 truncated, for 0 <= u < 2^16 and |v| < 2^23 (sin_cos_fast's z³ term). u = 6q + r
// splits it into q·v + (r·v) / 6: q·v is whole and of the sign of (r·v) / 6, so the truncations
// agree, and r·v fits 32 bits. On a core that divides by halves that is two 32-bit divisions
// instead of a long division of the 39-bit product (docs/TARGET.md, "Division on the core"); the
// tests check it against u · v / 6 on x86 too.
constexpr wide_t product_over_6_by_halves(wide_t u, wide_t v) {
  const auto uw = static_cast<std::uint32_t>(u);
  const std::uint32_t q = uw / 6u, r = uw - 6u * q;
  const std::int32_t rv = static_cast<std::int32_t>(r) * static_cast<std::int32_t>(v);
  return static_cast<wide_t>(q) * v + rv / 6;
}
constexpr wide_t product_over_6(wide_t u, wide_t v) {
  if constexpr (kDivideByHalves)
    return product_over_6_by_halves(u, v);
  else
    return u * v / 6;
}

// Vectoring mode, 8 steps, then the residual: atan2(y, x) with x > 0, |y| / x < tan(2^-6).
// Returns the angle in Q60.
constexpr wide_t cordic_vectoring_fast(wide_t y, wide_t x) {
  if (x == 0 && y == 0) return 0;
  wide_t z = 0;
  prepare_vectoring(x, y, z);
  vectoring_steps<false>(x, y, z, kFastIterations);
  // Now x in [2^58, 2^61) and the residual angle r = atan(t), t = |y|/x < tan(atan 2^-7)
  // (so |y| < 2^54). t in Q54 by two 64-bit divisions (x truncated to 2^-34 relative).
  const u64 ym = magnitude(y);
  const u64 xd = static_cast<u64>(x) >> 24;                    // [2^34, 2^37)
  const u64 yn = ym << 6;                                      // < 2^60
  const UDivMod t30 = udivmod(yn, xd);                         // t in Q30, < 2^24
  const u64 t54 = (t30.quot << 24) + udiv(t30.rem << 24, xd);  // rem < 2^37: << 24 < 2^61
  // atan t = t − t³/3 + t⁵/5 − …: t⁵/5 < 2^-37.
  const u64 t36 = t54 >> 18;               // < 2^29
  const u64 t2_36 = (t36 * t36) >> 36;     // < 2^22
  const u64 cube54 = (t2_36 * t36) >> 18;  // t³ in Q54
  const wide_t atan54 = static_cast<wide_t>(t54) - static_cast<wide_t>(udiv(cube54, 3));
  return z + (y >= 0 ? atan54 : -atan54) * 64;  // Q54 -> Q60
}

}  // namespace detail

// sin_cos by 8 rotation steps, then the residual rotation by |z| < atan 2^-7 in closed form:
// cos z = 1 − e, e = z²/2 − z⁴/24 (z⁶/720 < 2^-51), sin z = z − z³/6 (z⁵/120 < 2^-41).
constexpr SinCos sin_cos_fast(angle_t theta) {
  using detail::wide_t;
  // Its roundings inline also in size builds: kb-exact calls it twice per pixel and term, and
  // out of line they were a quarter of that method's time on the Cortex-M3 at -Os.
  constexpr auto rounded = [](wide_t v, int shift) {
    return detail::round_shift_right_inline(v, shift);
  };
  wide_t z = wide_t{theta.raw()} * (wide_t{1} << 31);
  const bool flip = detail::reduce_to_half_pi(z);
  wide_t x = tables::cordic_fast_gain_inv_q60, y = 0;
  detail::fast_rotation_steps(x, y, z);
  // |z| < 2^-7 (Q60: < 2^53); |x|, |y| <= 1 + 2^-50 (Q60).
  const wide_t z30 = rounded(z, 30);  // |.| < 2^23
  const wide_t z2_60 = z30 * z30;     // < 2^46
  const wide_t z2_30 = z2_60 >> 30;   // < 2^16
  // e = 1 − cos z, < 2^45; z2_30² < 2^32 takes a 32-bit division (one Cortex-M3 instruction).
  const wide_t e60 = z2_60 / 2 - static_cast<std::uint32_t>(z2_30 * z2_30) / 24u;
  const wide_t s60 = z - detail::product_over_6(z2_30, z30);  // sin z, |.| < 2^53
  // x·e: Q32 × Q45 -> Q77 (< 2^62); y·s: Q31 × Q38 -> Q69 (< 2^62).
  const wide_t e45 = e60 >> 15, s38 = rounded(s60, 22);
  const wide_t x32 = rounded(x, 28), y32 = rounded(y, 28);
  const wide_t x31 = rounded(x, 29), y31 = rounded(y, 29);
  wide_t xr = x - rounded(x32 * e45, 17) - rounded(y31 * s38, 9);
  wide_t yr = y - rounded(y32 * e45, 17) + rounded(x31 * s38, 9);
  if (flip) {
    xr = -xr;
    yr = -yr;
  }
  return SinCos{q1_30::from_raw_sat(rounded(yr, 30)), q1_30::from_raw_sat(rounded(xr, 30))};
}

template <QType T>
constexpr angle_t atan2_fast(T y, T x) {
  return detail::angle_from_q60(detail::cordic_vectoring_fast(y.raw(), x.raw()));
}
// The same for two integers of any common scale, |y|, |x| <= 2^62.
constexpr angle_t atan2_fast(std::int64_t y, std::int64_t x) {
  return detail::angle_from_q60(detail::cordic_vectoring_fast(y, x));
}

constexpr SinCos sin_cos(angle_t theta) {
  // angle_t raw * 2^31 -> Q60; |raw| <= 2^31 so |z| <= 2^62.
  detail::wide_t z = detail::wide_t{theta.raw()} * (detail::wide_t{1} << 31);
  const bool flip = detail::reduce_to_half_pi(z);
  detail::wide_t x = tables::cordic_gain_inv_q60, y = 0;  // gain compensated up front
  detail::rotation_steps<true>(x, y, z, detail::kCordicIterations);
  if (flip) {
    x = -x;
    y = -y;
  }
  return SinCos{q1_30::from_raw_sat(round_shift_right(y, 30)),
                q1_30::from_raw_sat(round_shift_right(x, 30))};
}

template <QType T>
constexpr angle_t atan2(T y, T x) {
  return detail::angle_from_q60(detail::cordic_vectoring(y.raw(), x.raw()).angle_q60);
}

template <QType T>
constexpr Polar<T> to_polar(T x, T y) {
  const detail::Vectored v = detail::cordic_vectoring(y.raw(), x.raw());
  // magnitude raw = x_final * (1/K) / 2^(60 + shift); x_final >= 0 after vectoring.
  const detail::U128 p = detail::mul_u64(detail::magnitude(v.x_scaled),
                                         static_cast<detail::u64>(tables::cordic_gain_inv_q60));
  bool over = false;
  const detail::u64 m = detail::round_shr(p, 60 + v.shift, over);
  return Polar<T>{detail::from_sign_mag<T>(false, m, over), detail::angle_from_q60(v.angle_q60)};
}

constexpr angle_t acos_unit(q1_30 c) {
  constexpr detail::wide_t one = detail::wide_t{1} << 30;
  const detail::wide_t cr = clamp(c.raw(), -one, one);
  // sin = sqrt(1 - c^2), exactly rounded in Q58: radicand (2^60 - c^2) is Q60, times 2^56.
  const auto radicand = static_cast<detail::u64>((one * one) - cr * cr);
  const detail::RootResult s = detail::isqrt_shifted(radicand, 56, detail::u64{1} << 59);
  const auto s58 = static_cast<detail::wide_t>(s.root + (s.round_up ? 1u : 0u));
  return detail::angle_from_q60(
      detail::cordic_vectoring(s58, cr * (detail::wide_t{1} << 28)).angle_q60);
}

}  // namespace tp::fx
